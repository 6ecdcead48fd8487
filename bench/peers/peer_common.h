// What every peer program (bench/peers/peer_*.cpp) does the same way around
// its algorithm, so that they keep the one interface bench/peers/README.md
// documents: lengths as "0.5" or "0.02d", exit code 2 for a bad command line
// and 1 for a bad file or a failure (each with a one-line message on stderr),
// the input read and the output written by detexture's own PLY code, and
// `seconds: <wall time of the algorithm>` as the last line of stdout.
#pragma once

#include <CLI/CLI.hpp>
#include <chrono>
#include <functional>
#include <optional>
#include <string>

#include "detexture/io/point_cloud.h"
#include "detexture/pipeline/remove_texture.h"
#include "detexture/types.h"

namespace detexture::peers {

/// A length option of a peer, in detexture::parse_length's syntax: "0.5" in
/// model units or "0.02d", a fraction of the bounding-box diagonal d. The "r"
/// unit (a multiple of detexture's radius) is refused: a peer has no such
/// radius. With `allow_zero`, a zero length ("0", "0d") is accepted (the
/// peers' "no radius, K nearest" default); otherwise the length must be > 0.
/// Throws CLI::ValidationError naming `option` with a sentence for anything
/// else.
Length parse_length_option(const std::string& text, const std::string& option, bool allow_zero);

/// `length` in model units for a cloud with positions P (its "d" resolved
/// against P's bounding-box diagonal).
double resolve_length(const Length& length, const Positions& P);

/// Adds the two positional arguments every peer takes: `input`, an existing
/// file described by `input_help`, and `output`, the PLY to write; both
/// required.
void add_input_output_options(CLI::App& app, std::string& input, std::string& output,
                              const std::string& input_help);

/// Parses the command line, then runs `validate` (further checks, which throw
/// CLI::ValidationError). Returns the exit code when the program should stop:
/// 0 after printing --help, 2 after printing "<program>: error: <message> (run
/// with --help for usage)" on stderr; std::nullopt when it should go on.
std::optional<int> parse_command_line(CLI::App& app, int argc, char** argv, const char* program,
                                      const std::function<void()>& validate = {});

/// Runs a peer's work and returns its exit code; any exception becomes
/// "<program>: error: <message>" on stderr and exit code 1.
int run_reporting_errors(const char* program, const std::function<int()>& work);

/// Reads the input cloud (PLY or any format read_point_cloud knows), after
/// refusing an output path that is the input file: the writer refuses too,
/// but only after the algorithm has run.
PointCloud read_input(const std::string& input, const std::string& output);

/// Writes `cloud` to `output` as binary little-endian PLY (every extra
/// property of the input carried through), never over `input`.
void write_output(const std::string& output, const PointCloud& cloud, const std::string& input);

/// Worker threads for a --threads value: the value itself, or all hardware
/// threads (at least 1) for 0.
int thread_count(int requested);

/// Wall time since construction, for the `seconds:` line.
class Stopwatch {
 public:
  double seconds() const;

 private:
  std::chrono::steady_clock::time_point start_ = std::chrono::steady_clock::now();
};

/// Prints the `seconds: <float>` line that every peer ends its stdout with.
void print_seconds(double seconds);

}  // namespace detexture::peers
