// `detexture INPUT -o OUTPUT [options]`: the texture-removal job. A thin layer
// over remove_texture(): parse, read, run, write, report. Every default shown
// by --help is read from the library's parameter structs.
#include <omp.h>
#include <pthread.h>
#include <signal.h>
#include <sys/resource.h>
#include <unistd.h>

#include <CLI/CLI.hpp>
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstring>
#include <exception>
#include <filesystem>
#include <map>
#include <new>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "commands.h"
#include "detexture/io/face_list.h"
#include "detexture/io/output_file.h"
#include "detexture/io/read_point_cloud.h"
#include "detexture/io/write_point_cloud.h"
#include "detexture/pipeline/remove_texture.h"
#include "detexture/pipeline/texture_fields.h"
#include "detexture/threads.h"
#include "detexture/tiling/remove_texture_out_of_core.h"
#include "tiling_options.h"

namespace detexture::app {
namespace {

struct InputError : std::runtime_error {
  using std::runtime_error::runtime_error;
};
struct OutputError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

// Progress on stderr: a line per stage, with percentages once a stage has run
// for more than a second (rewritten in place on a terminal).
class ProgressPrinter {
 public:
  explicit ProgressPrinter(bool quiet) : quiet_(quiet), tty_(isatty(fileno(stderr))) {}

  PipelineObserver observer() {
    PipelineObserver o;
    if (quiet_) return o;
    o.begin = [this](const std::string& stage) {
      start_ = std::chrono::steady_clock::now();
      last_percent_ = -1;
      shown_ = false;
      stage_ = stage;
    };
    o.progress = [this](const std::string&, double f) {
      const double elapsed =
          std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
      if (elapsed < 1.0) return;
      const int percent = static_cast<int>(f * 100.0);
      const int step = tty_ ? 1 : 10;
      if (percent / step == last_percent_ / step) return;
      last_percent_ = percent;
      shown_ = true;
      std::fprintf(stderr, tty_ ? "\r  %-20s %3d%%" : "  %-20s %3d%%\n", stage_.c_str(), percent);
      std::fflush(stderr);
    };
    o.end = [this](const std::string& stage, double seconds) {
      std::fprintf(stderr, "%s  %-20s done in %.2f s\n", (tty_ && shown_) ? "\r" : "",
                   stage.c_str(), seconds);
    };
    o.warning = [](const std::string& message) {
      std::fprintf(stderr, "detexture: warning: %s\n", message.c_str());
    };
    return o;
  }
  void note(const std::string& message) const {
    if (!quiet_) std::fprintf(stderr, "%s\n", message.c_str());
  }

 private:
  bool quiet_, tty_;
  std::chrono::steady_clock::time_point start_;
  int last_percent_ = -1;
  bool shown_ = false;
  std::string stage_;
};

void add_length(CLI::App& app, const std::string& flags, Length& target,
                const std::string& description) {
  app.add_option_function<std::string>(
         flags,
         [&target, flags](const std::string& text) {
           try {
             target = parse_length(text);
           } catch (const std::invalid_argument& e) {
             throw CLI::ValidationError(flags, e.what());
           }
         },
         description + " [default: " + to_string(target) + "]")
      ->type_name("LENGTH");
}

// The command-line name of an enum value, so --help shows the library default.
template <class E>
std::string name_of(const std::map<std::string, E>& names, E value) {
  for (const auto& [name, v] : names)
    if (v == value) return name;
  return "?";
}

// An option taking one of `names` (any case), shown as TYPE with the
// library's default.
template <class E>
CLI::Option* add_choice(CLI::App& app, const std::string& flags, E& target,
                        const std::map<std::string, E>& names, const std::string& description,
                        const std::string& type) {
  return app.add_option(flags, target, description)
      ->transform(CLI::CheckedTransformer(names, CLI::ignore_case).description(""))
      ->type_name(type)
      ->default_str(name_of(names, target));
}

std::string json_text(const std::string& s) {
  std::string out;
  for (char c : s) {
    if (c == '"' || c == '\\') out += '\\';
    out += c;
  }
  return out;
}

// One line: what the scale estimate found and how r was chosen.
std::string scale_line(const RemoveTextureReport& r) {
  char buf[256] = "";
  if (r.scale_estimated && r.scale.texture_found)
    std::snprintf(buf, sizeof buf,
                  "texture ≈ %.2g (radius), height ≈ %.2g, spacing %.2g, noise %.2g → r = %.3g "
                  "(%s)",
                  r.scale.texture_radius, r.scale.texture_height, r.scale.spacing, r.scale.noise,
                  r.radius, r.radius_reason.c_str());
  else if (r.scale_estimated)
    std::snprintf(buf, sizeof buf, "no texture found, spacing %.2g, noise %.2g → r = %.3g (%s)",
                  r.scale.spacing, r.scale.noise, r.radius, r.radius_reason.c_str());
  else
    std::snprintf(buf, sizeof buf, "r = %.3g (%s)", r.radius, r.radius_reason.c_str());
  return buf;
}

// --scale-report: the estimate, the r it gives, and the residual curve behind it.
int print_scale_report(const std::string& input, FileFormat format,
                       const RemoveTextureParams& params) {
  PointCloud cloud;
  try {
    cloud = read_point_cloud(input, format);
  } catch (const std::exception& e) {
    throw InputError(e.what());
  }
  RemoveTextureReport r;
  r.diagonal = bounding_box_diagonal(cloud.positions);
  r.scale = estimate_texture_scale(
      cloud.positions, params.ignore_input_normals ? Normals() : cloud.normals, params.scale);
  r.scale_estimated = true;
  RemoveTextureParams auto_params = params;
  if (auto_params.radius.unit != Length::Unit::Texture)
    auto_params.radius = RemoveTextureParams().radius;
  const RadiusChoice c = choose_radius(auto_params, r.diagonal, r.scale);
  r.radius = c.radius;
  r.radius_reason = c.reason;
  std::printf("%s: %zu points, bounding-box diagonal d = %g\n%s\n", input.c_str(), cloud.size(),
              r.diagonal, scale_line(r).c_str());
  if (!r.scale.texture_found) std::printf("%s\n", r.scale.reason.c_str());
  if (r.scale.thin_radius > 0.0)
    std::printf("thin parts: %g%% of the surface reaches the back of a thin part within %.3g\n",
                std::round(100.0 * params.scale.thin_share), r.scale.thin_radius);
  std::printf("radius      residual RMS  relief (peak-to-valley), median of %zu samples\n",
              r.scale.samples);
  for (std::size_t j = 0; j < r.scale.radii.size(); ++j)
    std::printf("%-11.4g %-13.4g %.4g\n", r.scale.radii[j], r.scale.residual[j], r.scale.relief[j]);
  return kExitOk;
}

// The --stats file: flat JSON, one key per figure, stage times under "seconds".
void write_stats(const std::string& path, std::size_t points, const RemoveTextureReport& r,
                 double read_s, double write_s, double peak_mib, const std::string& tiles = "") {
  std::string json;
  auto add = [&json](const char* format, auto... values) {
    char line[512];
    std::snprintf(line, sizeof line, format, values...);
    json += line;
  };
  double total = read_s + write_s;
  for (const auto& t : r.timings) total += t.seconds;
  add("{\n  \"points\": %zu,\n  \"threads\": %d,\n", points, omp_get_max_threads());
  add("  \"diagonal\": %.17g,\n  \"radius\": %.17g,\n  \"lambda\": %.17g,\n", r.diagonal, r.radius,
      r.lambda);
  add("  \"sigma_s\": %.17g,\n  \"sigma_p\": %.17g,\n", r.sigma_s, r.sigma_p);
  add("  \"radius_choice\": \"%s\",\n  \"radius_reason\": \"%s\",\n", r.radius_choice.c_str(),
      json_text(r.radius_reason).c_str());
  if (r.scale_estimated)
    add("  \"scale\": {\"texture_found\": %s, \"texture_radius\": %.6g, "
        "\"texture_height\": %.6g, \"spacing\": %.6g, \"noise\": %.6g, "
        "\"thin_radius\": %.6g, \"samples\": %zu, \"reason\": \"%s\"},\n",
        r.scale.texture_found ? "true" : "false", r.scale.texture_radius, r.scale.texture_height,
        r.scale.spacing, r.scale.noise, r.scale.thin_radius, r.scale.samples,
        json_text(r.scale.reason).c_str());
  add("  \"neighbors_mean\": %.6g,\n  \"neighbors_min\": %zu,\n  \"neighbors_max\": %zu,\n",
      r.neighbors.mean, r.neighbors.min, r.neighbors.max);
  add("  \"normals_ignored\": %s,\n  \"normals_estimated\": %s,\n",
      r.normals_ignored ? "true" : "false", r.normals_estimated ? "true" : "false");
  add("  \"normals_flipped\": %zu,\n  \"orientation_inconsistency\": %.6g,\n", r.normals_flipped,
      r.orientation_inconsistency);
  add("  \"duplicates_merged\": %zu,\n", r.duplicates_merged);
  add("  \"opposite_neighbors\": %zu,\n", r.opposite_neighbors);
  add("  \"surface_split_neighbors\": %zu,\n", r.surface_split_neighbors);
  add("  \"thin_part_points\": %zu,\n  \"thin_part_neighbors\": %zu,\n", r.thin_part_points,
      r.thin_part_neighbors);
  add("  \"mesh_path_points\": %zu,\n  \"mesh_path_neighbors\": %zu,\n", r.mesh_path_points,
      r.mesh_path_neighbors);
  add("  \"texture_height\": %.6g,\n  \"max_move\": %.6g,\n  \"moves_limited\": %zu,\n",
      r.texture_height, r.max_move, r.moves_limited);
  add("  \"relief_lean\": %.6g,\n  \"counter_moves_limited\": %zu,\n", r.relief_lean,
      r.counter_moves_limited);
  add("  \"tip_moves_limited\": %zu,\n", r.tip_moves_limited);
  add("  \"sink_moves_limited\": %zu,\n", r.sink_moves_limited);
  add("  \"raised_cells_lowered\": %zu,\n", r.raised_cells_lowered);
  add("  \"raised_cells_limited\": %zu,\n", r.raised_cells_limited);
  add("  \"raised_cells_turned\": %zu,\n", r.raised_cells_turned);
  add("  \"normals_not_fitted\": %zu,\n", r.normals_not_fitted);
  add("  \"normals_blended\": %zu,\n", r.normals_blended);
  add("  \"input_normals_kept\": %zu,\n", r.input_normals_kept);
  add("  \"input_normals_updated\": %zu,\n", r.input_normals_updated);
  add("  \"waves_flagged\": %zu,\n  \"waves_released\": %zu,\n", r.waves_flagged, r.waves_released);
  add("  \"texture_points\": %zu,\n  \"ransac_mean_iterations\": %.6g,\n", r.texture_points,
      r.ransac_mean_iterations);
  add("  \"rolling_iterations\": %d,\n  \"update_iterations\": %d,\n", r.rolling_iterations,
      r.update_iterations);
  if (r.mesh) {
    const auto& f = r.folds;
    add("  \"mesh\": {\"triangles\": %zu, \"edges\": %zu, \"normals_from_faces\": %s, "
        "\"vertices_held\": %zu, \"repair_rounds\": %d,\n",
        r.triangles, f.input.edges, r.normals_from_faces ? "true" : "false", f.vertices_held,
        f.rounds);
    for (const auto& [name, m] : {std::pair<const char*, const MeshFolds&>{"input", f.input},
                                  {"update", f.update},
                                  {"output", f.output}})
      add("    \"%s\": {\"folded_edges\": %zu, \"flipped_triangles\": %zu, "
          "\"p99_dihedral_deg\": %.6g}%s\n",
          name, m.folded, m.flipped, m.p99_dihedral_deg, std::string(name) == "output" ? "" : ",");
    add("  },\n");
  }
  json += tiles;
  add("  \"peak_memory_mib\": %.3f,\n  \"seconds\": {\n    \"read\": %.6f,\n", peak_mib, read_s);
  for (const auto& t : r.timings) add("    \"%s\": %.6f,\n", t.stage.c_str(), t.seconds);
  add("    \"write\": %.6f,\n    \"total\": %.6f\n  }\n}\n", write_s, total);
  write_text_file(path, json);  // temporary file renamed into place, like the clouds
}

// SIGINT and SIGTERM remove the hidden temporary outputs and exit 130 / 143,
// the shell's codes for death by those signals.
void on_interrupt(int signal_number) {
  remove_temporary_outputs();
  remove_tile_bins();
  _exit(128 + signal_number);
}

// OpenMP's runtime ends the process ("libgomp: Thread creation failed", exit
// 1) when it cannot start its threads, so they are tried first: a failure is
// then a clear message and the resource exit code.
void* idle(void*) { return nullptr; }
void check_threads(int count) {
  std::vector<pthread_t> started;
  int error = 0;
  for (int t = 1; t < count && error == 0; ++t) {
    pthread_t thread;
    error = pthread_create(&thread, nullptr, idle, nullptr);
    if (error == 0) started.push_back(thread);
  }
  for (pthread_t thread : started) pthread_join(thread, nullptr);
  if (error != 0)
    throw ResourceLimitError("cannot start " + std::to_string(count) + " worker threads (" +
                             std::strerror(error) + "); use --threads " +
                             std::to_string(std::max<std::size_t>(1, started.size())) +
                             " or raise the process limits (ulimit -u, -v, -s)");
}

// Memory that runs out inside a parallel loop cannot be caught there (an
// exception may not leave an OpenMP region): it ends in std::terminate. Say
// what happened and exit with the resource code instead of aborting.
[[noreturn]] void on_terminate() {
  remove_temporary_outputs();
  const char* message = "detexture: error: internal error (an unexpected exception)\n";
  int code = kExitFailure;
  try {
    if (const std::exception_ptr e = std::current_exception()) std::rethrow_exception(e);
  } catch (const std::bad_alloc&) {
    message =
        "detexture: error: out of memory; use a smaller --radius or --max-neighbors, fewer "
        "--threads, or a machine with more memory\n";
    code = kExitResource;
  } catch (...) {
  }
  if (write(STDERR_FILENO, message, std::strlen(message)) < 0) {
  }
  _exit(code);
}

void install_signal_cleanup() {
  std::set_terminate(on_terminate);
  struct sigaction action {};
  action.sa_handler = on_interrupt;
  sigemptyset(&action.sa_mask);
  for (const int signal_number : {SIGINT, SIGTERM, SIGHUP})
    sigaction(signal_number, &action, nullptr);
}

}  // namespace

int run_detexture(int argc, char** argv) {
  RemoveTextureParams params;
  std::string input, output, texture_layer, format_in = "auto", format_out = "auto",
                                            encoding = "binary";
  int threads = 0;
  bool quiet = false, force = false, texture_fields = false;
  bool no_subneighborhood = false, no_blend = false;

  CLI::App app{
      "detexture: remove geometric surface texture (scales, knurls, engravings, bumps) from a "
      "point cloud while keeping its underlying shape and sharp structures (Sun et al., "
      "Reliable Rolling-guided Point Normal Filtering for Surface Texture Removal, PG 2019).\n"
      "Lengths are in the cloud's units, a fraction of the bounding-box diagonal with a "
      "trailing d (0.02d), or a multiple of the radius r with a trailing r (0.5r).\nOther "
      "commands: 'detexture synth --help', 'detexture compare --help', 'detexture render --help'.",
      "detexture"};
  app.get_formatter()->column_width(34);
  app.footer(
      "Examples:\n"
      "  detexture scan.ply -o scan.smooth.ply               r chosen from the cloud (1.5 x the "
      "texture radius)\n"
      "  detexture scan.ply --scale-report                   what it finds, without filtering\n"
      "  detexture scan.xyz -o out.ply -r 0.03d --texture-fields --texture-layer texture.ply\n"
      "  detexture render scan.ply scan.smooth.ply -o before_after.png\n"
      "Exit codes: 0 ok, 1 internal error, 2 bad parameter, 3 bad input, 4 output cannot be "
      "written, 5 resource limit, 130/143/129 interrupted (README, Exit codes).\n"
      "'detexture --version' prints the version and commit; 'detexture help' is this text.");
  app.add_option("INPUT", input, "Input point cloud or mesh (" + known_extensions() + ")")
      ->required();
  app.add_option("-o,--output", output,
                 "Output point cloud or mesh (.ply, .obj, .off, .stl, .pcd, .xyz ...); required");
  app.add_option("--input-format", format_in,
                 "Input format: auto (by extension), ply, obj, off, stl, pcd, xyz")
      ->capture_default_str();
  app.add_option("--output-format", format_out,
                 "Output format: auto (by extension), ply, obj, off, stl, pcd, xyz")
      ->capture_default_str();
  app.add_option("--encoding", encoding,
                 "Output encoding: binary, ascii (PLY, STL, PCD), binary-big-endian (PLY), "
                 "binary-compressed (PCD)")
      ->capture_default_str();
  app.add_flag("-f,--force", force,
               "Overwrite OUTPUT if it exists; run even when r would put a large share of the "
               "cloud in every neighborhood");

  add_length(app, "-r,--radius", params.radius,
             "r: neighborhood radius (a radius, not a diameter), e.g. -r 0.05 or -r 0.03d. "
             "By default 1.5 × the texture radius estimated from the cloud (1.5t; see "
             "--scale-report); give it to override: about 1.5 × the radius of the largest "
             "texture feature you want gone; larger also blurs more of the shape.");
  bool scale_report = false;
  app.add_flag("--scale-report", scale_report,
               "Print the estimated point spacing, noise and texture size, and the r auto mode "
               "would choose, then exit without filtering (no -o needed)");
  add_length(app, "--lambda", params.lambda,
             "λ: RANSAC distance threshold (Eq. 2). Relief lower than λ counts as underlying "
             "surface; must exceed the noise");
  app.add_option("--delta", params.texture.delta,
                 "δ: share of its neighborhoods in which a point must fit the plane to count "
                 "as underlying surface (Eq. 2), in (0,1). Higher marks more points as texture")
      ->capture_default_str();
  add_length(app, "--sigma-s", params.sigma_s,
             "σs: spatial scale of the normal filters (Eqs. 1, 3). Texture finer than σs is "
             "smoothed away");
  app.add_option("--planes", params.texture.planes,
                 "RANSAC planes per neighborhood (Eq. 2): 1 is the paper; 2-3 also keep the "
                 "other faces at creases and corners as surface instead of texture")
      ->capture_default_str();
  app.add_option("--move-limit", params.move_limit,
                 "No point moves farther than this multiple of the texture height found, plus "
                 "λ; 0 for no limit (the paper)")
      ->capture_default_str();
  app.add_option("--counter-move-limit", params.counter_moves.limit,
                 "Where the relief was raised (the texture points' large moves go mostly "
                 "inward), no point moves outward by more than this multiple of the texture "
                 "height: no fillet bridging a concave junction (inward, where sparse relief "
                 "was engraved); 0 for no limit")
      ->capture_default_str();
  app.add_option("--counter-move-lean", params.counter_moves.min_lean,
                 "The relief counts as raised when the lean of the texture points' large "
                 "moves, (inward - outward) / all, reaches this, in (0, 1]")
      ->capture_default_str();
  app.add_option("--counter-move-released-lean", params.counter_moves.released_min_lean,
                 "... in the second update over waves, whose released anchors move both ways, "
                 "from this lean, in (0, 1]")
      ->capture_default_str();
  app.add_flag("!--counter-move-limit-released", params.counter_moves.free_released,
               "Also limit the outward moves of the points whose anchors the second update "
               "over waves released (before session 27)");
  app.add_option("--counter-move-engraved-lean", params.counter_moves.engraved_min_lean,
                 "... and as engraved when the lean is at most minus this, in (0, 1]")
      ->capture_default_str();
  app.add_option("--counter-move-engraved-share", params.counter_moves.engraved_share,
                 "Limit inward moves where the relief leans engraved only if texture points "
                 "are at most this share of the cloud (sparse grooves, not dense scales, "
                 "whose gaps read as engraved); 0 never, 1 always")
      ->capture_default_str();
  app.add_flag("!--counter-move-hard", params.counter_moves.soft,
               "Cut moves against the relief at the limit instead of saturating them "
               "smoothly (limit × tanh(move / limit))");
  app.add_option("--tip-depth", params.tips.depth,
                 "A point is a tip of the relief (a top, or a groove's bottom) when a neighbor "
                 "within the solve radius lies this many λ below it along its normal and none "
                 "more than --tip-slack λ above; a tip ends at most --tip-slack λ past its "
                 "farthest neighbor. 0 turns the limit off")
      ->capture_default_str();
  app.add_option("--tip-slack", params.tips.slack,
                 "How far past its farthest neighbor a tip may lie, and end, in units of λ")
      ->capture_default_str();
  app.add_option("--sink-depth", params.sinks.depth,
                 "Where the relief was raised, a point that a neighbor within the solve radius "
                 "rises this many λ above, along its normal, sinks no farther than the texture "
                 "height, or its own height above the surface fitted to its neighborhood plus "
                 "--sink-slack λ where that is more")
      ->capture_default_str();
  app.add_option("--sink-slack", params.sinks.slack,
                 "How far below its own height above its fitted surface such a point may sink, "
                 "in units of λ; 0 turns the limit off")
      ->capture_default_str();
  app.add_flag("!--keep-cells-tops", params.raised_cells.enabled,
               "Leave the output on the tops of dense raised cells (scales packed edge to "
               "edge, read from a lean of at least --counter-move-engraved-lean outward and "
               "more than --counter-move-engraved-share texture) instead of lowering it to "
               "the cells' feet (the paper)");
  app.add_option("--cells-low-quantile", params.raised_cells.low_quantile,
                 "Dense raised cells: the quantile of the input's heights below the output, "
                 "within the solve radius, read as the cells' feet")
      ->capture_default_str();
  app.add_option("--cells-spread-quantile", params.raised_cells.spread_quantile,
                 "Dense raised cells: the quantile of the neighbors' feet a point sinks to")
      ->capture_default_str();
  app.add_option("--cells-max-depth", params.raised_cells.max_depth,
                 "Dense raised cells: the deepest a point may end below its own input, along "
                 "its normal, in units of the texture height; 0 turns the limit off")
      ->capture_default_str();
  app.add_option("--cells-max-turn", params.raised_cells.max_turn_deg,
                 "Dense raised cells: a point whose output normal turned more than this many "
                 "degrees from the mean of its neighbors' sinks along that mean; 180 turns the "
                 "test off")
      ->capture_default_str();
  app.add_flag("!--sheet-any-pair", params.sheets.back_to_back_only,
               "Leave out every neighbor past --sheet-angle, not only those back to back "
               "with the point (across a thin part)");
  app.add_option("--sheet-angle", params.sheets.max_angle_deg,
                 "Neighbors back to back with the point (across a thin part or a convex "
                 "crease) whose normal differs from its normal by more than this (degrees) "
                 "are left out of R_i; 180 keeps all (the paper)")
      ->capture_default_str();
  app.add_option("--surface-split-angle", params.surface_split.max_angle_deg,
                 "Clouds: after texture detection, a neighbor pair leaves R_i when neither "
                 "point's surface (its normal, or the surface fitted under it if texture) is "
                 "within this angle of the other's normal (degrees): tips, rims, curled ears; "
                 "180 keeps all (the paper)")
      ->capture_default_str();
  app.add_option("--thin-part-radius", params.thin_parts.min_radius_fraction,
                 "On parts thinner than r (limbs, fingers), R_i shrinks to the distance of "
                 "the part's back, but not below this fraction of r; 1 keeps r everywhere "
                 "(the paper)")
      ->capture_default_str();
  app.add_option("--mesh-path-limit", params.mesh_paths.path_factor,
                 "Meshes: R_i keeps only the neighbors an edge path of the mesh reaches "
                 "within this multiple of r (not the next finger or a touching part); 0 "
                 "keeps R_i Euclidean")
      ->capture_default_str();
  std::map<std::string, UnderlyingSurface> surfaces{{"plane", UnderlyingSurface::Plane},
                                                    {"quadric", UnderlyingSurface::Quadric}};
  add_choice(app, "--surface", params.texture.surface, surfaces,
             "Model of the underlying surface in each neighborhood (Eq. 2): plane (the "
             "paper: piecewise flat) or quadric (ours: the RANSAC plane bent to a curved "
             "surface, for organic shapes)",
             "MODEL");
  add_length(app, "--min-surface-radius", params.min_surface_radius,
             "Quadric surface: the tightest radius of curvature the underlying surface may "
             "have; more tightly curved relief is texture");
  app.add_option("--sigma-r", params.rolling.sigma_r_deg,
                 "σr: range scale of the rolling filter (Eq. 3), degrees. Larger gives smoother "
                 "results; at 30 the filter alone brings back creases of 90° and more, at 45 "
                 "it leaves them to the surface split (--surface-split-angle)")
      ->capture_default_str();
  app.add_option("--iterations", params.rolling.iterations,
                 "Rolling iterations k (Eq. 3); more recovers larger structures")
      ->capture_default_str();
  app.add_option("--rolling-tolerance", params.rolling.tolerance_deg,
                 "Stop rolling once the mean normal change is below this, degrees")
      ->capture_default_str();
  add_length(app, "--sigma-p", params.sigma_p,
             "σp: spatial scale of the position-update weights (Eqs. 9-10)");
  app.add_option("--isotropy", params.update.isotropy_deg,
                 "Isotropic neighborhood Ψ (Eq. 10): neighbors whose normal is within this "
                 "angle, degrees")
      ->capture_default_str();
  std::map<std::string, UpdateMode> update_modes{{"global", UpdateMode::Global},
                                                 {"isotropic", UpdateMode::Isotropic},
                                                 {"eq9", UpdateMode::Eq9}};
  add_choice(app, "--update", params.update.mode, update_modes,
             "Position update: global (ours: one least-squares solve, removes the texture "
             "from the positions too), isotropic (the paper's Eq. 10), eq9 (Eq. 9, Fig. 8 "
             "ablation)",
             "MODE");
  std::map<std::string, GuidanceMode> guidance_modes{{"patch-shift", GuidanceMode::PatchShift},
                                                     {"plain", GuidanceMode::Plain}};
  add_choice(app, "--guidance", params.rolling.guidance.mode, guidance_modes,
             "Guidance normals: plain (classic rolling guidance of Zheng et al. 2018; as "
             "good or better on both quality suites) or patch-shift (the paper, Eqs. 4-8)",
             "MODE");
  std::map<std::string, NormalDifference> differences{
      {"angle", NormalDifference::Angle}, {"one-minus-cos", NormalDifference::OneMinusCos}};
  add_choice(app, "--difference", params.rolling.guidance.difference, differences,
             "D in Eq. 4-5 (patch-shift guidance): angle or one-minus-cos", "MODE");
  app.add_flag("--no-blend", no_blend, "Skip the α blend of the patch-shift guidance (Eqs. 7-8)");
  std::string mesh_mode = "faces";
  app.add_option("--mesh", mesh_mode,
                 "An input with faces: 'faces' takes its normals from the faces (no PCA) and "
                 "keeps the update from folding edges or flipping triangles; 'cloud' treats its "
                 "vertices as an unconnected cloud (the paper)")
      ->check(CLI::IsMember({"faces", "cloud"}))
      ->capture_default_str();
  app.add_flag("--no-subneighborhood", no_subneighborhood,
               "Filter over all of R_i instead of the sub-neighborhood Ω_i (plain Gaussian, "
               "Fig. 4 ablation); also in Eq. 3");
  std::map<std::string, SubneighborhoodMode> omega_modes{{"hard", SubneighborhoodMode::Hard},
                                                         {"soft", SubneighborhoodMode::Soft}};
  app.add_option("--vote-normal-angle", params.texture.vote_normal_angle_deg,
                 "Eq. 2's votes: a point counts as fitting a neighborhood's plane only if its "
                 "normal is also within this angle (degrees) of the plane's; 180 = positions "
                 "alone (the paper)")
      ->capture_default_str();
  add_choice(app, "--subneighborhood", params.texture.subneighborhood, omega_modes,
             "Ω_i in Eqs. 1 and 3: hard (the paper: surface points only) or soft (ours: "
             "weighted by the share of neighborhoods in which a point fits the plane; "
             "better on dense texture covering the whole surface, such as scales or "
             "knurls; worse on grooves)",
             "MODE");
  app.add_option("--soft-floor", params.texture.soft_floor,
                 "Soft sub-neighborhood: a point fitting the plane in at most this share of its "
                 "neighborhoods weighs nothing; at δ or more it weighs fully")
      ->capture_default_str();
  bool paper_rolling_neighborhood = false;
  app.add_flag("--paper-rolling-neighborhood", paper_rolling_neighborhood,
               "Sum Eq. 3 over R_i as printed in the paper, instead of Ω_i");
  app.add_option("--anchor-surface", params.update.anchor_surface,
                 "Global update: how strongly underlying-surface points keep their place")
      ->capture_default_str();
  app.add_option("--anchor-height", params.anchor_height,
                 "Global update: surface points are held at their place less the farther they "
                 "sit from the surface fitted to their neighborhood (noise, wave flanks), with "
                 "a Gaussian fall-off of this multiple of λ; 0 holds them all fully")
      ->capture_default_str();
  app.add_option("--anchor-angle", params.anchor_angle,
                 "Global update: surface points are also held less the more their input normal "
                 "turns from the filtered normal (the foot of a bump, noise), with a Gaussian "
                 "fall-off of this angle (degrees); 0 turns it off")
      ->capture_default_str();
  enum class OutputNormals { Filtered, Fitted, Blended };
  const std::map<std::string, OutputNormals> output_normal_modes{
      {"filtered", OutputNormals::Filtered},
      {"fitted", OutputNormals::Fitted},
      {"blended", OutputNormals::Blended}};
  OutputNormals output_normals = !params.fit_normals ? OutputNormals::Filtered
                                 : params.output_normals.blend_high_deg > 0.0
                                     ? OutputNormals::Blended
                                     : OutputNormals::Fitted;
  add_choice(app, "--output-normals", output_normals, output_normal_modes,
             "Clouds: blended (the normals of the output surface, a weighted plane fit to "
             "the output points guided by the filtered normals, taken where it agrees with "
             "the filtered normals around the point and the filtered normals where waves, "
             "grooves or noise left in the positions make them disagree), fitted (the fit "
             "everywhere) or filtered (the paper: the filtered normals, smoothed at σs). "
             "Meshes with --mesh faces take theirs from the output's faces",
             "MODE");
  add_length(app, "--fit-sigma", params.fit_sigma,
             "Fitted output normals: spatial scale of the fit's weights (neighbors within "
             "--solve-radius take part)");
  app.add_option("--fit-range-sigma", params.output_normals.range_sigma,
                 "Fitted output normals: range scale on 1 - cos of the angle between the "
                 "normals of --fit-range-normals; smaller keeps the fit closer to one side of a "
                 "crease")
      ->capture_default_str();
  enum class RangeNormals { Input, Filtered };
  const std::map<std::string, RangeNormals> range_normal_modes{
      {"input", RangeNormals::Input}, {"filtered", RangeNormals::Filtered}};
  RangeNormals range_normals =
      params.fit_range_input_normals ? RangeNormals::Input : RangeNormals::Filtered;
  add_choice(app, "--fit-range-normals", range_normals, range_normal_modes,
             "Fitted output normals: the normals --fit-range-sigma compares, input (those "
             "that came with the input, which turn where its surface does; the filtered ones "
             "when the input had none) or filtered (rounded at σs)",
             "WHICH");
  app.add_option("--fit-fine-ratio", params.output_normals.fine_ratio,
                 "Fitted output normals: a second fit at this fraction of --fit-sigma, taken "
                 "where it departs from the first by more than its noise explains; 0 for none")
      ->capture_default_str();
  app.add_option("--fit-fine-gamma", params.output_normals.fine_gamma,
                 "Fitted output normals: the fine fit is taken from a departure of this many "
                 "times its noise angle on (fully from one more)")
      ->capture_default_str();
  app.add_option("--keep-input-low", params.keep_input.low,
                 "Output normals: where no point within --solve-radius moved by more than this "
                 "multiple of λ, the input normal is kept (the output surface is the input's "
                 "there)")
      ->capture_default_str();
  app.add_option("--keep-input-high", params.keep_input.high,
                 "Output normals: from a move of this multiple of λ on, the fitted normal "
                 "stays (linearly between); 0 for no input normal kept by the move")
      ->capture_default_str();
  app.add_option("--keep-input-exact-angle", params.keep_input.exact_angle_deg,
                 "Output normals: an exact input normal (its nearest neighbors lie in its "
                 "tangent plane: no noise) is kept wherever it lies within this angle of the "
                 "fitted one, in degrees, in [0, 90); 0 for none")
      ->capture_default_str();
  app.add_option("--keep-input-exact-residual", params.keep_input.exact_residual,
                 "Output normals: an input normal is exact where its nearest neighbors lie "
                 "within this mean distance of its tangent plane, a multiple of λ")
      ->capture_default_str();
  app.add_option("--keep-input-still-angle", params.keep_input.still_angle_deg,
                 "Output normals: where nothing within --solve-radius moved by more than "
                 "--keep-input-still-move λ, an exact input normal is kept up to this angle of "
                 "the fitted one (degrees, in [0, 90)) if its neighbors' input normals agree "
                 "and the fitted normals around turn as much (facets); 0 for none")
      ->capture_default_str();
  app.add_option("--keep-input-still-move", params.keep_input.still_move,
                 "Output normals: the move, a multiple of λ, under which the surface counts as "
                 "stayed for --keep-input-still-angle (1 before session 32)")
      ->capture_default_str();
  app.add_option("--keep-input-still-move-engraved", params.keep_input.still_move_engraved,
                 "Output normals: --keep-input-still-move where the relief reads as sparse "
                 "engraving (see --counter-move-engraved-lean): flat groove walls move as "
                 "little as facets")
      ->capture_default_str();
  app.add_option("--keep-input-still-uniform", params.keep_input.still_uniform_deg,
                 "Output normals: the angle (degrees) within which the nearest neighbors' input "
                 "normals must agree for --keep-input-still-angle")
      ->capture_default_str();
  app.add_option("--keep-input-facet-neighbors", params.keep_input.facet_neighbors,
                 "Output normals: an input normal also counts as exact where, among this many "
                 "nearest neighbors, those whose input normals lie within "
                 "--keep-input-still-uniform of it (its facet, at least "
                 "--keep-input-facet-members) lie in its tangent plane and spread in two "
                 "directions, and at most 2 others turn gradually (up to 3 times that angle) "
                 "instead of by an edge's jump: facets a few points wide; 0 for none")
      ->capture_default_str();
  app.add_option("--keep-input-facet-members", params.keep_input.facet_members,
                 "Output normals: the fewest members (>= 3) a facet needs for "
                 "--keep-input-facet-neighbors; 8 before session 28")
      ->capture_default_str();
  app.add_option("--keep-input-facet-groups", params.keep_input.facet_groups,
                 "Output normals: for --keep-input-facet-neighbors, more than 2 neighbors that "
                 "turn gradually are allowed where their input normals lie on at most this "
                 "many other flat facets (the far side of a shallow edge, the facets around a "
                 "vertex); 0 for the count alone (before session 36)")
      ->capture_default_str();
  app.add_option("--keep-input-still-reach", params.keep_input.still_reach,
                 "Output normals: for --keep-input-still-angle, some fitted normal within "
                 "--solve-radius must lie within this fraction of the input normal's angle to "
                 "the point's own fitted normal of it (the fitted normals reach towards it, as "
                 "on a rounded facet), in [0, 1); 0 for the cone test instead (they turn as "
                 "much in any direction, before session 25)")
      ->capture_default_str();
  app.add_option("--keep-input-reached-angle", params.keep_input.reached_angle_deg,
                 "Output normals: an exact input normal no other test took is kept up to this "
                 "angle of the fitted one (degrees, in [0, 90)) where some output normal within "
                 "--solve-radius lies within --keep-input-reached-share of that angle of it "
                 "(a thin part's facet the fit rounded, not a groove wall or a wave's flank); 0 "
                 "for none (before session 37)")
      ->capture_default_str();
  app.add_option("--keep-input-reached-share", params.keep_input.reached_share,
                 "Output normals: for --keep-input-reached-angle, the fraction of the input "
                 "normal's angle to the fitted one within which some output normal around must "
                 "lie, in (0, 1)")
      ->capture_default_str();
  app.add_flag("--keep-input-reached-engraved", params.keep_input.reached_engraved,
               "Output normals: --keep-input-reached-angle also where the relief reads as "
               "sparse engraving (see --counter-move-engraved-lean), whose flat groove walls "
               "the earlier tests take in places");
  app.add_flag("!--keep-input-still-any-move", params.keep_input.still_facet_move,
               "Output normals: for --keep-input-still-angle the surface counts as stayed only "
               "where no point within --solve-radius moved by more than --keep-input-still-move "
               "λ, not also where none of the point's facet did (before session 25)");
  app.add_flag("!--keep-input-surface-only", params.keep_input.texture_facets,
               "Output normals: only points labelled surface (Eq. 2) may take their input "
               "normal, not also texture-labelled ones whose nearest neighbors' input normals "
               "agree (facets where several meet; before session 25)");
  app.add_flag("!--update-filtered-normals", params.update_input_normals,
               "Position update: fit the filtered normals everywhere, not the exact input normals "
               "that the --keep-input tests would take were nothing to move (facets the "
               "filters rounded; before session 43)");
  app.add_option("--fit-max-turn", params.output_normals.max_turn_deg,
                 "Fitted output normals: a fit turning farther than this from the filtered "
                 "normal (degrees) is not taken")
      ->capture_default_str();
  app.add_option("--blend-low", params.output_normals.blend_low_deg,
                 "Blended output normals: where the fit and the filtered normals differ by "
                 "at most this mean angle around a point (degrees), the fit is taken")
      ->capture_default_str();
  app.add_option("--blend-high", params.output_normals.blend_high_deg,
                 "Blended output normals: from this mean angle on (degrees), the filtered "
                 "normal; linearly between the two. 0 turns the blend off (= fitted)")
      ->capture_default_str();
  app.add_option("--blend-coherence", params.output_normals.blend_coherence,
                 "Blended output normals: where the fit's departures from the filtered normals "
                 "around a point have no one direction (their largest eigenvalue's share below "
                 "this; 1 = along one direction, as across waves or grooves), the fit is also "
                 "taken up to --blend-isotropic-high. 0 turns this off")
      ->capture_default_str();
  app.add_option("--blend-isotropic-high", params.output_normals.blend_isotropic_high_deg,
                 "Blended output normals: the mean angle (degrees) up to which the fit is taken "
                 "where --blend-coherence allows")
      ->capture_default_str();
  app.add_option("--wave-share-low", params.wave_share_low,
                 "Waves left in the positions: when the output-normal fit flags more than this "
                 "share of the surface points as lying on waves or grooves the update left, "
                 "the update runs again with their anchors lowered; 1 turns this off")
      ->capture_default_str();
  app.add_option("--wave-share-high", params.wave_share_high,
                 "Waves left in the positions: from this share on, the flagged points are "
                 "anchored like texture (the lowering ramps up from --wave-share-low)")
      ->capture_default_str();
  app.add_option("--wave-rest-anchor", params.wave_rest_anchor,
                 "Waves left in the positions: in the update's second run, the other surface "
                 "points are anchored with this factor (to the power of the same ramp), so the "
                 "flanks beside the flagged crests follow the filtered normals too; in (0, 1], "
                 "1 holds them fully (before session 38)")
      ->capture_default_str();
  app.add_option("--wave-ceiling", params.wave_ceiling,
                 "Waves left in the positions: in the update's second run, a point in the upper "
                 "half of its relief moves outward by at most this many lambda (one in the "
                 "lower half inward); 0 turns this off (before session 39)")
      ->capture_default_str();
  app.add_option("--blend-share-low", params.blend_share_low,
                 "Blended output normals: when the output-normal fit flags less than this "
                 "share of the surface points as lying on waves or grooves the update left, "
                 "the blend takes the open window (--blend-open-low, --blend-open-high)")
      ->capture_default_str();
  app.add_option("--blend-share-high", params.blend_share_high,
                 "Blended output normals: from this share on, the blend's own window (mixed "
                 "with the open one between the two shares); 0 keeps it on every cloud")
      ->capture_default_str();
  app.add_option("--blend-open-low", params.output_normals.blend_open_low_deg,
                 "Blended output normals, the open window (clouds without waves left): the fit "
                 "is taken up to this mean angle (degrees) from the filtered normals")
      ->capture_default_str();
  app.add_option("--blend-open-high", params.output_normals.blend_open_high_deg,
                 "Blended output normals, the open window: from this mean angle on, the "
                 "filtered normal is kept; linearly between the two")
      ->capture_default_str();
  app.add_option("--anchor-texture", params.update.anchor_texture,
                 "Global update: how strongly texture points keep their place")
      ->capture_default_str();
  app.add_option("--update-tolerance", params.update.tolerance,
                 "Position update: stop once the residual is below this fraction of where it "
                 "started (global), or a point moves less than this times σp (local modes)")
      ->capture_default_str();
  add_length(app, "--solve-radius", params.solve_radius,
             "Global update: neighbors closer than this take part in the solve");
  app.add_option("--max-neighbors", params.max_neighbors,
                 "Keep at most this many nearest neighbors in R_i (0 = no cap)")
      ->capture_default_str();
  app.add_option_function<std::string>(
         "--memory-limit",
         [&params](const std::string& text) {
           try {
             params.memory_limit = parse_memory_size(text);
           } catch (const std::invalid_argument& e) {
             throw CLI::ValidationError("--memory-limit", e.what());
           }
         },
         "Refuse a run whose neighborhoods would need more memory than this (estimated from a "
         "sample before they are built): bytes, or 500M, 4G; 'none' for no limit [default: 80% "
         "of the physical memory]")
      ->type_name("SIZE");
  app.add_option("--normal-neighbors", params.normal_neighbors,
                 "k nearest neighbors for estimating and orienting normals when the input has "
                 "none")
      ->capture_default_str();
  app.add_flag("--reorient", params.reorient,
               "Re-orient the input normals consistently before filtering");
  std::map<std::string, NormalSide> sides{
      {"auto", NormalSide::Auto}, {"outward", NormalSide::Outward}, {"inward", NormalSide::Inward},
      {"+x", NormalSide::PlusX},  {"-x", NormalSide::MinusX},       {"+y", NormalSide::PlusY},
      {"-y", NormalSide::MinusY}, {"+z", NormalSide::PlusZ},        {"-z", NormalSide::MinusZ}};
  add_choice(app, "--orient", params.orient.side, sides,
             "Side that estimated (and --reorient) normals face, for each connected part: "
             "auto (outward for closed parts and caps, up (+z) for flat open sheets), "
             "outward, inward, or +x, -x, +y, -y, +z, -z (a scan seen from that direction)",
             "SIDE");
  app.add_flag("--ignore-normals", params.ignore_input_normals,
               "Estimate the normals from the positions (as for a cloud without normals) even "
               "when the input has them: for scans whose normals are noisy or wrong in places");
  app.add_option("--ransac-confidence", params.texture.confidence,
                 "RANSAC stops once the best plane is found with this probability")
      ->capture_default_str();
  app.add_option("--ransac-max-iterations", params.texture.max_iterations,
                 "Cap on RANSAC tries per neighborhood")
      ->capture_default_str();
  app.add_option("--seed", params.texture.seed, "Seed of the RANSAC generators")
      ->capture_default_str();

  app.add_flag("--texture-fields", texture_fields,
               "Add per-point properties 'texture' (0/1, Eq. 2) and 'texture_height' (signed "
               "displacement removed along the output normal) to a PLY output");
  app.add_option("--texture-layer", texture_layer,
                 "Also write the input cloud with its 'texture_height' (PLY): the texture "
                 "layer on its own");
  app.add_option("-j,--threads", threads, "Worker threads (0 = all cores)")
      ->capture_default_str()
      ->check(CLI::Range(0, 4096));
  app.add_flag("-q,--quiet", quiet, "No progress or summary on stderr");
  TilingOptions tiling;
  add_tiling_options(app, tiling);
  std::string stats_path;
  app.add_option("--stats", stats_path,
                 "Write the run's figures (counts, resolved parameters, seconds per stage, peak "
                 "memory) as JSON to this file");

  try {
    app.parse(argc, argv);
    if (output.empty() && !scale_report) throw CLI::RequiredError("--output");
  } catch (const CLI::ParseError& e) {
    const int code = app.exit(e);
    return code == 0 ? kExitOk : kExitUsage;
  }

  tiling.memory_limit_given = app.count("--memory-limit") > 0;
  ProgressPrinter printer(quiet);
  try {
    if (output_normals != OutputNormals::Blended &&
        (app.count("--blend-low") > 0 || app.count("--blend-high") > 0 ||
         app.count("--blend-coherence") > 0 || app.count("--blend-isotropic-high") > 0))
      throw std::invalid_argument(
          "--blend-low, --blend-high, --blend-coherence and --blend-isotropic-high apply to "
          "--output-normals blended only, not to " +
          name_of(output_normal_modes, output_normals));
    params.fit_normals = output_normals != OutputNormals::Filtered;
    params.fit_range_input_normals = range_normals == RangeNormals::Input;
    if (output_normals == OutputNormals::Fitted) params.output_normals.blend_high_deg = 0.0;
    params.gaussian.use_subneighborhood = !no_subneighborhood;
    if (no_subneighborhood) params.rolling.use_subneighborhood = false;
    params.rolling.guidance.blend = !no_blend;
    if (paper_rolling_neighborhood) params.rolling.use_subneighborhood = false;
    params.allow_large_radius = force;
    params.threads = threads;
    validate(params);
    check_threads(thread_count(threads));
    const ScopedThreads thread_scope(threads);  // for the stages run outside remove_texture
    const FileFormat in_format = parse_file_format(format_in);
    const FileFormat out_format = parse_file_format(format_out);
    WriteOptions write_options;
    write_options.format = out_format;
    write_options.protect_path = input;
    if (encoding == "binary")
      write_options.encoding = PlyEncoding::BinaryLittleEndian;
    else if (encoding == "ascii")
      write_options.encoding = PlyEncoding::Ascii;
    else if (encoding == "binary-big-endian")
      write_options.encoding = PlyEncoding::BinaryBigEndian;
    else if (encoding == "binary-compressed")
      write_options.compressed = true;
    else
      throw std::invalid_argument(
          "--encoding must be binary, ascii, binary-big-endian or binary-compressed");
    std::vector<std::string> write_notices;
    write_options.notices = &write_notices;
    if (scale_report) return print_scale_report(input, in_format, params);
    // Check the outputs before the work, so a long run does not end in a refusal.
    try {
      check_output_paths({output, texture_layer, stats_path}, input, force);
    } catch (const std::runtime_error& e) {
      throw OutputError(e.what());
    }
    for (const std::string& path : {output, texture_layer}) {
      if (path.empty()) continue;
      try {
        check_write_options(path, write_options);
      } catch (const std::invalid_argument&) {
        throw;
      } catch (const std::runtime_error& e) {
        throw std::invalid_argument(e.what());  // a usage error: exit 2
      }
    }
    install_signal_cleanup();
    if (tiling.out_of_core()) {
      if (!texture_layer.empty() || texture_fields)
        throw std::invalid_argument(
            "--texture-fields and --texture-layer are not available out of core (--temp-dir)");
      if (encoding != "binary" || (out_format != FileFormat::Auto && out_format != FileFormat::Ply))
        throw std::invalid_argument("out-of-core runs write binary PLY");
      if (out_format == FileFormat::Auto && format_from_extension(output) != FileFormat::Ply)
        throw std::invalid_argument("out-of-core runs write binary PLY: give OUTPUT a .ply name");
      const auto start = std::chrono::steady_clock::now();
      OutOfCoreReport ooc;
      try {
        ooc = run_out_of_core(input, output, params, tiling, quiet);
      } catch (const ResourceLimitError&) {
        throw;
      } catch (const std::runtime_error& e) {
        throw InputError(e.what());
      }
      if (!ooc.root) return kExitOk;
      const double total =
          std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
      struct rusage usage {};
      getrusage(RUSAGE_SELF, &usage);
      RemoveTextureReport& r = ooc.report;
      r.timings.insert(r.timings.begin(), {{"scan", ooc.scan_seconds}, {"bin", ooc.bin_seconds}});
      if (!stats_path.empty()) try {
          write_stats(stats_path, ooc.points, r, 0.0, 0.0, usage.ru_maxrss / 1024.0,
                      tiles_json(ooc.tiles));
        } catch (const std::runtime_error& e) {
          throw OutputError(e.what());
        }
      if (!quiet)
        std::fprintf(stderr,
                     "wrote %s\nsummary: %llu points out of core in %zu tiles, r = %g; texture "
                     "points %zu; total %.2f s; peak memory %.0f MiB\n",
                     output.c_str(), static_cast<unsigned long long>(ooc.points),
                     ooc.tiles.tiles_run, r.radius, r.texture_points, total,
                     usage.ru_maxrss / 1024.0);
      return kExitOk;
    }

    const auto t0 = std::chrono::steady_clock::now();
    PointCloud cloud;
    ReadReport read_report;
    try {
      cloud = read_point_cloud(input, in_format, &read_report);
    } catch (const std::bad_alloc&) {
      throw;  // a resource limit, not a bad file
    } catch (const std::exception& e) {
      throw InputError(e.what());
    }
    const double read_s =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    for (const std::string& path : {output, texture_layer})
      if (!path.empty() && !has_faces(cloud) &&
          (out_format == FileFormat::Auto ? format_from_extension(path) : out_format) ==
              FileFormat::Stl)
        throw std::invalid_argument("'" + path + "': STL holds triangles, and '" + input +
                                    "' has no faces; write .ply, .xyz or .pcd for a point cloud");
    for (const auto& notice : read_report.notices) printer.note("detexture: note: " + notice);
    params.use_faces = mesh_mode == "faces";
    const std::string source =
        has_faces(cloud) && params.use_faces ? "taking them from the faces" : "estimating them";
    printer.note("read " + std::to_string(cloud.size()) + " points from " + input +
                 (!cloud.has_normals()          ? " (no normals: " + source + ")"
                  : params.ignore_input_normals ? " (with normals, ignored: " + source + ")"
                                                : " (with normals)"));
    if (read_report.zero_length_normals > 0)
      printer.note("detexture: note: " + std::to_string(read_report.zero_length_normals) +
                   " input normals have zero length; they are re-estimated");

    // Positions and normals are handed over and come back in the result, so
    // the pipeline can free them early: memory per point is a stated target.
    Normals normals = cloud.has_normals() ? std::move(cloud.normals) : Normals();
    cloud.normals = Normals();
    FaceList faces;
    try {
      faces = face_list(cloud);
    } catch (const std::invalid_argument& e) {
      throw InputError("'" + input + "': " + e.what());
    }
    std::string tiles;
    if (faces.size() > 0 && tiling.tile_given)
      throw std::invalid_argument(
          "--tile works on point clouds, and '" + input +
          "' has faces; leave out --tile, or "
          "filter the vertices as a cloud with --mesh cloud and drop the faces first");
    RemoveTextureResult result =
        faces.size() > 0 ? remove_texture(std::move(cloud.positions), std::move(normals), faces,
                                          params, printer.observer())
                         : run_maybe_tiled(std::move(cloud.positions), std::move(normals), params,
                                           tiling, printer.observer(), quiet, &tiles);
    cloud.positions = std::move(result.input_positions);
    if (result.report.duplicates_merged > 0)
      printer.note("detexture: note: " + std::to_string(result.report.duplicates_merged) +
                   " points lie exactly on an earlier point; the method ran on the distinct "
                   "positions and each copy got the result of the first");

    const auto t1 = std::chrono::steady_clock::now();
    const PointCloud out = detextured_cloud(cloud, result, texture_fields);
    try {
      write_point_cloud(output, out, write_options);
      if (!texture_layer.empty())
        write_point_cloud(texture_layer, detexture::texture_layer(cloud, result), write_options);
    } catch (const std::bad_alloc&) {
      throw;
    } catch (const std::exception& e) {
      throw OutputError(e.what());
    }
    for (const auto& notice : write_notices) printer.note("detexture: note: " + notice);
    const double write_s =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - t1).count();

    struct rusage usage {};
    getrusage(RUSAGE_SELF, &usage);
    const double peak_mib = usage.ru_maxrss / 1024.0;  // ru_maxrss is in KiB on Linux
    if (!stats_path.empty()) try {
        write_stats(stats_path, cloud.size(), result.report, read_s, write_s, peak_mib, tiles);
      } catch (const std::runtime_error& e) {
        throw OutputError(e.what());
      }
    if (!quiet) {
      const auto& r = result.report;
      double total = read_s + write_s;
      for (const auto& t : r.timings) total += t.seconds;
      std::fprintf(stderr,
                   "wrote %s\n"
                   "summary: %zu points, bounding-box diagonal d = %g\n"
                   "  %s\n"
                   "  r = %g, λ = %g, σs = %g, σr = %g°, δ = %g, σp = %g\n"
                   "  neighbors per point: mean %.1f, min %zu, max %zu\n"
                   "  texture points (Eq. 2): %zu (%.1f%%); RANSAC tries per point %.1f\n"
                   "  rolling iterations: %d; position update: %d iterations, mean move %g\n",
                   output.c_str(), cloud.size(), r.diagonal, scale_line(r).c_str(), r.radius,
                   r.lambda, r.sigma_s, params.rolling.sigma_r_deg, params.texture.delta, r.sigma_p,
                   r.neighbors.mean, r.neighbors.min, r.neighbors.max, r.texture_points,
                   100.0 * r.texture_points / cloud.size(), r.ransac_mean_iterations,
                   r.rolling_iterations, r.update_iterations, r.mean_displacement);
      if (r.mesh) {
        const auto& f = r.folds;
        auto share = [](std::size_t k, std::size_t of) { return of ? 100.0 * k / of : 0.0; };
        std::fprintf(stderr,
                     "  mesh: %zu triangles%s; edges folded past %g°: input %zu (%.2f%%), "
                     "output %zu (%.2f%%); flipped triangles: %zu (%.2f%%); 99th-percentile "
                     "dihedral angle %.1f° -> %.1f°",
                     r.triangles, r.normals_from_faces ? ", normals from the faces" : "",
                     params.folds.fold_angle_deg, f.input.folded,
                     share(f.input.folded, f.input.edges), f.output.folded,
                     share(f.output.folded, f.output.edges), f.output.flipped,
                     share(f.output.flipped, f.output.triangles), f.input.p99_dihedral_deg,
                     f.output.p99_dihedral_deg);
        if (f.vertices_held > 0)
          std::fprintf(stderr,
                       "; %zu vertices held back (the update alone: %zu folded, %zu flipped)",
                       f.vertices_held, f.update.folded, f.update.flipped);
        std::fprintf(stderr, "\n");
      }
      if (r.moves_limited > 0)
        std::fprintf(stderr, "  moves cut to the limit %g (texture height %g): %zu points\n",
                     r.max_move, r.texture_height, r.moves_limited);
      if (r.counter_moves_limited > 0)
        std::fprintf(stderr, "  moves against the relief limited (lean %.2f): %zu points\n",
                     r.relief_lean, r.counter_moves_limited);
      if (r.tip_moves_limited > 0)
        std::fprintf(stderr, "  tips of the relief held at their neighbors: %zu points\n",
                     r.tip_moves_limited);
      if (r.sink_moves_limited > 0)
        std::fprintf(stderr, "  sinks held at their own relief's depth: %zu points\n",
                     r.sink_moves_limited);
      if (r.raised_cells_lowered > 0)
        std::fprintf(stderr,
                     "  dense raised cells (lean %.2f): %zu points lowered to the cells' feet\n",
                     r.relief_lean, r.raised_cells_lowered);
      if (r.raised_cells_limited > 0)
        std::fprintf(stderr, "  held within the depth limit %g below their inputs: %zu points\n",
                     params.raised_cells.max_depth * r.texture_height, r.raised_cells_limited);
      if (r.raised_cells_turned > 0)
        std::fprintf(stderr,
                     "  sunk along their neighbors' normal, their own turned over: %zu points\n",
                     r.raised_cells_turned);
      if (r.thin_part_points > 0)
        std::fprintf(stderr, "  neighborhoods shrunk to a thin part: %zu points (%.2f%%)\n",
                     r.thin_part_points, 100.0 * r.thin_part_points / cloud.size());
      if (r.mesh_path_points > 0)
        std::fprintf(stderr, "  neighborhoods cut to the mesh's paths: %zu points (%.2f%%)\n",
                     r.mesh_path_points, 100.0 * r.mesh_path_points / cloud.size());
      if (r.opposite_neighbors > 0)
        std::fprintf(stderr, "  neighbor pairs left out as another sheet: %zu (%.2f%%)\n",
                     r.opposite_neighbors,
                     100.0 * r.opposite_neighbors / (r.neighbors.mean * cloud.size()));
      if (r.surface_split_neighbors > 0)
        std::fprintf(stderr, "  neighbor pairs left out as another surface: %zu (%.2f%%)\n",
                     r.surface_split_neighbors,
                     100.0 * r.surface_split_neighbors / (r.neighbors.mean * cloud.size()));
      if (!texture_layer.empty())
        std::fprintf(stderr, "  texture layer: %s\n", texture_layer.c_str());
      std::fprintf(stderr, "  time: read %.2f s", read_s);
      for (const auto& t : r.timings)
        std::fprintf(stderr, ", %s %.2f s", t.stage.c_str(), t.seconds);
      std::fprintf(stderr, ", write %.2f s; total %.2f s on %d threads; peak memory %.0f MiB\n",
                   write_s, total, omp_get_max_threads(), peak_mib);
    }
    return kExitOk;
  } catch (const InputError& e) {
    std::fprintf(stderr, "detexture: error: %s\n", e.what());
    return kExitInput;
  } catch (const OutputError& e) {
    std::fprintf(stderr, "detexture: error: %s\n", e.what());
    return kExitOutput;
  } catch (const std::invalid_argument& e) {
    std::fprintf(stderr, "detexture: error: %s\n", e.what());
    return kExitUsage;
  } catch (const ResourceLimitError& e) {
    std::fprintf(stderr, "detexture: error: %s\n", e.what());
    return kExitResource;
  } catch (const std::bad_alloc&) {
    std::fprintf(stderr,
                 "detexture: error: out of memory; use a smaller --radius or --max-neighbors, "
                 "fewer --threads, or a machine with more memory\n");
    return kExitResource;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "detexture: error: %s\n", e.what());
    return kExitFailure;
  }
}

}  // namespace detexture::app
