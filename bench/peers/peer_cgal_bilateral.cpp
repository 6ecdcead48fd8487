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
#include <cmath>
#include <cstdio>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#ifdef CGAL_LINKED_WITH_TBB
#include <tbb/global_control.h>
#endif

#include "detexture/types.h"
#include "peer_common.h"

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

namespace peers = detexture::peers;

}  // namespace

int main(int argc, char** argv) {
  Params params;
  CLI::App app{
      "CGAL 5.5 bilateral_smooth_point_set (edge-aware, Huang et al. 2013) as a detexture peer.\n"
      "Reads a PLY with normals, writes the smoothed points and normals; the last line of\n"
      "stdout is `seconds: <time of the smoothing passes, without I/O>`.",
      kProgram};
  peers::add_input_output_options(app, params.input, params.output, "Input PLY with normals");
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

  detexture::Length radius_arg;
  if (const auto stop = peers::parse_command_line(app, argc, argv, kProgram, [&] {
        radius_arg = peers::parse_length_option(params.radius, "--radius", true);
      }))
    return *stop;

  return peers::run_reporting_errors(kProgram, [&] {
    detexture::PointCloud cloud = peers::read_input(params.input, params.output);
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

    const int threads = peers::thread_count(params.threads);
#ifdef CGAL_LINKED_WITH_TBB
    tbb::global_control thread_limit(tbb::global_control::max_allowed_parallelism,
                                     static_cast<std::size_t>(threads));
    std::printf("parallel: TBB, %d threads\n", threads);
#else
    std::printf("parallel: no (built without TBB), 1 thread\n");
#endif
    const double radius = peers::resolve_length(radius_arg, cloud.positions);
    std::printf("points: %zu\n", n);
    std::printf("neighbourhood: %s\n",
                radius > 0.0 ? ("radius " + std::to_string(radius) + ", at most " +
                                std::to_string(params.neighbors) + " points")
                                   .c_str()
                             : (std::to_string(params.neighbors) + " nearest").c_str());
    std::fflush(stdout);

    const peers::Stopwatch stopwatch;
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
    const double seconds = stopwatch.seconds();

    for (std::size_t i = 0; i < n; ++i) {
      const Point& p = points[i].first;
      const Vector& q = points[i].second;
      cloud.positions.row(static_cast<Eigen::Index>(i)) << p.x(), p.y(), p.z();
      cloud.normals.row(static_cast<Eigen::Index>(i)) << q.x(), q.y(), q.z();
    }
    peers::write_output(params.output, cloud, params.input);

    peers::print_seconds(seconds);
    return 0;
  });
}
