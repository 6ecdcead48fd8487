// The out-of-core run spread over the ranks of an MPI job
// (`mpirun -np N detexture --mpi IN -o OUT --temp-dir SHARED`). Built only
// when CMake finds MPI (DETEXTURE_HAVE_MPI); mpi.h stays inside the .cpp.
//
// Rank 0 reads the input (scan and bin passes, as remove_texture_out_of_core)
// into a temporary folder under --temp-dir, which must be on storage every
// rank sees (a cluster's shared file system; any folder on one machine).
// The plan, the resolved lengths and the tiles' point counts are broadcast;
// every rank derives the same tile assignment: tiles sorted by points (core
// and halo), largest first, each to the rank with the fewest points so far
// (ties to the lowest rank). Each rank runs its tiles with run_tile; rank 0
// writes its results straight into the output, the others into one result
// file per tile that rank 0 copies in once all are done. The output is the
// single-process out-of-core output byte for byte. A tile failing on any
// rank fails the run on every rank, with the message on rank 0, and nothing
// is left at the output path.
#pragma once

#include <string>
#include <vector>

#include "detexture/tiling/remove_texture_out_of_core.h"

namespace detexture {

/// MPI_Init on construction (if not yet initialized), MPI_Finalize on
/// destruction. Only in builds with MPI (DETEXTURE_HAVE_MPI), like
/// remove_texture_mpi; assign_tiles is always there.
class MpiSession {
 public:
  MpiSession();
  ~MpiSession();
  MpiSession(const MpiSession&) = delete;
  MpiSession& operator=(const MpiSession&) = delete;
  int rank() const { return rank_; }
  int size() const { return size_; }

 private:
  int rank_ = 0, size_ = 1;
  bool finalize_ = false;
};

/// The tile assignment described above: owner rank of each tile (-1 for
/// tiles without core points), from the tiles' core and total point counts.
std::vector<int> assign_tiles(const std::vector<std::uint64_t>& core,
                              const std::vector<std::uint64_t>& points, int ranks);

/// The MPI run; every rank calls it. The report is complete on rank 0 (the
/// tile log of every rank, with the rank that ran each tile); other ranks get
/// their own tiles only. Throws on every rank when any rank fails.
OutOfCoreReport remove_texture_mpi(const MpiSession& session, const std::string& input,
                                   const std::string& output, const RemoveTextureParams& params,
                                   const TilingParams& tiling, const OutOfCoreParams& ooc,
                                   const TiledRunObserver& observer = {});

}  // namespace detexture
