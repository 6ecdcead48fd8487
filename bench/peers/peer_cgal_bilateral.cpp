// peer_cgal_bilateral: CGAL's edge-aware bilateral smoothing of a point set
// (CGAL::bilateral_smooth_point_set, Huang et al., "Edge-Aware Point Set
// Resampling", ToG 2013), as a peer for detexture's benchmarks.
//
// Reads a PLY with normals, runs `iterations` passes, writes the cloud with the
// smoothed positions and normals (every other property carried through), and
// prints `seconds: <wall time of the passes>` as the last line of stdout.
//
// Neighbourhoods (CGAL 5.5, bilateral_smooth_point_set.h):
//  * --neighbors K alone: the K nearest neighbours of each point.
//  * --radius R: the points within R, at most K of them (K is a cap; when the
//    cap is hit, CGAL keeps the first K found by the tree, not the nearest K).
//  In both modes CGAL sets the Gaussian spatial bandwidth itself, to 0.95 times
//  the largest K-nearest-neighbour distance over the whole cloud, and drops
//  neighbours beyond that distance. So K also controls the amount of smoothing
//  in --radius mode, and a radius larger than that bandwidth has no effect.
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/bilateral_smooth_point_set.h>
#include <CGAL/property_map.h>
#include <CGAL/tags.h>

#include <CLI/CLI.hpp>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <exception>
#include <filesystem>
#include <string>
#include <thread>
#include <utility>
#include <vector>

#ifdef CGAL_LINKED_WITH_TBB
#include <tbb/global_control.h>
#endif

#include "detexture/io/read_point_cloud.h"
#include "detexture/io/write_point_cloud.h"
#include "detexture/types.h"

namespace {

using Kernel = CGAL::Exact_predicates_inexact_constructions_kernel;
using Point = Kernel::Point_3;
using Vector = Kernel::Vector_3;
using PointWithNormal = std::pair<Point, Vector>;

struct Params {
  std::string input;
  std::string output;
  unsigned int neighbors = 120;   ///< K: neighbourhood size (CGAL's example value)
  std::string radius = "0";       ///< neighbourhood radius R: model units or "0.02d"; 0 = K nearest
  double sharpness_angle = 30.0;  ///< degrees in (0, 90); CGAL's default
  int iterations = 3;             ///< passes (CGAL's example value)
  int threads = 0;                ///< 0 = all hardware threads
};

const char* kProgram = "peer_cgal_bilateral";

/// A length as given on the command line: "0.5" in model units or "0.02d", a
/// fraction of the bounding-box diagonal d (detexture's own syntax).
struct LengthArg {
  double value = 0.0;
  bool relative = false;
  double resolve(double diagonal) const { return relative ? value * diagonal : value; }
};

LengthArg parse_length_arg(const std::string& text, const std::string& option) {
  LengthArg length;
  std::string number = text;
  if (!number.empty() && (number.back() == 'd' || number.back() == 'D')) {
    length.relative = true;
    number.pop_back();
  }
  std::size_t used = 0;
  try {
    length.value = std::stod(number, &used);
  } catch (const std::exception&) {
    used = 0;
  }
  if (number.empty() || used != number.size() || !std::isfinite(length.value) || length.value < 0.0)
    throw CLI::ValidationError(
        option,
        "expected a length >= 0 in model units (0.5) or as a fraction of the "
        "bounding-box diagonal (0.02d), got '" +
            text + "'");
  return length;
}

/// Refuse output == input before any work (the writer refuses too, but only
/// after the algorithm has run).
void check_output_is_not_input(const std::string& input, const std::string& output) {
  std::error_code error;
  if (std::filesystem::exists(output, error) && std::filesystem::equivalent(input, output, error))
    throw std::runtime_error("output '" + output +
                             "' is the input file; choose another output path.");
}

}  // namespace

int main(int argc, char** argv) {
  Params params;
  CLI::App app{
      "CGAL 5.5 bilateral_smooth_point_set (edge-aware, Huang et al. 2013) as a detexture peer.\n"
      "Reads a PLY with normals, writes the smoothed points and normals; the last line of\n"
      "stdout is `seconds: <time of the smoothing passes, without I/O>`.",
      kProgram};
  app.add_option("input", params.input, "Input PLY with normals")
      ->required()
      ->check(CLI::ExistingFile);
  app.add_option("output", params.output, "Output PLY (binary little endian)")->required();
  app.add_option(
         "-k,--neighbors", params.neighbors,
         "Neighbourhood size K (>= 2). Also sets CGAL's spatial bandwidth: 0.95 x the largest "
         "K-nearest-neighbour distance in the cloud. With --radius, caps the points kept per "
         "sphere")
      ->capture_default_str()
      ->check(CLI::Range(2u, 100000u));
  app.add_option(
         "-r,--radius", params.radius,
         "Spherical neighbourhood radius (CGAL's neighbor_radius), in model units or as a fraction "
         "of the bounding-box diagonal (0.02d, detexture's default radius); 0 = K nearest")
      ->capture_default_str();
  app.add_option("-s,--sharpness-angle", params.sharpness_angle,
                 "Sharpness angle in degrees, in (0, 90); larger is smoother")
      ->capture_default_str()
      ->check(CLI::Range(1e-6, 90.0 - 1e-6));
  app.add_option("-i,--iterations", params.iterations, "Number of smoothing passes (>= 1)")
      ->capture_default_str()
      ->check(CLI::PositiveNumber);
  app.add_option("-t,--threads", params.threads, "Worker threads (TBB); 0 = all hardware threads")
      ->capture_default_str()
      ->check(CLI::NonNegativeNumber);

  LengthArg radius_arg;
  try {
    app.parse(argc, argv);
    radius_arg = parse_length_arg(params.radius, "--radius");
  } catch (const CLI::CallForHelp& e) {
    return app.exit(e);
  } catch (const CLI::ParseError& e) {
    std::fprintf(stderr, "%s: error: %s (run with --help for usage)\n", kProgram, e.what());
    return 2;
  }

  try {
    check_output_is_not_input(params.input, params.output);
    detexture::PointCloud cloud = detexture::read_point_cloud(params.input);
    if (!cloud.has_normals())
      throw std::runtime_error(
          "input '" + params.input +
          "' has no normals (nx, ny, nz); bilateral smoothing needs oriented normals.");
    const std::size_t n = cloud.size();
    std::size_t zero_normals = 0;
    for (std::size_t i = 0; i < n; ++i)
      if (cloud.normals.row(static_cast<Eigen::Index>(i)).squaredNorm() == 0.0) ++zero_normals;
    if (zero_normals > 0)
      throw std::runtime_error(
          "input '" + params.input + "' has " + std::to_string(zero_normals) +
          " zero-length normals; bilateral smoothing needs a unit normal at every point.");
    if (n < 3) throw std::runtime_error("input '" + params.input + "' has fewer than 3 points.");

    std::vector<PointWithNormal> points(n);
    for (std::size_t i = 0; i < n; ++i) {
      const auto p = cloud.positions.row(static_cast<Eigen::Index>(i));
      const auto q = cloud.normals.row(static_cast<Eigen::Index>(i));
      points[i] = {Point(p(0), p(1), p(2)), Vector(q(0), q(1), q(2))};
    }

    const int hardware = static_cast<int>(std::thread::hardware_concurrency());
    const int threads = params.threads > 0 ? params.threads : (hardware > 0 ? hardware : 1);
#ifdef CGAL_LINKED_WITH_TBB
    tbb::global_control thread_limit(tbb::global_control::max_allowed_parallelism,
                                     static_cast<std::size_t>(threads));
    std::printf("parallel: TBB, %d threads\n", threads);
#else
    std::printf("parallel: no (built without TBB), 1 thread\n");
#endif
    const double radius = radius_arg.resolve(detexture::bounding_box_diagonal(cloud.positions));
    std::printf("points: %zu\n", n);
    std::printf("neighbourhood: %s\n",
                radius > 0.0 ? ("radius " + std::to_string(radius) + ", at most " +
                                std::to_string(params.neighbors) + " points")
                                   .c_str()
                             : (std::to_string(params.neighbors) + " nearest").c_str());
    std::fflush(stdout);

    const auto start = std::chrono::steady_clock::now();
    for (int it = 0; it < params.iterations; ++it) {
      const double mean_sq_move = CGAL::bilateral_smooth_point_set<CGAL::Parallel_if_available_tag>(
          points, params.neighbors,
          CGAL::parameters::point_map(CGAL::First_of_pair_property_map<PointWithNormal>())
              .normal_map(CGAL::Second_of_pair_property_map<PointWithNormal>())
              .sharpness_angle(params.sharpness_angle)
              .neighbor_radius(radius));
      if (!std::isfinite(mean_sq_move))
        throw std::runtime_error(
            "CGAL's bilateral smoothing returned a non-finite result in pass " +
            std::to_string(it + 1) + " (a point with no neighbour within the bandwidth?).");
      std::printf("iteration %d: mean squared point movement %.9g\n", it + 1, mean_sq_move);
    }
    const double seconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();

    for (std::size_t i = 0; i < n; ++i) {
      const Point& p = points[i].first;
      const Vector& q = points[i].second;
      cloud.positions.row(static_cast<Eigen::Index>(i)) << p.x(), p.y(), p.z();
      cloud.normals.row(static_cast<Eigen::Index>(i)) << q.x(), q.y(), q.z();
    }
    detexture::WriteOptions options;
    options.format = detexture::FileFormat::Ply;
    options.protect_path = params.input;
    detexture::write_point_cloud(params.output, cloud, options);

    std::printf("seconds: %.6f\n", seconds);
    return 0;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "%s: error: %s\n", kProgram, e.what());
    return 1;
  }
}
