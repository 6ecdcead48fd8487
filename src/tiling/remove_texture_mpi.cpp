// Built only when CMake finds MPI (see CMakeLists.txt).
#include "detexture/tiling/remove_texture_mpi.h"

#include <mpi.h>
#include <unistd.h>

#include <cerrno>
#include <chrono>
#include <cstring>
#include <iterator>
#include <memory>
#include <set>
#include <stdexcept>

#include "detexture/geometry/estimate_neighborhoods_memory.h"
#include "detexture/io/output_file.h"

namespace detexture {
namespace {

enum ErrorKind : int { kNone = 0, kArgument = 1, kResource = 2, kOther = 3 };

struct Failure {
  int kind = kNone;
  std::string message;
  void set(const std::exception& e) {
    message = e.what();
    kind = dynamic_cast<const std::invalid_argument*>(&e) ? kArgument
           : dynamic_cast<const ResourceLimitError*>(&e)  ? kResource
                                                          : kOther;
  }
};

// Every rank learns whether any failed; the lowest failing rank's message
// is sent to all, and every rank throws it.
void agree_on_failure(const Failure& mine, int rank, int size) {
  const int candidate = mine.kind != kNone ? rank : size;
  int first = size;
  MPI_Allreduce(&candidate, &first, 1, MPI_INT, MPI_MIN, MPI_COMM_WORLD);
  if (first == size) return;
  int kind = mine.kind;
  MPI_Bcast(&kind, 1, MPI_INT, first, MPI_COMM_WORLD);
  std::string message = mine.message;
  int length = static_cast<int>(message.size());
  MPI_Bcast(&length, 1, MPI_INT, first, MPI_COMM_WORLD);
  message.resize(static_cast<std::size_t>(length));
  MPI_Bcast(message.data(), length, MPI_CHAR, first, MPI_COMM_WORLD);
  if (first != 0) message = "rank " + std::to_string(first) + ": " + message;
  if (kind == kArgument) throw std::invalid_argument(message);
  if (kind == kResource) throw ResourceLimitError(message);
  throw std::runtime_error(message);
}

void bcast_string(std::string& s) {
  int length = static_cast<int>(s.size());
  MPI_Bcast(&length, 1, MPI_INT, 0, MPI_COMM_WORLD);
  s.resize(static_cast<std::size_t>(length));
  MPI_Bcast(s.data(), length, MPI_CHAR, 0, MPI_COMM_WORLD);
}

constexpr int kLogFields = 11;

void pack(const TileLogEntry& e, double* out) {
  const double v[kLogFields] = {double(e.tile),
                                double(e.cell(0)),
                                double(e.cell(1)),
                                double(e.cell(2)),
                                double(e.core_points),
                                double(e.points),
                                double(e.texture_points),
                                double(e.rolling_iterations),
                                double(e.update_iterations),
                                e.seconds,
                                double(e.rank)};
  std::memcpy(out, v, sizeof v);
}

TileLogEntry unpack(const double* v) {
  TileLogEntry e;
  e.tile = static_cast<std::size_t>(v[0]);
  e.cell = {int(v[1]), int(v[2]), int(v[3])};
  e.core_points = static_cast<std::size_t>(v[4]);
  e.points = static_cast<std::size_t>(v[5]);
  e.texture_points = static_cast<std::size_t>(v[6]);
  e.rolling_iterations = int(v[7]);
  e.update_iterations = int(v[8]);
  e.seconds = v[9];
  e.rank = int(v[10]);
  return e;
}

}  // namespace

MpiSession::MpiSession() {
  int initialized = 0;
  MPI_Initialized(&initialized);
  if (!initialized) {
    MPI_Init(nullptr, nullptr);
    finalize_ = true;
  }
  MPI_Comm_rank(MPI_COMM_WORLD, &rank_);
  MPI_Comm_size(MPI_COMM_WORLD, &size_);
}

MpiSession::~MpiSession() {
  if (finalize_) MPI_Finalize();
}

OutOfCoreReport remove_texture_mpi(const MpiSession& session, const std::string& input,
                                   const std::string& output, const RemoveTextureParams& params,
                                   const TilingParams& tiling, const OutOfCoreParams& ooc,
                                   const TiledRunObserver& observer) {
  const int rank = session.rank(), size = session.size();
  const auto start = std::chrono::steady_clock::now();
  OutOfCoreReport rep;
  Failure failure;

  // Rank 0: scan, plan, bin.
  std::unique_ptr<PlyVertexReader> reader;
  std::unique_ptr<TileBins> bins;
  TiledRunPlan run;
  std::vector<std::uint64_t> core, points;
  double numbers[10] = {0};  // bounds lo, hi, tile size, halo, diagonal, r
  std::string folder;
  if (rank == 0) {
    try {
      reader = std::make_unique<PlyVertexReader>(input);
      const PlyScan scan = scan_ply(*reader, ooc.max_sample, input);
      rep.scan_seconds = scan.seconds;
      run = plan_out_of_core(scan, params, tiling, reader->layout().record_size);
      const auto t0 = std::chrono::steady_clock::now();
      bins = std::make_unique<TileBins>(ooc.temp_dir, run.plan.tiles.size());
      bins->bin(*reader, run.plan, &core, &points);
      rep.bin_seconds =
          std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
      for (int d = 0; d < 3; ++d) {
        numbers[d] = run.plan.bounds.lo(d);
        numbers[3 + d] = run.plan.bounds.hi(d);
      }
      numbers[6] = run.plan.tile_size;
      numbers[7] = run.plan.halo;
      numbers[8] = run.lengths.diagonal;
      numbers[9] = run.lengths.radius.radius;
      folder = bins->folder();
    } catch (const std::exception& e) {
      failure.set(e);
    }
  }
  agree_on_failure(failure, rank, size);

  // The plan on every rank.
  MPI_Bcast(numbers, 10, MPI_DOUBLE, 0, MPI_COMM_WORLD);
  bcast_string(folder);
  unsigned long long tiles = core.size();
  MPI_Bcast(&tiles, 1, MPI_UNSIGNED_LONG_LONG, 0, MPI_COMM_WORLD);
  core.resize(tiles);
  points.resize(tiles);
  MPI_Bcast(core.data(), static_cast<int>(tiles), MPI_UINT64_T, 0, MPI_COMM_WORLD);
  MPI_Bcast(points.data(), static_cast<int>(tiles), MPI_UINT64_T, 0, MPI_COMM_WORLD);
  Box bounds;
  bounds.lo = Eigen::Vector3d(numbers[0], numbers[1], numbers[2]);
  bounds.hi = Eigen::Vector3d(numbers[3], numbers[4], numbers[5]);
  PlyVertexLayout in;
  TilePlan plan;
  RemoveTextureParams tile_params;
  try {
    if (rank == 0) {
      in = reader->layout();
      plan = run.plan;
      tile_params = run.tile_params;
    } else {
      in = PlyVertexReader(input).layout();  // the header only
      plan = plan_tiles(bounds, numbers[6], numbers[7]);
      TileLengths lengths;
      lengths.diagonal = numbers[8];
      lengths.radius.radius = numbers[9];
      tile_params = resolve_tile_params(params, lengths);
      bins = std::make_unique<TileBins>(folder, static_cast<std::size_t>(tiles), false);
    }
  } catch (const std::exception& e) {
    failure.set(e);
  }
  agree_on_failure(failure, rank, size);
  const std::vector<int> owner = assign_tiles(core, points, size);
  const PlyVertexLayout out = result_layout(in, in.count);

  // Rank 0 writes into the output; the others into result files.
  std::unique_ptr<OutputFile> file;
  std::string header;
  int fd = -1;
  if (rank == 0) {
    try {
      file = std::make_unique<OutputFile>(output);
      header = ply_header_text(out);
      if (std::fwrite(header.data(), 1, header.size(), file->get()) != header.size() ||
          std::fflush(file->get()) != 0)
        throw std::runtime_error("cannot write '" + output + "': " + std::strerror(errno));
      fd = fileno(file->get());
      if (ftruncate(fd, static_cast<off_t>(header.size() + out.record_size * in.count)) != 0)
        throw std::runtime_error("cannot write '" + output + "' (" + std::strerror(errno) +
                                 "); out-of-core outputs must be regular files");
    } catch (const std::exception& e) {
      failure.set(e);
    }
  }
  agree_on_failure(failure, rank, size);
  auto put = [&](std::uint64_t index, const unsigned char* record) {
    const off_t at = static_cast<off_t>(header.size() + out.record_size * index);
    if (pwrite(fd, record, out.record_size, at) != static_cast<ssize_t>(out.record_size))
      throw std::runtime_error("cannot write '" + output + "': " + std::strerror(errno));
  };

  rep.points = in.count;
  rep.had_normals = in.has_normals();
  rep.report = tiled_run_report(run);
  rep.report.radius = tile_params.radius.value;
  std::set<std::string> warned;
  auto warning = [&](const std::string& message) {
    if (warned.insert(message).second && observer.warning)
      observer.warning((rank ? "rank " + std::to_string(rank) + ": " : std::string()) + message);
  };
  std::size_t count = 0, mine = 0;
  for (std::size_t t = 0; t < tiles; ++t) {
    count += owner[t] >= 0;
    mine += owner[t] == rank;
  }
  std::vector<double> log;
  std::size_t done = 0, k_run = 0;
  try {
    for (std::size_t t = 0; t < tiles; ++t) {
      if (owner[t] != rank) continue;
      if (observer.tile_begin)
        observer.tile_begin(k_run, mine, plan.tiles[t], static_cast<std::size_t>(points[t]));
      std::FILE* result = nullptr;
      if (rank != 0) {
        result = std::fopen(bins->path(t, "result").c_str(), "wb");
        if (!result)
          throw std::runtime_error("cannot create '" + bins->path(t, "result") +
                                   "': " + std::strerror(errno));
        std::setvbuf(result, nullptr, _IOFBF, 1 << 18);
      }
      auto sink = [&](std::uint64_t index, const unsigned char* record) {
        if (rank == 0) return put(index, record);
        if (std::fwrite(&index, sizeof index, 1, result) != 1 ||
            std::fwrite(record, out.record_size, 1, result) != 1)
          throw std::runtime_error("cannot write '" + bins->path(t, "result") +
                                   "': " + std::strerror(errno) + " (is --temp-dir full?)");
      };
      TileLogEntry e;
      try {
        e = run_binned_tile(*bins, t, plan, in, out, tile_params, warning, sink, &rep.report, done);
      } catch (...) {
        if (result) std::fclose(result);
        throw;
      }
      if (result && std::fclose(result) != 0)
        throw std::runtime_error("cannot write '" + bins->path(t, "result") +
                                 "' (is --temp-dir full?)");
      bins->remove(t);
      e.rank = rank;
      log.resize(log.size() + kLogFields);
      pack(e, log.data() + log.size() - kLogFields);
      done += e.core_points;
      if (observer.tile_end) observer.tile_end(k_run, mine, e);
      ++k_run;
    }
  } catch (const std::exception& e) {
    failure.set(e);
  }
  agree_on_failure(failure, rank, size);

  // The tile log and the texture count on rank 0.
  int length = static_cast<int>(log.size());
  std::vector<int> lengths(static_cast<std::size_t>(size)), offsets(static_cast<std::size_t>(size));
  MPI_Gather(&length, 1, MPI_INT, lengths.data(), 1, MPI_INT, 0, MPI_COMM_WORLD);
  std::vector<double> all;
  if (rank == 0) {
    int total = 0;
    for (int r = 0; r < size; ++r) {
      offsets[static_cast<std::size_t>(r)] = total;
      total += lengths[static_cast<std::size_t>(r)];
    }
    all.resize(static_cast<std::size_t>(total));
  }
  MPI_Gatherv(log.data(), length, MPI_DOUBLE, all.data(), lengths.data(), offsets.data(),
              MPI_DOUBLE, 0, MPI_COMM_WORLD);
  // The counts each rank's tiles added up, summed over the ranks.
  const unsigned long long counts[] = {
      rep.report.texture_points,          rep.report.opposite_neighbors,
      rep.report.surface_split_neighbors, rep.report.normals_not_fitted,
      rep.report.normals_blended,         rep.report.waves_flagged,
      rep.report.waves_released,          rep.report.input_normals_kept,
      rep.report.counter_moves_limited,   rep.report.tip_moves_limited,
      rep.report.raised_cells_lowered,    rep.report.raised_cells_limited,
      rep.report.raised_cells_turned,     rep.report.sink_moves_limited,
      rep.report.input_normals_updated};
  unsigned long long counts_all[std::size(counts)] = {};
  MPI_Reduce(counts, counts_all, static_cast<int>(std::size(counts)), MPI_UNSIGNED_LONG_LONG,
             MPI_SUM, 0, MPI_COMM_WORLD);

  if (rank == 0) {
    try {
      rep.report.texture_points = static_cast<std::size_t>(counts_all[0]);
      rep.report.opposite_neighbors = static_cast<std::size_t>(counts_all[1]);
      rep.report.surface_split_neighbors = static_cast<std::size_t>(counts_all[2]);
      rep.report.normals_not_fitted = static_cast<std::size_t>(counts_all[3]);
      rep.report.normals_blended = static_cast<std::size_t>(counts_all[4]);
      rep.report.waves_flagged = static_cast<std::size_t>(counts_all[5]);
      rep.report.waves_released = static_cast<std::size_t>(counts_all[6]);
      rep.report.input_normals_kept = static_cast<std::size_t>(counts_all[7]);
      rep.report.counter_moves_limited = static_cast<std::size_t>(counts_all[8]);
      rep.report.tip_moves_limited = static_cast<std::size_t>(counts_all[9]);
      rep.report.raised_cells_lowered = static_cast<std::size_t>(counts_all[10]);
      rep.report.raised_cells_limited = static_cast<std::size_t>(counts_all[11]);
      rep.report.raised_cells_turned = static_cast<std::size_t>(counts_all[12]);
      rep.report.sink_moves_limited = static_cast<std::size_t>(counts_all[13]);
      rep.report.input_normals_updated = static_cast<std::size_t>(counts_all[14]);
      std::vector<TileLogEntry> entries;
      for (std::size_t k = 0; k + kLogFields <= all.size(); k += kLogFields)
        entries.push_back(unpack(all.data() + k));
      std::sort(entries.begin(), entries.end(),
                [](const TileLogEntry& a, const TileLogEntry& b) { return a.tile < b.tile; });
      rep.tiles.tiles = entries;
      rep.tiles.tile_size = plan.tile_size;
      rep.tiles.halo = plan.halo;
      rep.tiles.grid = plan.grid;
      rep.tiles.tiles_run = count;
      rep.tiles.tile_size_reason = run.tile_size_reason + "; " + std::to_string(size) + " ranks";
      rep.tiles.bytes_per_point = run.bytes_per_point;
      // The other ranks' results, into place.
      std::vector<unsigned char> block;
      const std::size_t entry = sizeof(std::uint64_t) + out.record_size;
      for (std::size_t t = 0; t < tiles; ++t) {
        if (owner[t] <= 0) continue;
        const std::string name = bins->path(t, "result");
        std::FILE* f = std::fopen(name.c_str(), "rb");
        if (!f) throw std::runtime_error("cannot open '" + name + "': " + std::strerror(errno));
        block.resize(entry * 4096);
        std::size_t got;
        while ((got = std::fread(block.data(), entry, 4096, f)) > 0)
          for (std::size_t k = 0; k < got; ++k) {
            std::uint64_t index;
            std::memcpy(&index, block.data() + k * entry, sizeof index);
            put(index, block.data() + k * entry + sizeof index);
          }
        std::fclose(f);
        unlink(name.c_str());
      }
      file->commit();
    } catch (const std::exception& e) {
      failure.set(e);
    }
  }
  agree_on_failure(failure, rank, size);
  rep.tiles_seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count() -
      rep.scan_seconds - rep.bin_seconds;
  rep.report.ransac_mean_iterations /= static_cast<double>(std::max<std::uint64_t>(1, in.count));
  rep.report.relief_lean /= static_cast<double>(std::max<std::uint64_t>(1, in.count));
  return rep;
}

}  // namespace detexture
