// detexture render IN.ply [MORE.ply ...] -o OUT.png: pictures of clouds side
// by side, shaded from their normals, optionally coloured by a property.
#include <CLI/CLI.hpp>
#include <cctype>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <filesystem>
#include <stdexcept>
#include <string>
#include <vector>

#include "commands.h"
#include "detexture/io/read_point_cloud.h"
#include "detexture/render/face_triangles.h"
#include "detexture/render/render_point_cloud.h"
#include "detexture/render/write_png.h"

namespace detexture::app {
namespace {

struct UsageError : std::runtime_error {
  using std::runtime_error::runtime_error;
};
struct InputError : std::runtime_error {
  using std::runtime_error::runtime_error;
};
struct OutputError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

// "A,B" as two numbers; what names the option in the message.
void parse_pair(const std::string& text, char sep, const std::string& what, double* a, double* b) {
  const std::size_t at = text.find(sep);
  if (at != std::string::npos) {
    const std::string sa = text.substr(0, at), sb = text.substr(at + 1);
    char* ea = nullptr;
    char* eb = nullptr;
    *a = std::strtod(sa.c_str(), &ea);
    *b = std::strtod(sb.c_str(), &eb);
    if (!sa.empty() && !sb.empty() && *ea == '\0' && *eb == '\0') return;
  }
  throw UsageError(what + " must be two numbers separated by '" + std::string(1, sep) + "', not '" +
                   text + "'");
}

// The named per-point values of a cloud ("x", "y", "z" or an extra
// property); false if it has none of that name.
bool find_scalar(const PointCloud& cloud, const std::string& name, std::vector<double>* values) {
  for (int axis = 0; axis < 3; ++axis)
    if (name == std::string(1, "xyz"[axis])) {
      values->resize(cloud.size());
      for (std::size_t i = 0; i < cloud.size(); ++i) (*values)[i] = cloud.positions(i, axis);
      return true;
    }
  for (const PointProperty& p : cloud.extras)
    if (p.name == name) {
      *values = p.values;
      return true;
    }
  return false;
}

std::string property_names(const PointCloud& cloud) {
  std::string s = "x, y, z";
  for (const PointProperty& p : cloud.extras) s += ", " + p.name;
  return s;
}

}  // namespace

int run_render(int argc, char** argv) {
  RenderParams params;
  std::vector<std::string> inputs, labels;
  std::string output, size, range, color_by;
  std::string view =
      number_text(params.view.azimuth_deg) + "," + number_text(params.view.elevation_deg);
  std::string light = number_text(params.light_left_deg) + "," + number_text(params.light_up_deg);
  std::string up = up_axis_name(params.up), color_map = color_map_name(params.color_map);
  bool force = false, quiet = false, no_labels = false, no_color_bar = false;

  CLI::App app{
      "Draw point clouds (or meshes, when the PLY has faces) side by side in one PNG, shaded\n"
      "from their normals, in software (no display or GPU needed). Every panel shares the view\n"
      "and the scale, so before/after pictures compare pixel for pixel. Clouds without normals\n"
      "get PCA normals (meshes: from their faces).",
      "detexture render"};
  app.get_formatter()->column_width(30);
  app.add_option("INPUT", inputs, "Point clouds or meshes (.ply, .xyz, ...), one panel each")
      ->required();
  app.add_option("-o,--output", output, "Picture to write (.png)")->required();
  app.add_option("--size", size, "Image size WIDTHxHEIGHT in pixels (sets --width and --height)");
  app.add_option("--width", params.width, "Image width in pixels")->capture_default_str();
  app.add_option("--height", params.height, "Image height in pixels")->capture_default_str();
  app.add_option("--view", view,
                 "Camera direction AZIMUTH,ELEVATION in degrees, or front, back, left, right, "
                 "top, bottom, iso")
      ->capture_default_str();
  app.add_option("--up", up, "The scene's up axis: x, y or z")->capture_default_str();
  app.add_option("--color-by", color_by,
                 "Colour by this per-point property (e.g. texture_height; x, y, z also work); "
                 "clouds without it are drawn plain");
  app.add_option("--range", range,
                 "MIN,MAX of the colour map [default: the data's, symmetric about 0 for "
                 "the diverging map]");
  app.add_option("--color-map", color_map,
                 "auto (diverging if the range has both signs, else viridis), viridis or "
                 "diverging")
      ->capture_default_str();
  app.add_option("--point-size", params.point_size,
                 "Point disc diameter in pixels; 0 = from the point density, so that the "
                 "discs close the surface")
      ->capture_default_str();
  app.add_option("--normal-neighbors", params.normal_neighbors,
                 "k nearest points for the normals of clouds without normals")
      ->capture_default_str();
  app.add_option("--ambient", params.ambient,
                 "Share of light that does not depend on the normal, in [0, 1]")
      ->capture_default_str();
  app.add_option("--light", light,
                 "Light direction LEFT,UP: degrees to the left of and above the view direction")
      ->capture_default_str();
  app.add_option("--label", labels,
                 "Text above each panel, once per input in order [default: the file names]");
  app.add_flag("--no-labels", no_labels, "No text above the panels");
  app.add_flag("--no-color-bar", no_color_bar, "No colour bar when colouring");
  app.add_flag("-f,--force", force, "Overwrite OUTPUT if it exists");
  app.add_flag("-q,--quiet", quiet, "Print nothing on success");

  try {
    app.parse(argc, argv);
  } catch (const CLI::Success& e) {
    return app.exit(e);
  } catch (const CLI::ParseError& e) {
    std::fprintf(stderr, "detexture render: %s (see --help)\n", e.what());
    return kExitUsage;
  }

  try {
    try {
      if (!size.empty()) {
        double w = 0, h = 0;
        parse_pair(size, 'x', "--size", &w, &h);
        if (w != static_cast<int>(w) || h != static_cast<int>(h))
          throw UsageError("--size must be whole pixels, not '" + size + "'");
        params.width = static_cast<int>(w);
        params.height = static_cast<int>(h);
      }
      params.view = parse_view(view);
      params.up = parse_up_axis(up);
      parse_pair(light, ',', "--light", &params.light_left_deg, &params.light_up_deg);
      params.color_map = parse_color_map(color_map);
      if (!range.empty()) parse_pair(range, ',', "--range", &params.range_min, &params.range_max);
      if (!labels.empty() && labels.size() != inputs.size())
        throw UsageError("--label is given " + std::to_string(labels.size()) + " times for " +
                         std::to_string(inputs.size()) + " inputs; give it once per input");
      params.labels = !no_labels;
      params.color_bar = !no_color_bar;
      std::string ext = std::filesystem::path(output).extension().string();
      for (char& c : ext) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
      if (ext != ".png") throw UsageError(output + ": the output must be a .png file");
      validate(params);
    } catch (const std::invalid_argument& e) {
      throw UsageError(e.what());
    }

    // Check the output before reading anything.
    if (!force && std::filesystem::exists(output))
      throw OutputError(output + ": exists; pass --force to overwrite it");
    for (const std::string& in : inputs) {
      std::error_code ec;
      if (std::filesystem::exists(in) && std::filesystem::equivalent(in, output, ec))
        throw OutputError(output + ": is the input file " + in + "; refusing to overwrite it");
    }

    const auto t0 = std::chrono::steady_clock::now();
    std::vector<RenderCloud> clouds(inputs.size());
    std::size_t coloured = 0;
    for (std::size_t k = 0; k < inputs.size(); ++k) {
      RenderCloud& rc = clouds[k];
      try {
        PointCloud cloud = read_point_cloud(inputs[k]);
        try {
          rc.triangles = face_triangles(cloud);
        } catch (const std::invalid_argument& e) {
          throw std::runtime_error(inputs[k] + ": " + e.what());
        }
        if (!color_by.empty()) {
          if (find_scalar(cloud, color_by, &rc.scalar))
            ++coloured;
          else if (!quiet)
            std::fprintf(stderr,
                         "detexture render: note: %s has no property '%s' (it has %s); "
                         "drawn without colours\n",
                         inputs[k].c_str(), color_by.c_str(), property_names(cloud).c_str());
        }
        if (cloud.has_normals()) rc.normals = std::move(cloud.normals);
        rc.positions = std::move(cloud.positions);
      } catch (const std::exception& e) {
        throw InputError(e.what());
      }
      rc.label = labels.empty() ? std::filesystem::path(inputs[k]).filename().string() : labels[k];
    }
    if (!color_by.empty() && coloured == 0)
      throw InputError("no input has a property '" + color_by + "' to colour by");

    RenderReport report;
    Image image;
    try {
      image = render_point_clouds(clouds, params, &report);
    } catch (const std::invalid_argument& e) {
      throw UsageError(e.what());
    }
    const double render_s =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    try {
      write_png(output, image);
    } catch (const std::exception& e) {
      throw OutputError(e.what());
    }
    if (!quiet) {
      std::fprintf(stderr, "wrote %s: %d x %d, %zu panel%s, %.0f pixels per unit", output.c_str(),
                   image.width, image.height, clouds.size(), clouds.size() == 1 ? "" : "s",
                   report.pixels_per_unit);
      if (!color_by.empty())
        std::fprintf(stderr, ", %s on [%s, %s] (%s)", color_by.c_str(),
                     number_text(report.range_min).c_str(), number_text(report.range_max).c_str(),
                     color_map_name(report.color_map));
      std::fprintf(stderr, "; read and drawn in %.2f s\n", render_s);
    }
    return kExitOk;
  } catch (const UsageError& e) {
    std::fprintf(stderr, "detexture render: error: %s\n", e.what());
    return kExitUsage;
  } catch (const InputError& e) {
    std::fprintf(stderr, "detexture render: error: %s\n", e.what());
    return kExitInput;
  } catch (const OutputError& e) {
    std::fprintf(stderr, "detexture render: error: %s\n", e.what());
    return kExitOutput;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "detexture render: error: %s\n", e.what());
    return kExitFailure;
  }
}

}  // namespace detexture::app
