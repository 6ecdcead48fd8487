// peer_pcl_mls: PCL's moving least squares smoothing
// (pcl::MovingLeastSquares<PointNormal, PointNormal>, Alexa et al. 2003 with a
// local polynomial fit), as a peer for detexture's benchmarks.
//
// Reads a PLY (normals optional), projects every point onto the MLS surface of
// its radius neighbourhood, computes MLS normals and flips each to agree with
// the input normal of the point it came from (with NONE upsampling every
// output point comes from exactly one input point, so that input point is also
// its nearest input point). Writes the cloud in input order (every other
// property carried through) and prints `seconds: <wall time of MLS + normal
// orientation>` last.
//
// PCL drops points with fewer than 3 neighbours within the radius; those keep
// their input position and normal here, and their count is reported.
#include <pcl/point_cloud.h>
#include <pcl/point_types.h>
#include <pcl/search/kdtree.h>
#include <pcl/surface/mls.h>

#include <CLI/CLI.hpp>
#include <cstdint>
#include <cstdio>
#include <stdexcept>
#include <string>
#include <vector>

#include "detexture/types.h"
#include "peer_common.h"

namespace {

using PclPoint = pcl::PointNormal;
using Mls = pcl::MovingLeastSquares<PclPoint, PclPoint>;

struct Params {
  std::string input;
  std::string output;
  std::string radius;                 ///< search radius: model units or "0.02d" (required, > 0)
  int order = 2;                      ///< polynomial order; PCL's default (0 or 1 = plane fit only)
  std::string projection = "simple";  ///< PCL's default projection method
  double sqr_gauss_param =
      0.0;          ///< squared Gaussian bandwidth of the weights; 0 = radius², PCL's default
  int threads = 0;  ///< 0 = all hardware threads
};

const char* kProgram = "peer_pcl_mls";

namespace peers = detexture::peers;

}  // namespace

int main(int argc, char** argv) {
  Params params;
  CLI::App app{
      "PCL 1.13 MovingLeastSquares<PointNormal, PointNormal> as a detexture peer.\n"
      "Reads a PLY, writes the MLS-projected points with MLS normals (oriented to agree with\n"
      "the input normals when there are any); the last line of stdout is\n"
      "`seconds: <time of MLS + normal orientation, without I/O>`.",
      kProgram};
  peers::add_input_output_options(app, params.input, params.output,
                                  "Input PLY (normals optional, used only for orientation)");
  app.add_option(
         "-r,--radius", params.radius,
         "Search radius (> 0), in model units or as a fraction of the bounding-box diagonal "
         "(0.02d, detexture's default radius); no default")
      ->required();
  app.add_option("-o,--order", params.order,
                 "Polynomial order of the local fit (0 to 5; 0 or 1 = tangent plane only)")
      ->capture_default_str()
      ->check(CLI::Range(0, 5));
  app.add_option("-p,--projection", params.projection,
                 "Projection onto the fitted surface: simple (along the plane normal), orthogonal "
                 "(closest point on the polynomial), none (onto the plane)")
      ->capture_default_str()
      ->check(CLI::IsMember({"simple", "orthogonal", "none"}));
  app.add_option("--sqr-gauss-param", params.sqr_gauss_param,
                 "Squared Gaussian bandwidth of the fit weights (model units²); 0 = radius² (PCL's "
                 "default)")
      ->capture_default_str()
      ->check(CLI::NonNegativeNumber);
  app.add_option("-t,--threads", params.threads,
                 "Worker threads (OpenMP); 0 = all hardware threads")
      ->capture_default_str()
      ->check(CLI::NonNegativeNumber);

  detexture::Length radius_arg;
  if (const auto stop = peers::parse_command_line(app, argc, argv, kProgram, [&] {
        radius_arg = peers::parse_length_option(params.radius, "--radius", false);
      }))
    return *stop;

  return peers::run_reporting_errors(kProgram, [&] {
    detexture::PointCloud cloud = peers::read_input(params.input, params.output);
    const std::size_t n = cloud.size();
    const bool orient = cloud.has_normals();

    pcl::PointCloud<PclPoint>::Ptr input(new pcl::PointCloud<PclPoint>);
    input->resize(n);
    for (std::size_t i = 0; i < n; ++i) {
      const auto p = cloud.positions.row(static_cast<Eigen::Index>(i));
      PclPoint& q = (*input)[i];
      q.x = static_cast<float>(p(0));
      q.y = static_cast<float>(p(1));
      q.z = static_cast<float>(p(2));
      if (orient) {
        const auto m = cloud.normals.row(static_cast<Eigen::Index>(i));
        q.normal_x = static_cast<float>(m(0));
        q.normal_y = static_cast<float>(m(1));
        q.normal_z = static_cast<float>(m(2));
      } else {
        q.normal_x = q.normal_y = q.normal_z = 0.0f;
      }
      q.curvature = 0.0f;
    }
    input->width = static_cast<std::uint32_t>(n);
    input->height = 1;
    input->is_dense = true;

    const int threads = peers::thread_count(params.threads);
    std::printf("parallel: OpenMP, %d threads\n", threads);
    const double radius = peers::resolve_length(radius_arg, cloud.positions);
    if (!(radius > 0.0))
      throw std::runtime_error("input '" + params.input +
                               "' has a zero bounding-box diagonal; give --radius in model units.");
    std::printf("points: %zu\n", n);
    std::printf("neighbourhood: radius %s\n", std::to_string(radius).c_str());
    std::fflush(stdout);

    pcl::PointCloud<PclPoint> result;
    std::vector<int> source_of(n, -1);  // output row of each input point, -1 = dropped by PCL
    std::size_t flipped = 0;
    const peers::Stopwatch stopwatch;
    {
      Mls mls;
      mls.setInputCloud(input);
      mls.setSearchMethod(
          pcl::search::KdTree<PclPoint>::Ptr(new pcl::search::KdTree<PclPoint>(false)));
      mls.setSearchRadius(radius);
      if (params.sqr_gauss_param > 0.0) mls.setSqrGaussParam(params.sqr_gauss_param);
      mls.setPolynomialOrder(params.order);
      mls.setComputeNormals(true);
      mls.setUpsamplingMethod(Mls::NONE);
      mls.setProjectionMethod(params.projection == "simple"       ? pcl::MLSResult::SIMPLE
                              : params.projection == "orthogonal" ? pcl::MLSResult::ORTHOGONAL
                                                                  : pcl::MLSResult::NONE);
      mls.setNumberOfThreads(static_cast<unsigned int>(threads));
      mls.process(result);
      const pcl::PointIndicesPtr corresponding = mls.getCorrespondingIndices();
      if (!corresponding || corresponding->indices.size() != result.size())
        throw std::runtime_error(
            "PCL's MLS returned " + std::to_string(result.size()) +
            " points without a source index for each; cannot keep the input order.");
      for (std::size_t j = 0; j < result.size(); ++j) {
        const int i = corresponding->indices[j];
        source_of[static_cast<std::size_t>(i)] = static_cast<int>(j);
        if (orient) {
          PclPoint& q = result[j];
          const PclPoint& p = (*input)[static_cast<std::size_t>(i)];
          if (q.normal_x * p.normal_x + q.normal_y * p.normal_y + q.normal_z * p.normal_z < 0.0f) {
            q.normal_x = -q.normal_x;
            q.normal_y = -q.normal_y;
            q.normal_z = -q.normal_z;
            ++flipped;
          }
        }
      }
    }
    const double seconds = stopwatch.seconds();

    if (!orient) cloud.normals = detexture::Normals::Zero(static_cast<Eigen::Index>(n), 3);
    std::size_t kept = 0;
    for (std::size_t i = 0; i < n; ++i) {
      if (source_of[i] < 0) {
        ++kept;  // PCL dropped it: too few neighbours; keep the input values.
        continue;
      }
      const PclPoint& q = result[static_cast<std::size_t>(source_of[i])];
      cloud.positions.row(static_cast<Eigen::Index>(i)) << q.x, q.y, q.z;
      cloud.normals.row(static_cast<Eigen::Index>(i)) << q.normal_x, q.normal_y, q.normal_z;
    }
    peers::write_output(params.output, cloud, params.input);

    std::printf("points with fewer than 3 neighbours, kept unchanged: %zu\n", kept);
    if (orient)
      std::printf("normals flipped to agree with the input: %zu\n", flipped);
    else
      std::printf("normals: input has none; MLS normals written unoriented\n");
    peers::print_seconds(seconds);
    return 0;
  });
}
