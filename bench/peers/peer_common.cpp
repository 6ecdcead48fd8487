#include "peer_common.h"

#include <cstdio>
#include <cstdlib>
#include <exception>
#include <filesystem>
#include <limits>
#include <stdexcept>
#include <system_error>
#include <thread>

#include "detexture/io/read_point_cloud.h"
#include "detexture/io/write_point_cloud.h"

namespace detexture::peers {
namespace {

// parse_length refuses zero, but "0" (or "0d") is the K-nearest default of
// the CGAL peers, so zero is recognised here first.
bool is_zero_length(const std::string& text) {
  std::string number = text;
  if (!number.empty() && (number.back() == 'd' || number.back() == 'D')) number.pop_back();
  if (number.empty()) return false;
  char* end = nullptr;
  const double value = std::strtod(number.c_str(), &end);
  return end == number.c_str() + number.size() && value == 0.0;
}

}  // namespace

Length parse_length_option(const std::string& text, const std::string& option, bool allow_zero) {
  if (allow_zero && is_zero_length(text)) return {0.0, Length::Unit::Absolute};
  Length length;
  try {
    length = parse_length(text);
  } catch (const std::invalid_argument&) {
    throw CLI::ValidationError(option, std::string("expected a length ") +
                                           (allow_zero ? ">= 0" : "> 0") +
                                           " in model units (0.5) or as a fraction of the "
                                           "bounding-box diagonal (0.02d), got '" +
                                           text + "'");
  }
  if (length.unit == Length::Unit::Radius)
    throw CLI::ValidationError(option, "'" + text +
                                           "' is a multiple of detexture's radius r, which a "
                                           "peer does not have; give the length in model units "
                                           "(0.5) or as a fraction of the bounding-box diagonal "
                                           "(0.02d)");
  return length;
}

double resolve_length(const Length& length, const Positions& P) {
  // parse_length_option refuses "r", so there is no radius to resolve against.
  return length.resolve(bounding_box_diagonal(P), std::numeric_limits<double>::quiet_NaN());
}

void add_input_output_options(CLI::App& app, std::string& input, std::string& output,
                              const std::string& input_help) {
  app.add_option("input", input, input_help)->required()->check(CLI::ExistingFile);
  app.add_option("output", output, "Output PLY (binary little endian)")->required();
}

std::optional<int> parse_command_line(CLI::App& app, int argc, char** argv, const char* program,
                                      const std::function<void()>& validate) {
  try {
    app.parse(argc, argv);
    if (validate) validate();
  } catch (const CLI::CallForHelp& e) {
    return app.exit(e);
  } catch (const CLI::ParseError& e) {
    std::fprintf(stderr, "%s: error: %s (run with --help for usage)\n", program, e.what());
    return 2;
  }
  return std::nullopt;
}

int run_reporting_errors(const char* program, const std::function<int()>& work) {
  try {
    return work();
  } catch (const std::exception& e) {
    std::fprintf(stderr, "%s: error: %s\n", program, e.what());
    return 1;
  }
}

PointCloud read_input(const std::string& input, const std::string& output) {
  std::error_code error;
  if (std::filesystem::exists(output, error) && std::filesystem::equivalent(input, output, error))
    throw std::runtime_error("output '" + output +
                             "' is the input file; choose another output path.");
  return read_point_cloud(input);
}

void write_output(const std::string& output, const PointCloud& cloud, const std::string& input) {
  WriteOptions options;
  options.format = FileFormat::Ply;
  options.protect_path = input;
  write_point_cloud(output, cloud, options);
}

int thread_count(int requested) {
  const int hardware = static_cast<int>(std::thread::hardware_concurrency());
  return requested > 0 ? requested : (hardware > 0 ? hardware : 1);
}

double Stopwatch::seconds() const {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
}

void print_seconds(double seconds) { std::printf("seconds: %.6f\n", seconds); }

}  // namespace detexture::peers
