#include "detexture/tiling/remove_texture_out_of_core.h"

#include <unistd.h>

#include <cerrno>
#include <chrono>
#include <cstring>
#include <set>
#include <stdexcept>

#include "detexture/geometry/estimate_neighborhoods_memory.h"
#include "detexture/geometry/spatial_order.h"
#include "detexture/io/output_file.h"

namespace detexture {
namespace {

double since(std::chrono::steady_clock::time_point t) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t).count();
}

}  // namespace

double out_of_core_bytes_per_point(std::size_t record_size) {
  // Bin entry (index + record), positions and normals handed to the tile,
  // the core mask, and the core results (positions, normals, input normals,
  // height, label) with their output record.
  return 8.0 + static_cast<double>(record_size) + 48.0 + 1.0 + 4.0 + 3 * 24.0 + 9.0 +
         static_cast<double>(record_size);
}

PlyScan scan_ply(PlyVertexReader& reader, std::size_t max_sample, const std::string& path) {
  const auto start = std::chrono::steady_clock::now();
  const PlyVertexLayout& L = reader.layout();
  PlyScan scan;
  scan.points = L.count;
  if (L.count == 0) throw std::invalid_argument("the point cloud is empty");
  scan.stride =
      std::max<std::uint64_t>(1, (L.count + max_sample - 1) / std::max<std::size_t>(1, max_sample));
  scan.sample.resize(static_cast<Eigen::Index>((L.count + scan.stride - 1) / scan.stride), 3);
  if (L.has_normals()) scan.sample_normals.resize(scan.sample.rows(), 3);
  scan.bounds.lo.setConstant(std::numeric_limits<double>::infinity());
  scan.bounds.hi.setConstant(-std::numeric_limits<double>::infinity());
  reader.rewind();
  std::vector<unsigned char> block;
  std::uint64_t index = 0;
  while (const std::size_t got = reader.read(1 << 16, &block)) {
    for (std::size_t k = 0; k < got; ++k, ++index) {
      const Eigen::Vector3d p = record_position(L, block.data() + k * L.record_size, index, path);
      scan.bounds.lo = scan.bounds.lo.cwiseMin(p);
      scan.bounds.hi = scan.bounds.hi.cwiseMax(p);
      if (index % scan.stride == 0) {
        const auto row = static_cast<Eigen::Index>(index / scan.stride);
        scan.sample.row(row) = p.transpose();
        if (L.has_normals())
          scan.sample_normals.row(row) =
              record_normal(L, block.data() + k * L.record_size).transpose();
      }
    }
  }
  scan.seconds = since(start);
  return scan;
}

TiledRunPlan plan_out_of_core(const PlyScan& scan, const RemoveTextureParams& params,
                              const TilingParams& tiling, std::size_t record_size) {
  TilingParams t = tiling;
  t.extra_bytes_per_point += out_of_core_bytes_per_point(record_size);
  t.reserved_bytes += static_cast<double>(scan.sample.rows()) * 24.0;
  if (scan.stride == 1 && params.radius.unit == Length::Unit::Texture) {
    // The sample is the whole cloud: estimate r on it in spatial order, as
    // remove_texture and remove_texture_tiled do (the estimate samples rows).
    const std::vector<std::uint32_t> order = spatial_order(scan.sample);
    return plan_tiled_run(
        permute_rows(scan.sample, order),
        scan.sample_normals.rows() ? permute_rows(scan.sample_normals, order) : Normals(), 1.0,
        scan.bounds, static_cast<std::size_t>(scan.points), params, t);
  }
  return plan_tiled_run(scan.sample, Normals(), static_cast<double>(scan.stride), scan.bounds,
                        static_cast<std::size_t>(scan.points), params, t);
}

TileLogEntry run_binned_tile(const TileBins& bins, std::size_t t, const TilePlan& plan,
                             const PlyVertexLayout& in, const PlyVertexLayout& out,
                             const RemoveTextureParams& tile_params,
                             const std::function<void(const std::string&)>& warning,
                             const std::function<void(std::uint64_t, const unsigned char*)>& sink,
                             RemoveTextureReport* merged, std::size_t merged_core) {
  std::vector<std::uint64_t> indices;
  std::vector<unsigned char> records;
  bins.read(t, in.record_size, &indices, &records);
  const std::size_t m = indices.size();
  Positions P(static_cast<Eigen::Index>(m), 3);
  Normals N(in.has_normals() ? static_cast<Eigen::Index>(m) : 0, 3);
  std::vector<std::uint8_t> is_core(m);
  for (std::size_t k = 0; k < m; ++k) {
    const unsigned char* record = records.data() + k * in.record_size;
    const Eigen::Vector3d p = record_position(in, record, indices[k], "input");
    P.row(static_cast<Eigen::Index>(k)) = p.transpose();
    if (N.rows() != 0) N.row(static_cast<Eigen::Index>(k)) = record_normal(in, record).transpose();
    is_core[k] = core_tile(plan, p) == t;
  }
  PipelineObserver inner;
  inner.warning = warning;
  TileResult tr;
  try {
    tr = run_tile(std::move(P), std::move(N), is_core, tile_params, inner);
  } catch (...) {
    rethrow_tile_failure(t, m, true);
  }
  std::vector<unsigned char> record(out.record_size);
  for (std::size_t c = 0; c < tr.core.size(); ++c) {
    const std::size_t k = tr.core[c];
    const auto ci = static_cast<Eigen::Index>(c);
    encode_result_record(in, records.data() + k * in.record_size, out,
                         tr.positions.row(ci).transpose(), tr.normals.row(ci).transpose(),
                         record.data());
    sink(indices[k], record.data());
  }
  if (merged) merge_tile_report(tr, merged_core, merged);
  TileLogEntry e;
  e.tile = t;
  e.cell = plan.tiles[t].cell;
  e.core_points = tr.core.size();
  e.points = m;
  for (const std::uint8_t x : tr.is_texture) e.texture_points += x;
  e.rolling_iterations = tr.report.rolling_iterations;
  e.update_iterations = tr.report.update_iterations;
  e.seconds = tr.seconds;
  return e;
}

OutOfCoreReport remove_texture_out_of_core(const std::string& input, const std::string& output,
                                           const RemoveTextureParams& params,
                                           const TilingParams& tiling, const OutOfCoreParams& ooc,
                                           const TiledRunObserver& observer) {
  OutOfCoreReport rep;
  PlyVertexReader reader(input);
  const PlyVertexLayout& in = reader.layout();
  rep.points = in.count;
  rep.had_normals = in.has_normals();
  const PlyScan scan = scan_ply(reader, ooc.max_sample, input);
  rep.scan_seconds = scan.seconds;
  if (observer.progress) observer.progress(0.05);
  const TiledRunPlan run = plan_out_of_core(scan, params, tiling, in.record_size);
  const TilePlan& plan = run.plan;

  auto start = std::chrono::steady_clock::now();
  TileBins bins(ooc.temp_dir, plan.tiles.size());
  std::vector<std::uint64_t> core, points;
  bins.bin(reader, plan, &core, &points);
  rep.bin_seconds = since(start);
  if (observer.progress) observer.progress(0.1);

  const PlyVertexLayout out = result_layout(in, in.count);
  OutputFile file(output);
  const std::string header = ply_header_text(out);
  if (std::fwrite(header.data(), 1, header.size(), file.get()) != header.size() ||
      std::fflush(file.get()) != 0)
    throw std::runtime_error("cannot write '" + output + "': " + std::strerror(errno));
  const int fd = fileno(file.get());
  const off_t total = static_cast<off_t>(header.size() + out.record_size * in.count);
  if (ftruncate(fd, total) != 0)
    throw std::runtime_error("cannot write '" + output + "' (" + std::strerror(errno) +
                             "); out-of-core outputs must be regular files");
  auto sink = [&](std::uint64_t index, const unsigned char* record) {
    const off_t at = static_cast<off_t>(header.size() + out.record_size * index);
    if (pwrite(fd, record, out.record_size, at) != static_cast<ssize_t>(out.record_size))
      throw std::runtime_error("cannot write '" + output + "': " + std::strerror(errno));
  };

  rep.report = tiled_run_report(run);
  rep.tiles.tile_size = plan.tile_size;
  rep.tiles.halo = plan.halo;
  rep.tiles.grid = plan.grid;
  rep.tiles.tile_size_reason = run.tile_size_reason;
  rep.tiles.bytes_per_point = run.bytes_per_point;
  std::size_t count = 0;
  for (const std::uint64_t c : core) count += c > 0;
  rep.tiles.tiles_run = count;
  std::set<std::string> warned;
  auto warning = [&](const std::string& message) {
    if (warned.insert(message).second && observer.warning) observer.warning(message);
  };
  start = std::chrono::steady_clock::now();
  std::size_t done = 0, k_run = 0;
  for (std::size_t t = 0; t < plan.tiles.size(); ++t) {
    if (core[t] == 0) continue;
    if (observer.tile_begin)
      observer.tile_begin(k_run, count, plan.tiles[t], static_cast<std::size_t>(points[t]));
    const TileLogEntry e =
        run_binned_tile(bins, t, plan, in, out, run.tile_params, warning, sink, &rep.report, done);
    bins.remove(t);
    rep.tiles.tiles.push_back(e);
    done += e.core_points;
    if (observer.tile_end) observer.tile_end(k_run, count, e);
    if (observer.progress)
      observer.progress(0.1 + 0.9 * static_cast<double>(done) / static_cast<double>(in.count));
    ++k_run;
  }
  rep.tiles_seconds = since(start);
  rep.report.ransac_mean_iterations /= static_cast<double>(in.count);
  rep.report.relief_lean /= static_cast<double>(in.count);
  file.commit();
  return rep;
}

}  // namespace detexture
