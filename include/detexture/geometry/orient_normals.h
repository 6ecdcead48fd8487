// Consistent orientation of unoriented normals (Hoppe et al. 1992), with a
// sign rule and an edge order that survive sharp edges and thin sheets.
#pragma once

#include <cstddef>

#include "detexture/geometry/radius_neighborhoods.h"
#include "detexture/types.h"

namespace detexture {

/// Which side each connected component's normals face (orient_normals,
/// "Side" below): Auto chooses it from the shape; Outward and Inward by the
/// component's flux alone (rule 1 without its threshold); the others face
/// the named axis direction on average (Σ n̂ along it > 0), for a scan seen
/// from that direction, like CloudCompare's preferred orientation, PCL's
/// viewpoint or Open3D's orient_normals_to_align_with_direction.
enum class NormalSide { Auto, Outward, Inward, PlusX, MinusX, PlusY, MinusY, PlusZ, MinusZ };

struct OrientNormalsParams {
  /// Suspected cross-sheet edges, in degrees, in (0, 90]; default 15.
  /// An edge i-j is suspected of jumping between the two sides of a thin
  /// sheet when its chord leaves the tangent planes by more than the normals
  /// turn: α_i + α_j - θ > cross_sheet_angle, where α_i = asin|d̂·n_i| is the
  /// chord's elevation above the tangent plane of i (d̂ = unit p_j - p_i) and
  /// θ = acos|n_i·n_j| the angle between the unoriented normals. Along any
  /// surface whose cross-section between the two points is a planar curve
  /// without inflection (an arc, a sharp crease) α_i + α_j = θ, so the
  /// excess is about 0; between the two sides of a sheet of thickness t at
  /// lateral distance L it is 2 atan(t/L) (44 degrees at L = 2.5 t).
  /// Smaller values detect thinner sheets (edges up to L ≈ 7.6 t at 15
  /// degrees: 2 atan(1/7.6) = 15) but demote more edges on rough or textured
  /// surfaces (harmless on its own: demoted edges are still used, only later).
  /// The thin-plate test fails at 60 degrees and passes at 15 with k up to 30.
  double cross_sheet_angle = 15.0;
  /// Side each connected component faces; Auto = the rules of "Side" in
  /// orient_normals.h (outward by the flux, up for a flat open sheet).
  /// A component the chosen rule cannot decide (Outward on a plane, +x on a
  /// sheet parallel to x) falls back to the farthest-point rule (rule 3).
  NormalSide side = NormalSide::Auto;
};

/// Throws std::invalid_argument naming a parameter out of range.
void validate(const OrientNormalsParams& params);

struct OrientNormalsResult {
  Normals normals;             ///< #P by 3 input normals, flipped where needed; zero stays zero
  std::size_t components = 0;  ///< connected components of the neighbor graph (non-zero normals)
  std::size_t flipped = 0;     ///< normals whose sign was changed
  /// Spanning-tree edges that had to be suspected cross-sheet edges (no
  /// other path reached their point). Non-zero means part of the cloud may
  /// be oriented wrongly, e.g. a thin sheet sampled more coarsely than its
  /// thickness, or a heavily textured surface (where the edges are fine).
  std::size_t cross_sheet_edges = 0;
};

/// Orient normals consistently by propagating signs along a minimum
/// spanning tree of the neighbor graph N (Hoppe et al. 1992), grown with
/// Prim's algorithm and a heap (O(E log P)). Costs are compared as floats;
/// edges within ~1e-7 of each other tie, and ties go to the lower index.
///
/// Graph: N is used as given (pass k-NN neighborhoods, k ≈ 10-30, or the
/// radius neighborhoods) and treated as undirected: an edge j ∈ N_i is also
/// an edge of j, even if i ∉ N_j (k-NN graphs are not symmetric). Points
/// with a zero normal are skipped: they keep their zero normal and carry no
/// sign, but the points around them are still reached through other edges.
///
/// Sign rule: n_j is flipped if n_i⊥·n_j⊥ < 0, where n⊥ = n - (d̂·n) d̂ is a
/// normal with its component along the chord d̂ removed. This agrees with
/// Hoppe's n_i·n_j < 0 on smooth surfaces (n_i⊥·n_j⊥ = cos²(θ/2) > 0 on a
/// consistently oriented circular arc), and unlike it still decides across
/// sharp creases, where n_i·n_j ≈ 0 (on a 90-degree edge both projected
/// normals point along the bisector).
///
/// Edge order: cross-sheet suspects (see OrientNormalsParams) come after all
/// other edges; within each group the cost is 1 - |n_i⊥·n_j⊥|, in [0, 1]:
/// 0 for parallel normals side by side, 1 when the sign cannot be decided.
/// Why: on a thin two-sided plate, k-NN neighborhoods reach across the
/// sheet, and those edges cost nothing with Hoppe's 1 - |n_i·n_j| (parallel
/// normals), so the tree jumps sides and turns the bottom face up. The chord
/// of such an edge runs along the normals; demoting these edges makes the
/// tree go around the rim, where the sign rule above turns the normal with
/// the surface. This needs a rim that the normals resolve; a sheet whose
/// rim is thinner than the sampling is ambiguous to any local rule.
///
/// Side: propagation fixes the signs within a connected component relative
/// to each other; which way the whole component faces is params.side
/// (NormalSide). With Auto, the default, it is chosen from the component's
/// shape, with c its centroid, n̂ its oriented unit normals and m = Σ n̂:
///  1. Outward, when the flux says so clearly: |Σ n̂·(p - c)| >=
///     kOutwardFluxRatio Σ |p - c|, and the sign of the sum decides. On a
///     closed surface the sum is 3 V (volume V, times the density), > 0 for
///     outward normals, from any c (divergence theorem); over a cap or a
///     bent sheet it is > 0 on the convex side. Unlike one point's normal it
///     does not hang on a noisy tip or a rim.
///  2. Up, for a flat-ish open sheet seen from one side (terrain, a relief, a
///     plate scanned from above, a tile of such a scan): its normals agree,
///     |m| >= kOpenSheetResultant × count (on a closed surface m ≈ 0), and m
///     is within 60 degrees of the z axis, |m_z| >= kUpwardCosine |m|: the
///     normals face +z, as PDAL's normal filter does by default (always_up).
///     A saddle or a plane with bumps has no convex side for rule 1.
///  3. Otherwise the component's point farthest from c (lowest index on
///     ties) faces away from c (the rule alone before session 11).
/// A sheet whose sides the shape cannot tell (a wall seen from one side, a
/// bowl seen from inside) may face either way; so may parts that pierce
/// each other, which one tree joins.

/// Deterministic: the result does not depend on the number of threads.
/// Time: Prim's loop is serial; it is bound by cache misses on neighbors, so
/// clouds stored in spatial order (scans, or Morton-sorted) run several times
/// faster than shuffled ones. Measured on a shared 2-core machine: 1M points
/// in 0.6 s (k = 10) and 0.9 s (k = 30); 5M points in 2.6 s (k = 10) and
/// 5.6 s (k = 30); 1M shuffled points in 2.1 s (k = 10).
///
/// P  #P by 3 positions
/// normals  #P by 3 unoriented normals (any non-zero length; zero = unknown)
/// N  neighbor graph of P, N.size() == #P
/// Throws std::invalid_argument for mismatched sizes or a cross_sheet_angle
/// outside (0, 90].
OrientNormalsResult orient_normals(const Positions& P, const Normals& normals,
                                   const Neighborhoods& N, const OrientNormalsParams& params);

/// orient_normals with the default OrientNormalsParams.
OrientNormalsResult orient_normals(const Positions& P, const Normals& normals,
                                   const Neighborhoods& N);

/// Rule 1 of "Side" above: |Σ n̂·(p - c)| / Σ |p - c| is 1 on a sphere, 0.42
/// on a torus of radii 1 and 0.3, about 0.75 α on a spherical cap of
/// half-angle α (radians), 0 on a plane or a symmetric saddle. At 0.05,
/// caps of more than about 4 degrees (a tile of a closed scan) are decided
/// by their convex side, and flatter sheets by rule 2.
constexpr double kOutwardFluxRatio = 0.05;
/// Rule 2: |Σ n̂| / count of an open sheet. 1 on a plane, 0.5 on a
/// hemisphere, 0 on a closed surface sampled evenly (0.33 if one half is
/// sampled twice as densely as the other).
constexpr double kOpenSheetResultant = 0.5;
/// Rule 2: the sheet's mean normal is within 60 degrees of the z axis.
constexpr double kUpwardCosine = 0.5;

/// Neighbor pairs whose normals make less than 60 degrees when one of them is
/// flipped, |n_i·n_j| >= 0.5, are "comparable"; pairs closer to perpendicular
/// (across the sharp edges of a cube, say) carry no reliable sign and are
/// ignored.
constexpr double kComparableNormalsCosine = 0.5;

/// orientation_inconsistency above this suggests that the input normals are
/// not consistently oriented (the CLI then suggests --reorient).
/// Derivation: with consistent normals the inconsistency is 0 except where
/// neighborhoods span both sides of a sheet (exactly 0 on the test sphere
/// and cube). If a random fraction f of the normals is flipped, a pair disagrees
/// when exactly one of its two normals was flipped: 2 f (1 - f), i.e. 0.18 at
/// f = 10% and 0.02 at f = 1% (both verified in test_orient_normals.cpp).
/// 0.01 flags about 0.5% flipped normals, or a seam between two oppositely
/// oriented halves once about 1% of the neighbor pairs straddle it.
constexpr double kInconsistentOrientationThreshold = 0.01;

/// Fraction of comparable neighbor pairs (i, j ∈ N_i, j != i, both normals
/// non-zero, |n_i·n_j| >= kComparableNormalsCosine) whose normals point in
/// opposite directions (n_i·n_j < 0). 0 if there are no comparable pairs.
/// Near 0 for consistent normals; see kInconsistentOrientationThreshold.
/// Limitation: without positions it cannot tell the two sides of a thin
/// sheet from flipped neighbors, so neighborhoods that reach across a sheet
/// raise the score.
/// `nearest` > 0 looks only at the first `nearest` members of each row (the
/// nearest, in radius or k-NN neighborhoods): as telling, cheaper on large
/// neighborhoods, and less likely to reach across a sheet. 0 uses all.
/// Throws std::invalid_argument if N does not match normals.
double orientation_inconsistency(const Normals& normals, const Neighborhoods& N,
                                 std::size_t nearest = 0);

}  // namespace detexture
