// Texture identification (Sun et al. 2019, Sec. 4, Eq. 2).
//
// A RANSAC plane is fitted to every radius neighborhood R_i. Point p_j is
// counted as an inlier T_j times over the N_j neighborhoods that produced a
// plane and contain it; it is underlying surface iff T_j > δ·N_j (Eq. 2),
// texture otherwise. The non-texture points of R_i form the sub-neighborhood
// Ω_i used by the Gaussian filter (Eq. 1).
//
// One plane per neighborhood, as in the paper, marks a band of width ~r on
// both sides of every sharp edge as texture: near an edge, the neighborhoods
// centred across it fit the other face and count the point as an outlier.
// The filters then never see the faces' own normals next to the edge, and
// the rolling filter recovers the edge late and off its place. By default we
// therefore fit a second plane to the outliers of the first: when it carries
// a real share of the neighborhood and meets the first at a clear angle, it is
// the other face of a crease, and its inliers count too (a third plane does
// the same at corners). Texture relief is
// curved, so a plane through it finds only a thin band of support and is
// rejected. `planes = 1` is the paper's rule.
//
// Curved underlying surfaces. A plane through R_i (radius r) cannot hold a
// surface whose sag over it, r²/(2ρ) for a radius of curvature ρ, exceeds λ:
// on a sphere of ρ = 10r at the default λ = 0.05r every neighborhood already
// loses its rim, and on organic shapes (limbs, snouts, ears) most points end
// up labelled texture, Ω_i collapses to a biased band and the filters make
// the surface worse than the input. By default the first plane is therefore
// bent into a quadratic height field over it, h = a u² + b uv + c v² + e u +
// f v (u, v along the plane), fitted by least squares to the plane's inliers
// and re-counted, for a few rounds while the inliers grow. Starting from the
// plane's inliers keeps relief the plane rejected (a bump) out of the fit; a
// fit that bends more tightly than `min_surface_radius` is refused (texture,
// not shape), and so is one that adds less than `surface_min_gain` of R_i
// to the plane's inliers. The model with the quadric and the further planes
// (below) is kept only when it explains more points than the planes alone,
// so at creases the planes stay. The further planes at creases stay planes. `surface = Plane` is
// the paper's test.
//
// Ω_i as weights. The filters (Eqs. 1, 3) take each neighbor's membership of
// Ω as a weight ω_j in [0, 1]. `Hard` (the paper) is 1 for underlying
// surface and 0 for texture. `Soft` (ours, the default) ramps with the vote
// share T_j/N_j: 0 at or below `soft_floor`, 1 at or above δ, linear between.
// On separated features the votes are bimodal (near 0 on the feature, near 1
// elsewhere) and both agree; on dense texture covering the whole surface
// (scales, knurls, waves) most votes are in between, the hard rule keeps an
// arbitrary, biased subset, and the soft one degrades towards the plain
// Gaussian, which is better there (bench/RESULTS.md). On curved and thin
// real shapes the hard Ω_i also keeps a biased band; soft wins every case of
// the real-shape suite. Hard keeps grooves cleaner (noisy U grooves 2.1°
// against 3.6°), so it stays an option.
//
// Votes with normals. With the input normals given, a point's vote in Eq. 2
// also asks that its normal agree with the model's within
// `vote_normal_angle_deg` (45° by default; 180° is the paper's positions-only
// test). Points midway up a wave or a scale lie on the fitted plane but are
// tilted with the relief; so are the flanks of a dome where they cross λ.
#pragma once

#include <cstdint>
#include <vector>

#include "detexture/geometry/radius_neighborhoods.h"
#include "detexture/types.h"

namespace detexture {

/// The model RANSAC's first fit of each R_i is refined into.
enum class UnderlyingSurface {
  Plane,    ///< a plane (the paper: the underlying surface is piecewise flat)
  Quadric,  ///< the plane bent into a quadratic height field over it (see above)
};

enum class SubneighborhoodMode {
  Hard,  ///< ω = 1 for underlying surface, 0 for texture (the paper)
  Soft,  ///< ω ramps with the vote share T/N (see above)
};

struct DetectTextureParams {
  /// λ: RANSAC distance threshold, in the cloud's units; > 0. A point farther
  /// than λ from a neighborhood's plane is an outlier of that plane. Smaller
  /// than the texture's height, larger than noise and than the sag r²/(2·R) of
  /// the underlying surface over a neighborhood of radius r.
  double lambda = 0.0;
  /// δ: fraction of a point's neighborhoods in which it must be an inlier to
  /// count as underlying surface, in (0, 1). Larger marks more points texture.
  double delta = 0.8;
  /// Probability that the best plane of a neighborhood has been found when
  /// RANSAC stops early, in (0, 1).
  double confidence = 0.99;
  /// Planes fitted per neighborhood: 1 (the paper), 2 (a second face across
  /// a crease also counts as surface; see above) or 3 (and a third at a
  /// corner). Each further plane is fitted to the outliers of the earlier ones.
  int planes = 3;
  /// Further planes: least share of the neighborhood each must fit, in (0, 1).
  double second_plane_share = 0.15;
  /// Further planes: least angle to every earlier plane, in degrees, in (0,
  /// 90]; parallel terraces (raised plateaus) stay texture.
  double second_plane_angle_deg = 20.0;
  /// Cap on RANSAC tries per plane, ≥ 1.
  int max_iterations = 100;
  /// The model of the underlying surface in each R_i (see above).
  UnderlyingSurface surface = UnderlyingSurface::Quadric;
  /// Quadric: the tightest radius of curvature the underlying surface may
  /// have, in the cloud's units; > 0, or 0 for no limit. Filled from
  /// RemoveTextureParams (default 0.5r).
  double min_surface_radius = 0.0;
  /// Quadric: least share of R_i it must add to the plane's inliers to be
  /// used, in [0, 1). Bending onto the foot of a bump on a flat face gains a
  /// few points; a curved surface whose rim the plane misses gains many
  /// (0.03 and 0.1 were measured: 0.1 gave up a fifth of the gain on a sphere
  /// with dense scales, 0.03 left a flat cube with bumps 2% worse than the plane).
  double surface_min_gain = 0.05;
  /// Quadric: tried only where the planes explain less than this share of
  /// R_i, in (0, 1]. Where a plane already holds most of the neighborhood the
  /// surface is flat enough for the paper's test, and a quadric could only
  /// bend into the texture (measured: V and U grooves lost 5-15% against the
  /// plane with 1, nothing at 0.7; curved shapes kept most of their gain).
  double surface_max_plane_share = 0.7;
  /// Quadric, when normals are given: a point counts as an inlier of a
  /// quadric only if its normal also lies within this angle of the
  /// quadric's normal there, in degrees, in (0, 180] (180: no test). A
  /// curved underlying surface agrees with its own normals; a quadric bent
  /// onto the flank of a bump or into a groove does not.
  double surface_normal_angle_deg = 30.0;
  /// Votes of Eq. 2, when normals are given: a point is counted as an inlier
  /// of a neighborhood's model (plane or quadric) only if its normal also
  /// lies within this angle of the model's normal, in degrees, in (0, 180]
  /// (180: positions alone, the paper). On a profile that covers the whole
  /// surface (waves, knurls, scales) the points midway up the relief lie on
  /// the fitted plane but are tilted with it; counted as surface, they make
  /// Ω_i a biased set of flank normals.
  /// The default, 45°, was measured with the soft Ω (bench/RESULTS.md): at
  /// 20-30° the upright floor of noisy grooves and dome bases vote cleaner,
  /// but limbs and scales lose points to normal noise.
  double vote_normal_angle_deg = 45.0;
  /// Quadric: least-squares rounds (refit to the inliers, recount), ≥ 1.
  int surface_rounds = 3;
  /// Refit the best plane to its inliers by least squares before the final
  /// inlier count (not in the paper; steadier classification).
  bool refine = true;
  /// Seed of the per-point generators (seeded from seed and point index).
  std::uint64_t seed = 1;
  /// How the filters weigh a neighbor's membership of Ω (see above).
  /// Soft by default (measured on both suites; bench/RESULTS.md): it wins
  /// every real-shape case against Hard and loses on grooves; Hard is the paper.
  SubneighborhoodMode subneighborhood = SubneighborhoodMode::Soft;
  /// Soft: vote share T/N at or below which ω = 0, in [0, δ).
  double soft_floor = 0.3;
  /// Also return each point's surface normal (TextureDetection::surface_normal).
  bool surface_normals = false;
};

struct TextureDetection {
  std::vector<std::uint8_t> is_texture;  ///< #P; 1 = texture (Eq. 2 fails), 0 = underlying surface
  std::vector<std::uint32_t> inliers;    ///< #P; T_i
  std::vector<std::uint32_t> members;    ///< #P; N_i, neighborhoods with a plane that contain i
  std::vector<float> omega;              ///< #P; ω_i in [0, 1], membership of Ω (see above)
  /// #P; distance of p_i from the underlying surface fitted to its own R_i
  /// (the nearest of its models): the height of the texture at p_i as seen
  /// at scale r; 0 where no plane was found.
  std::vector<float> height;
  /// #P by 3 when DetectTextureParams::surface_normals, else empty: the unit
  /// normal at p_i of the same nearest model (the underlying surface's normal
  /// under texture: the base of a bump, not its flank), signed like p_i's
  /// normal when normals are given (like the normals of the points the
  /// models hold where p_i's is within 30° of the model's plane, as on a
  /// flank turning past 90°); zero where no plane was found.
  Normals surface_normal;
  std::size_t texture_points = 0;
  std::size_t no_plane = 0;      ///< neighborhoods with fewer than 3 points or collinear
  double mean_iterations = 0.0;  ///< RANSAC tries per neighborhood
};

/// Classify every point as texture or underlying surface (Eq. 2). Deterministic
/// for any thread count. Throws std::invalid_argument on out-of-range params.
TextureDetection detect_texture(const Positions& P, const Neighborhoods& R,
                                const DetectTextureParams& params, const ProgressFn& progress = {});

/// The same with the points' normals N (#P by 3, or 0 rows for none), which
/// the quadric surface uses to tell curvature from texture (see above).
TextureDetection detect_texture(const Positions& P, const Normals& N, const Neighborhoods& R,
                                const DetectTextureParams& params, const ProgressFn& progress = {});

/// Hard Ω weights from labels: ω = 0 for texture, 1 otherwise (#P).
std::vector<float> hard_omega(const std::vector<std::uint8_t>& is_texture);

/// Check params; throws std::invalid_argument with a sentence naming the bad one.
void validate(const DetectTextureParams& params);

}  // namespace detexture
