// detexture compare RESULT GROUND_TRUTH: how far a result is from the
// surface it should recover (the paper's Table 3, and more).
#include <CLI/CLI.hpp>
#include <cstdio>
#include <exception>
#include <string>

#include "commands.h"
#include "detexture/eval/compare_to_ground_truth.h"
#include "detexture/io/read_point_cloud.h"

namespace detexture::app {

int run_compare(int argc, char** argv) {
  std::string result_path, truth_path;
  bool json = false;

  CLI::App app{
      "Measure a result cloud against a ground-truth sample of the surface it should recover:\n"
      "point-to-plane distances at the nearest ground-truth point (Dmax, Dmean, sigma as in\n"
      "the paper's Table 3; signed mean and std), normal angle errors and coverage.\n"
      "See docs/synth_and_compare.md.",
      "detexture compare"};
  app.add_option("RESULT", result_path, "Result point cloud (.ply, .xyz, ...); normals optional")
      ->required();
  app.add_option("GROUND_TRUTH", truth_path,
                 "Ground-truth point cloud with normals, e.g. the .gt.ply of 'detexture synth'")
      ->required();
  app.add_flag("--json", json, "Print a JSON object with stable keys instead of a table");

  try {
    app.parse(argc, argv);
  } catch (const CLI::Success& e) {
    return app.exit(e);
  } catch (const CLI::ParseError& e) {
    std::fprintf(stderr, "detexture compare: %s (see --help)\n", e.what());
    return kExitUsage;
  }

  PointCloud result, truth;
  try {
    result = read_point_cloud(result_path);
    truth = read_point_cloud(truth_path);
    if (!truth.has_normals())
      throw std::runtime_error(truth_path +
                               " has no normals; point-to-plane distances need ground-truth "
                               "normals (nx, ny, nz)");
  } catch (const std::exception& e) {
    std::fprintf(stderr, "detexture compare: %s\n", e.what());
    return kExitInput;
  }

  try {
    const Normals none;
    const GroundTruthComparison c =
        compare_to_ground_truth(result.positions, result.has_normals() ? result.normals : none,
                                truth.positions, truth.normals);
    const std::string text = json ? comparison_to_json(c) : comparison_to_table(c);
    std::fputs(text.c_str(), stdout);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "detexture compare: %s\n", e.what());
    return kExitInput;
  }
  return kExitOk;
}

}  // namespace detexture::app
