// peer_cgal_wlop: CGAL's weighted locally optimal projection (WLOP, Huang et
// al., "Consolidation of unorganized point clouds for surface reconstruction",
// SIGGRAPH Asia 2009), as a peer for detexture's benchmarks.
//
// CGAL::wlop_simplify_and_regularize_point_set moves a set of samples, taken
// from the input, towards the input's local L1 median while a repulsion term
// spreads them evenly; with select_percentage 100 every input point is one
// sample, so the output has as many points as the input. WLOP gives positions
// only; normals are then estimated on the output with
// CGAL::jet_estimate_normals (K nearest output points) and each is flipped to
// agree with the normal of the nearest *input* point (the sample may have
// moved away from the point it started at, so its nearest input point is the
// better witness of which side is out).
//
// CGAL shuffles the points it is given (a fixed boost::rand48 seed, so the
// output is deterministic); the samples are tracked by index and written back
// in input order, each with the other properties of the point it started as.
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/jet_estimate_normals.h>
#include <CGAL/property_map.h>
#include <CGAL/tags.h>
#include <CGAL/wlop_simplify_and_regularize_point_set.h>

#include <CLI/CLI.hpp>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <iterator>
#include <stdexcept>
#include <string>
#include <tuple>
#include <vector>

#ifdef CGAL_LINKED_WITH_TBB
#include <tbb/global_control.h>
#endif

#include "detexture/geometry/point_index.h"
#include "detexture/types.h"
#include "peer_common.h"

namespace {

using Kernel = CGAL::Exact_predicates_inexact_constructions_kernel;
using Point = Kernel::Point_3;
using Vector = Kernel::Vector_3;
using IndexedPoint = std::pair<Point, std::size_t>;
using PointWithNormal = std::pair<Point, Vector>;

struct Params {
  std::string input;
  std::string output;
  std::string radius = "0";            ///< WLOP's neighbor_radius; 0 = CGAL's 8 x average spacing
  unsigned int iterations = 35;        ///< WLOP iterations; CGAL's default
  bool uniform = false;                ///< require_uniform_sampling; CGAL's default
  unsigned int normal_neighbors = 24;  ///< K for jet_estimate_normals (CGAL's example value)
  int threads = 0;                     ///< 0 = all hardware threads
};

const char* kProgram = "peer_cgal_wlop";
namespace peers = detexture::peers;

}  // namespace

int main(int argc, char** argv) {
  Params params;
  CLI::App app{
      "CGAL 5.5 WLOP (wlop_simplify_and_regularize_point_set, every point kept) + jet normals\n"
      "as a detexture peer. Reads a PLY with normals, writes the moved points in input order\n"
      "with jet normals oriented like the nearest input point's normal; the last line of\n"
      "stdout is `seconds: <time of WLOP + normal estimation + orientation, without I/O>`.",
      kProgram};
  peers::add_input_output_options(app, params.input, params.output,
                                  "Input PLY with normals (used only for orientation)");
  app.add_option("-r,--radius", params.radius,
                 "WLOP's neighbor_radius, in model units or as a fraction of the bounding-box "
                 "diagonal (0.02d); 0 = CGAL's default, 8 x the average spacing")
      ->capture_default_str();
  app.add_option("-i,--iterations", params.iterations, "WLOP iterations (>= 1)")
      ->capture_default_str()
      ->check(CLI::PositiveNumber);
  app.add_flag("--uniform", params.uniform,
               "CGAL's require_uniform_sampling: weight the input by its local density");
  app.add_option("-k,--normal-neighbors", params.normal_neighbors,
                 "K nearest output points for CGAL::jet_estimate_normals (>= 6)")
      ->capture_default_str()
      ->check(CLI::Range(6u, 100000u));
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
    const std::size_t n = cloud.size();
    if (!cloud.has_normals())
      throw std::runtime_error("input '" + params.input +
                               "' has no normals (nx, ny, nz); they are needed to orient the "
                               "normals estimated on WLOP's output.");
    if (n <= params.normal_neighbors)
      throw std::runtime_error("input '" + params.input + "' has " + std::to_string(n) +
                               " points; normal estimation needs more than --normal-neighbors (" +
                               std::to_string(params.normal_neighbors) + ").");
    const int threads = peers::thread_count(params.threads);
    const double radius = peers::resolve_length(radius_arg, cloud.positions);
#ifdef CGAL_LINKED_WITH_TBB
    tbb::global_control thread_limit(tbb::global_control::max_allowed_parallelism,
                                     static_cast<std::size_t>(threads));
    std::printf("parallel: TBB, %d threads\n", threads);
#else
    std::printf("parallel: no (built without TBB), 1 thread\n");
#endif
    std::printf("points: %zu\n", n);
    std::printf("neighbor radius: %s\n",
                radius > 0.0 ? std::to_string(radius).c_str() : "CGAL's default (8 x average spacing)");
    std::printf("iterations: %u%s\n", params.iterations, params.uniform ? ", uniform sampling" : "");
    std::printf("normals: jet, %u nearest output points\n", params.normal_neighbors);
    std::fflush(stdout);

    std::vector<IndexedPoint> points(n);
    for (std::size_t i = 0; i < n; ++i) {
      const auto p = cloud.positions.row(static_cast<Eigen::Index>(i));
      points[i] = {Point(p(0), p(1), p(2)), i};
    }
    std::vector<Point> moved;
    moved.reserve(n);

    const peers::Stopwatch stopwatch;
    auto np = CGAL::parameters::point_map(CGAL::First_of_pair_property_map<IndexedPoint>())
                  .select_percentage(100.0)
                  .number_of_iterations(params.iterations)
                  .require_uniform_sampling(params.uniform);
    if (radius > 0.0)
      CGAL::wlop_simplify_and_regularize_point_set<CGAL::Parallel_if_available_tag>(
          points, std::back_inserter(moved), np.neighbor_radius(radius));
    else
      CGAL::wlop_simplify_and_regularize_point_set<CGAL::Parallel_if_available_tag>(
          points, std::back_inserter(moved), np);
    // With 100%, sample k is the point CGAL shuffled to position k.
    if (moved.size() != n)
      throw std::runtime_error("WLOP returned " + std::to_string(moved.size()) + " points for " +
                               std::to_string(n) + " input points.");

    std::vector<PointWithNormal> out(n);
    for (std::size_t k = 0; k < n; ++k) out[points[k].second] = {moved[k], CGAL::NULL_VECTOR};
    CGAL::jet_estimate_normals<CGAL::Parallel_if_available_tag>(
        out, params.normal_neighbors,
        CGAL::parameters::point_map(CGAL::First_of_pair_property_map<PointWithNormal>())
            .normal_map(CGAL::Second_of_pair_property_map<PointWithNormal>()));

    const detexture::PointIndex input_index(cloud.positions);
    std::size_t flipped = 0;
    double moved_sum = 0.0;
    for (std::size_t i = 0; i < n; ++i) {
      const Point& p = out[i].first;
      const double q[3] = {p.x(), p.y(), p.z()};
      double distance_sq = 0.0;
      const std::uint32_t j = input_index.nearest(q, &distance_sq);
      const auto m = cloud.normals.row(static_cast<Eigen::Index>(j));
      Vector& normal = out[i].second;
      if (normal.x() * m(0) + normal.y() * m(1) + normal.z() * m(2) < 0.0) {
        normal = -normal;
        ++flipped;
      }
      const auto p0 = cloud.positions.row(static_cast<Eigen::Index>(i));
      moved_sum += std::sqrt(CGAL::squared_distance(p, Point(p0(0), p0(1), p0(2))));
    }
    const double seconds = stopwatch.seconds();

    for (std::size_t i = 0; i < n; ++i) {
      const Point& p = out[i].first;
      const Vector& m = out[i].second;
      cloud.positions.row(static_cast<Eigen::Index>(i)) << p.x(), p.y(), p.z();
      cloud.normals.row(static_cast<Eigen::Index>(i)) << m.x(), m.y(), m.z();
    }
    peers::write_output(params.output, cloud, params.input);
    std::printf("mean distance from each point to where it started: %.6g\n",
                moved_sum / static_cast<double>(n));
    std::printf("normals flipped to agree with the nearest input point: %zu\n", flipped);
    peers::print_seconds(seconds);
    return 0;
  });
}
