// The temporary files of an out-of-core run: one per tile, holding the tile's
// core and halo points as (input index, input record) in input order, in a
// private folder under --temp-dir. The folder and its files are removed by
// the destructor (normal exit, exceptions) and by remove_tile_bins() (from a
// signal handler).
#pragma once

#include <cstdint>
#include <cstdio>
#include <string>
#include <vector>

#include "detexture/io/ply_stream.h"
#include "detexture/tiling/plan_tiles.h"

namespace detexture {

class TileBins {
 public:
  /// Create a private folder "detexture-XXXXXX" in `parent` (which must
  /// exist) for the tiles of `plan`. Throws std::runtime_error naming the
  /// folder when it cannot be created. With `owner` false the folder is
  /// `parent` itself, made by another process (MPI rank 0), and is neither
  /// created nor removed here.
  TileBins(const std::string& parent, std::size_t tiles, bool owner = true);
  ~TileBins();
  TileBins(const TileBins&) = delete;
  TileBins& operator=(const TileBins&) = delete;

  const std::string& folder() const { return folder_; }
  std::string path(std::size_t tile, const char* kind = "tile") const;

  /// Bin every record of `reader` (rewound first) to the tiles whose extended
  /// box holds its position: appends (index, record) to the tile's file.
  /// Fills core[t] and points[t] (core and halo) per tile. At most 1000
  /// tiles may hold points (open files); more throws std::runtime_error
  /// asking for a larger --tile. Throws on write errors (disk full), naming
  /// the file.
  void bin(PlyVertexReader& reader, const TilePlan& plan, std::vector<std::uint64_t>* core,
           std::vector<std::uint64_t>* points, const std::function<void(double)>& progress = {});

  /// The records of a tile's file: indices[k] and records (record_size each).
  void read(std::size_t tile, std::size_t record_size, std::vector<std::uint64_t>* indices,
            std::vector<unsigned char>* records) const;
  /// Remove a tile's file once it has been run.
  void remove(std::size_t tile) const;

 private:
  std::string folder_;
  std::size_t tiles_ = 0;
  bool owner_ = true;
};

/// Unlink every file of the live TileBins and its folder. Async-signal-safe
/// (only unlink and rmdir on names kept in static buffers), for the CLI's
/// SIGINT/SIGTERM/SIGHUP handler.
void remove_tile_bins() noexcept;

}  // namespace detexture
