// peer_cgal_jet: CGAL's jet smoothing (each point is projected onto a local
// polynomial "jet" fitted to its neighbours, Cazals & Pouget 2005) followed by
// jet normal estimation, as a peer for detexture's benchmarks.
//
// Reads a PLY (normals optional), smooths the positions, re-estimates normals
// on the smoothed points, flips each to agree with the input normal of the same
// point (when the input has normals), writes the cloud (every other property
// carried through) and prints `seconds: <wall time of smoothing + normal
// estimation + orientation>` as the last line of stdout.
//
// Neighbourhoods:
//  * --neighbors K (default): the K nearest neighbours, through CGAL 5.5's own
//    CGAL::jet_smooth_point_set and CGAL::jet_estimate_normals.
//  * --radius R: detexture's radius neighbourhoods (the point itself first,
//    then by increasing distance, at most --max-neighbors), fitted with CGAL's
//    Monge_via_jet_fitting, i.e. the same code those two functions run per
//    point. Not CGAL's own neighbor_radius: in CGAL 5.5 a sphere query returns
//    the points in k-d tree order, and Monge_via_jet_fitting evaluates the jet
//    at the *first* point of its range, so every point is replaced by the
//    projection of some neighbour (mean displacement ~0.8 R on a noisy sphere,
//    against ~the noise level in K-nearest mode). Points with fewer neighbours
//    than the jet needs ((d+1)(d+2)/2) keep their input position and normal
//    and are counted.
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Monge_via_jet_fitting.h>
#include <CGAL/jet_estimate_normals.h>
#include <CGAL/jet_smooth_point_set.h>
#include <CGAL/property_map.h>
#include <CGAL/tags.h>

#include <CLI/CLI.hpp>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#ifdef CGAL_LINKED_WITH_TBB
#include <tbb/global_control.h>
#endif

#include "detexture/geometry/radius_neighborhoods.h"
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
  unsigned int neighbors = 24;  ///< K (CGAL's jet smoothing example value)
  std::string radius = "0";     ///< neighbourhood radius R: model units or "0.02d"; 0 = K nearest
  int max_neighbors = 0;        ///< with --radius: keep at most this many nearest; 0 = all
  unsigned int degree_fitting = 2;    ///< degree of the fitted jet; CGAL's default
  unsigned int degree_monge = 2;      ///< degree of the Monge form; CGAL's default
  unsigned int normal_neighbors = 0;  ///< K for normal estimation; 0 = same as --neighbors
  int threads = 0;                    ///< 0 = all hardware threads
};

const char* kProgram = "peer_cgal_jet";

namespace peers = detexture::peers;

/// With --radius: fit a jet at every point to its radius neighbourhood (the
/// point first, as Monge_via_jet_fitting evaluates the jet there). Smooths the
/// positions (smooth = true) or sets the normals (smooth = false). Returns the
/// number of points left as they were: too few neighbours, or a non-finite fit.
std::size_t jet_fit_radius(std::vector<PointWithNormal>& points, double radius, int max_neighbors,
                           unsigned int degree_fitting, unsigned int degree_monge, bool smooth,
                           int threads) {
  using MongeFit = CGAL::Monge_via_jet_fitting<Kernel>;
  const std::size_t n = points.size();
  detexture::Positions P(static_cast<Eigen::Index>(n), 3);
  for (std::size_t i = 0; i < n; ++i)
    P.row(static_cast<Eigen::Index>(i)) << points[i].first.x(), points[i].first.y(),
        points[i].first.z();
  detexture::RadiusNeighborhoodsParams neighborhood;
  neighborhood.radius = radius;
  neighborhood.max_neighbors = max_neighbors;
  const detexture::Neighborhoods N = detexture::radius_neighborhoods(P, neighborhood);
  const std::size_t min_points = (degree_fitting + 1) * (degree_fitting + 2) / 2;

  std::vector<PointWithNormal> result = points;
  std::size_t unchanged = 0;
#pragma omp parallel for schedule(dynamic, 256) num_threads(threads) reduction(+ : unchanged)
  for (std::int64_t ii = 0; ii < static_cast<std::int64_t>(n); ++ii) {
    const std::size_t i = static_cast<std::size_t>(ii);
    if (N.count(i) < min_points) {
      ++unchanged;
      continue;
    }
    std::vector<Point> local;
    local.reserve(N.count(i));
    for (const std::uint32_t* j = N.begin(i); j != N.end(i); ++j) local.push_back(points[*j].first);
    MongeFit fit;
    const MongeFit::Monge_form form =
        fit(local.begin(), local.end(), degree_fitting, smooth ? degree_monge : 1);
    if (smooth) {
      const Point q = form.origin();
      if (std::isfinite(q.x()) && std::isfinite(q.y()) && std::isfinite(q.z()))
        result[i].first = q;
      else
        ++unchanged;
    } else {
      const Vector m = form.normal_direction();
      if (std::isfinite(m.x()) && std::isfinite(m.y()) && std::isfinite(m.z()))
        result[i].second = m;
      else
        ++unchanged;
    }
  }
  points.swap(result);
  return unchanged;
}

}  // namespace

int main(int argc, char** argv) {
  Params params;
  CLI::App app{
      "CGAL 5.5 jet smoothing + jet normal estimation as a detexture peer.\n"
      "Reads a PLY, writes the smoothed points with re-estimated normals (oriented to agree\n"
      "with the input normals when there are any); the last line of stdout is\n"
      "`seconds: <time of smoothing + normal estimation + orientation, without I/O>`.",
      kProgram};
  peers::add_input_output_options(app, params.input, params.output,
                                  "Input PLY (normals optional, used only for orientation)");
  app.add_option(
         "-k,--neighbors", params.neighbors,
         "Neighbourhood size K (>= 2) for CGAL::jet_smooth_point_set; ignored with --radius")
      ->capture_default_str();
  app.add_option("-r,--radius", params.radius,
                 "Radius neighbourhoods instead of K nearest (detexture's, fitted with CGAL's "
                 "Monge_via_jet_fitting), in model units or as a fraction of the bounding-box "
                 "diagonal (0.02d, detexture's default radius); 0 = K nearest")
      ->capture_default_str();
  app.add_option("--max-neighbors", params.max_neighbors,
                 "With --radius: keep at most this many nearest neighbours; 0 = all")
      ->capture_default_str()
      ->check(CLI::NonNegativeNumber);
  app.add_option("-d,--degree", params.degree_fitting, "Degree of the fitted jet (1 to 4)")
      ->capture_default_str()
      ->check(CLI::Range(1u, 4u));
  app.add_option("--degree-monge", params.degree_monge,
                 "Degree of the Monge form (1 to 4, <= --degree)")
      ->capture_default_str()
      ->check(CLI::Range(1u, 4u));
  app.add_option("--normal-neighbors", params.normal_neighbors,
                 "K for CGAL::jet_estimate_normals; 0 = same as --neighbors; ignored with --radius")
      ->capture_default_str();
  app.add_option(
         "-t,--threads", params.threads,
         "Worker threads (TBB for K nearest, OpenMP for --radius); 0 = all hardware threads")
      ->capture_default_str()
      ->check(CLI::NonNegativeNumber);

  detexture::Length radius_arg;
  unsigned int normal_k = 0;
  if (const auto stop = peers::parse_command_line(app, argc, argv, kProgram, [&] {
        radius_arg = peers::parse_length_option(params.radius, "--radius", true);
        if (params.degree_monge > params.degree_fitting)
          throw CLI::ValidationError(
              "--degree-monge",
              "must not exceed --degree (" + std::to_string(params.degree_fitting) + ")");
        normal_k = params.normal_neighbors > 0 ? params.normal_neighbors : params.neighbors;
        if (radius_arg.value == 0.0 && (params.neighbors < 2 || normal_k < 2))
          throw CLI::ValidationError("--neighbors", "must be at least 2 without --radius");
      }))
    return *stop;

  return peers::run_reporting_errors(kProgram, [&] {
    detexture::PointCloud cloud = peers::read_input(params.input, params.output);
    const std::size_t n = cloud.size();
    // A degree-d jet needs (d+1)(d+2)/2 points: 6 for degree 2. Refuse clouds
    // too small for any fit rather than let CGAL divide by zero.
    const std::size_t min_points = (params.degree_fitting + 1) * (params.degree_fitting + 2) / 2;
    if (n < min_points)
      throw std::runtime_error("input '" + params.input + "' has " + std::to_string(n) +
                               " points; a degree-" + std::to_string(params.degree_fitting) +
                               " jet needs at least " + std::to_string(min_points) + ".");
    const bool orient = cloud.has_normals();

    std::vector<PointWithNormal> points(n);
    for (std::size_t i = 0; i < n; ++i) {
      const auto p = cloud.positions.row(static_cast<Eigen::Index>(i));
      const Vector m = orient ? Vector(cloud.normals(static_cast<Eigen::Index>(i), 0),
                                       cloud.normals(static_cast<Eigen::Index>(i), 1),
                                       cloud.normals(static_cast<Eigen::Index>(i), 2))
                              : CGAL::NULL_VECTOR;
      points[i] = {Point(p(0), p(1), p(2)), m};
    }

    const int threads = peers::thread_count(params.threads);
    const double radius = peers::resolve_length(radius_arg, cloud.positions);
#ifdef CGAL_LINKED_WITH_TBB
    tbb::global_control thread_limit(tbb::global_control::max_allowed_parallelism,
                                     static_cast<std::size_t>(threads));
#endif
    if (radius > 0.0) {
      std::printf("parallel: OpenMP, %d threads\n", threads);
      std::printf("points: %zu\n", n);
      std::printf("neighbourhood: radius %s, %s (detexture's radius_neighborhoods)\n",
                  std::to_string(radius).c_str(),
                  params.max_neighbors > 0
                      ? ("at most " + std::to_string(params.max_neighbors) + " nearest").c_str()
                      : "no cap");
    } else {
#ifdef CGAL_LINKED_WITH_TBB
      std::printf("parallel: TBB, %d threads\n", threads);
#else
      std::printf("parallel: no (built without TBB), 1 thread\n");
#endif
      std::printf("points: %zu\n", n);
      std::printf("neighbourhood: %u nearest (normals: %u nearest)\n", params.neighbors, normal_k);
    }
    std::fflush(stdout);

    const auto point_map = CGAL::First_of_pair_property_map<PointWithNormal>();
    const auto normal_map = CGAL::Second_of_pair_property_map<PointWithNormal>();
    std::size_t unsmoothed = 0, unestimated = 0;
    const peers::Stopwatch stopwatch;
    if (radius > 0.0) {
      unsmoothed = jet_fit_radius(points, radius, params.max_neighbors, params.degree_fitting,
                                  params.degree_monge, true, threads);
      unestimated = jet_fit_radius(points, radius, params.max_neighbors, params.degree_fitting,
                                   params.degree_monge, false, threads);
    } else {
      CGAL::jet_smooth_point_set<CGAL::Parallel_if_available_tag>(
          points, params.neighbors,
          CGAL::parameters::point_map(point_map)
              .degree_fitting(params.degree_fitting)
              .degree_monge(params.degree_monge));
      CGAL::jet_estimate_normals<CGAL::Parallel_if_available_tag>(
          points, normal_k,
          CGAL::parameters::point_map(point_map)
              .normal_map(normal_map)
              .degree_fitting(params.degree_fitting));
    }
    std::size_t flipped = 0;
    if (orient) {
      for (std::size_t i = 0; i < n; ++i) {
        const auto q = cloud.normals.row(static_cast<Eigen::Index>(i));
        Vector& m = points[i].second;
        if (m.x() * q(0) + m.y() * q(1) + m.z() * q(2) < 0.0) {
          m = -m;
          ++flipped;
        }
      }
    }
    const double seconds = stopwatch.seconds();

    if (!orient) cloud.normals.resize(static_cast<Eigen::Index>(n), 3);
    for (std::size_t i = 0; i < n; ++i) {
      const Point& p = points[i].first;
      const Vector& q = points[i].second;
      cloud.positions.row(static_cast<Eigen::Index>(i)) << p.x(), p.y(), p.z();
      cloud.normals.row(static_cast<Eigen::Index>(i)) << q.x(), q.y(), q.z();
    }
    peers::write_output(params.output, cloud, params.input);

    if (radius > 0.0) {
      std::printf("points kept at their input position (too few neighbours or no fit): %zu\n",
                  unsmoothed);
      std::printf("normals kept from the input (too few neighbours or no fit): %zu\n", unestimated);
    }
    if (orient)
      std::printf("normals flipped to agree with the input: %zu\n", flipped);
    else
      std::printf("normals: input has none; jet normals written unoriented\n");
    peers::print_seconds(seconds);
    return 0;
  });
}
