// A position update that keeps a mesh valid. The method moves each vertex on
// its own (Eqs. 9-10), unaware of the faces between them; on a mesh, two
// vertices moving past each other crumple the faces between them (textured
// real meshes at r = 0.04 d: folded edges from 0.16% to 3.9%, the 99th
// percentile dihedral angle from 44° to 136°). repair_folds takes back, step
// by step, the moves of the vertices of every edge or triangle the update made
// worse than it was in the input, until none is.
#pragma once

#include <cstddef>

#include "detexture/geometry/face_normals.h"
#include "detexture/geometry/mesh_folds.h"
#include "detexture/types.h"

namespace detexture {

struct RepairFoldsParams {
  /// false: keep the positions as the update gives them (the paper, which
  /// treats a mesh's vertices as an unconnected cloud).
  bool enabled = true;
  /// An edge is folded when its dihedral angle exceeds this, degrees (0, 180).
  double fold_angle_deg = 60.0;
  /// The least dihedral angle bound L (see repair_folds), degrees, so that a
  /// nearly flat input (99th percentile near 0) still lets the update bend an
  /// edge a little; in [0, fold_angle_deg].
  double least_limit_deg = 20.0;
};

struct RepairFoldsReport {
  MeshFolds input;                ///< of the input mesh
  MeshFolds update;               ///< after the update, before the repair
  MeshFolds output;               ///< after the repair
  std::size_t vertices_held = 0;  ///< vertices whose move was shortened
  int rounds = 0;
};

/// The output positions (#P by 3) with the moves output - input shortened
/// where needed. An interior edge is made worse when its dihedral angle
/// exceeds both its input angle and L = min(fold_angle_deg, max(the input's
/// 99th percentile dihedral angle, least_limit_deg)); a triangle when its normal turns more than
/// 90° from its input normal. Every round halves the move of each vertex of such an edge (the four
/// corners of its two triangles) or triangle, and cancels it after 6 halvings. The rounds end when
/// nothing is made worse, which they always reach: an element whose vertices are all back at the
/// input is as it was. So the output has no flipped triangle, no more folded edges than the input,
/// and no more edges above L than the input (whence, when L is the input's 99th percentile, a 99th
/// percentile no higher than the input's). T as orient_triangles leaves it. Throws
/// std::invalid_argument for a fold angle out of range or sizes that disagree.
Positions repair_folds(const Positions& input, const Positions& output, const TriangleIndices& T,
                       const RepairFoldsParams& params = {}, RepairFoldsReport* report = nullptr);

}  // namespace detexture
