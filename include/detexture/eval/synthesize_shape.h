// Synthetic textured point clouds whose underlying surface is known exactly:
// the ground truth for measuring texture removal (the paper's Table 3 needs
// one, and real scans with a known underlying shape are rare).
//
// A base shape B (sphere, cube, ...) carries a height field h: the textured
// surface is p = b + h(b) n(b) for b on B, with n the outward unit normal of
// B. Points are sampled uniformly by area on B and then displaced, so the
// density is that of the base surface (like a scanner looking along n).
// Every sample keeps its exact h, its exact normal and its base point b.
//
// Sharp edges (cube, pyramid, the rims of the cylinder) and the border of the
// plane patch split the base into patches. Each feature belongs to one patch
// and h = 0 within `size` of every patch border, so next to an edge the
// textured surface coincides with B and the underlying surface is well
// defined. docs/synth_and_compare.md gives every formula.
//
// The shapes after Plane (ellipsoid, saddle, knot, blob, disc, mesh) are one
// patch each and have thin parts or close passes (the disc's two sheets 0.06
// apart, neighbouring strands of the knot, legs and ears of a mesh). There a
// feature must not reach through to the other side, so on these shapes a
// feature centred at c with base normal n_c acts on a point b only as far as
// n(b).n_c > 0: bumps and domes are multiplied by a C1 weight that is 1 for
// n(b).n_c >= 1/2 and 0 for n(b).n_c <= 0, dart throwing lets centres with
// n_i.n_j <= 0 come closer than the spacing, and scale cells are Voronoi cells
// of the lifted points (b, 2R n(b)). The older shapes keep their exact former
// output (on them the weight is always 1).
#pragma once

#include <cstdint>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "detexture/io/point_cloud.h"
#include "detexture/types.h"

namespace detexture {

/// Base shapes, all centered at the origin and fitting the box [-0.5, 0.5]^3
/// (except Mesh, whose coordinates are used as given).
enum class BaseShape : std::uint8_t {
  Sphere,     ///< radius 0.5
  Cube,       ///< side 1, axis-aligned; 6 patches
  Cylinder,   ///< radius 0.5, height 1 along z, closed by two flat caps; 3 patches
  Torus,      ///< major radius 0.35, tube radius 0.15, around the z axis
  Pyramid,    ///< square base of side 1 at z = -0.5, apex (0, 0, 0.5); 5 patches
  Plane,      ///< the square [-0.5, 0.5]^2 at z = 0, normal +z
  Ellipsoid,  ///< semi-axes (0.5, 0.32, 0.2) along x, y, z
  Saddle,     ///< z = 0.6 (x^2 - y^2) over the disk x^2 + y^2 <= 0.25, normal up; open
  Knot,       ///< tube of radius 0.07 around a trefoil (docs give the curve)
  Blob,       ///< star-shaped body with 6 limbs, r(d) = 0.22 + sum L_k exp((d.a_k - 1)/w_k)
  Disc,       ///< flat disc of radius 0.4, thickness 0.06, rim a half-torus of radius 0.03
  Mesh,       ///< the triangle mesh SynthParams::mesh, used as it is (face normals)
};

/// A triangle mesh used as the base surface (BaseShape::Mesh). Triangles are
/// counter-clockwise seen from the side their normal points to (the outside
/// for a consistently oriented closed mesh). Degenerate triangles (zero area,
/// relative to the longest edge) are skipped when the shape is built.
struct BaseMesh {
  Positions vertices;                                                         ///< #V by 3
  Eigen::Matrix<std::int32_t, Eigen::Dynamic, 3, Eigen::RowMajor> triangles;  ///< #T by 3 rows of V
};

/// The triangles of a cloud read from a PLY file with a "face" element whose
/// list property is vertex_indices or vertex_index (as read_point_cloud keeps
/// it in other_elements); polygons are fan-triangulated (v0, vi, vi+1).
/// Throws std::invalid_argument with a sentence when there is no face
/// element, no such list, an index out of range, or no triangle at all.
BaseMesh base_mesh_from_cloud(const PointCloud& cloud);

/// Height fields. A is `amplitude`, R is `size`; d is the 3D distance from b
/// to a feature center; u = k.b with k = (1, 2, 3)/sqrt(14) for the line
/// textures.
enum class TextureKind : std::uint8_t {
  None,        ///< h = 0: the clean base shape
  Bumps,       ///< A exp(-2 s) (1 - s)^2, s = d^2/R^2 < 1: a Gaussian cut off smoothly at R
  Domes,       ///< A sqrt(1 - s): hemispheres of radius R when A = R (ellipsoidal caps otherwise)
  Scales,      ///< Voronoi cells rising as A (1 - (1 - t)^2) with the distance t to the cell border
  Waves,       ///< parallel ridges A (1 + cos(pi v/R))/2, |v| < R: a sinusoid when dense
  VGrooves,    ///< parallel grooves -A (1 - |v|/R), |v| < R
  UGrooves,    ///< parallel grooves -A sqrt(1 - (v/R)^2), |v| < R
  MultiScale,  ///< Bumps of (R, A) plus Bumps of (R/3, A/3) placed independently; heights add
};

/// How densely features cover the surface.
enum class TextureLayout : std::uint8_t {
  Sparse,  ///< separated features: bump centers >= 3R apart, ridge period 4R, scale channels R wide
  Dense,   ///< touching features: bump centers >= 2R apart, ridge period 2R, no channels
};

/// Parse the command-line names ("sphere", "v-grooves", "dense", ...); throw
/// std::invalid_argument listing the valid names for anything else.
BaseShape parse_base_shape(const std::string& name);
TextureKind parse_texture_kind(const std::string& name);
TextureLayout parse_texture_layout(const std::string& name);
const char* base_shape_name(BaseShape shape);
const char* texture_kind_name(TextureKind texture);
const char* texture_layout_name(TextureLayout layout);

struct SynthParams {
  BaseShape shape = BaseShape::Cube;
  TextureKind texture = TextureKind::Bumps;
  TextureLayout layout = TextureLayout::Sparse;
  /// R: feature radius (bumps, domes), ridge or groove half-width, or scale
  /// cell radius, in model units (the base fits a unit box); [0.005, 0.1].
  /// Also the margin kept free of texture along edges and borders.
  double size = 0.05;
  /// A: peak height along the outward normal, in model units; |A| <= size
  /// (multiscale heights add up to 4A/3).
  /// Negative values press the texture into the surface (grooves with A < 0
  /// become ridges).
  double amplitude = 0.02;
  /// Give each feature (bump, cell, ridge, groove) a random sign, so the
  /// surface has bumps up and down (the paper's "BUDs").
  bool mixed_signs = false;
  std::int64_t points = 100000;               ///< textured samples; [1, 2^31)
  std::int64_t ground_truth_points = 200000;  ///< samples of the clean base surface; [1, 2^31)
  /// Standard deviation of Gaussian noise added to each coordinate of the
  /// textured positions (normals and heights stay noise-free), as a fraction
  /// of the base shape's bounding-box diagonal (or absolute, see below);
  /// [0, 0.1] as a fraction, >= 0 when absolute.
  double noise = 0.0;
  bool noise_absolute = false;  ///< read `noise` in model units instead
  std::uint64_t seed = 1;       ///< same seed, same cloud, on any thread count
  /// The base surface when shape == BaseShape::Mesh (required then, ignored
  /// otherwise); shared so that copies of the params stay cheap.
  std::shared_ptr<const BaseMesh> mesh;
};

/// |h| above which a sample counts as texture, in model units.
constexpr double kTextureHeightEpsilon = 1e-13;

struct SynthesizedShape {
  Positions positions;  ///< #P by 3 textured samples b + h n (+ noise)
  /// #P by 3 exact unit normals of the textured surface at b + h n, from the
  /// first fundamental form of the displaced surface (docs), noise-free.
  Normals normals;
  std::vector<double> texture_heights;   ///< #P signed heights h(b)
  std::vector<std::uint8_t> is_texture;  ///< #P: 1 where |h| > kTextureHeightEpsilon
  Positions base_positions;              ///< #P by 3 base points b (on the analytic shape)
  Normals base_normals;                  ///< #P by 3 outward normals of the base at b
  Positions ground_truth_positions;      ///< #G by 3 samples of the clean base surface
  Normals ground_truth_normals;          ///< #G by 3 their outward normals
  std::size_t feature_count = 0;         ///< bumps, domes or cells placed (0 for line textures)
  Positions feature_centers;             ///< feature_count by 3 centres on the base (all sets)
  Normals feature_normals;               ///< feature_count by 3 base normals at the centres
  double area = 0.0;                     ///< area of the base surface
  double diagonal = 0.0;                 ///< bounding-box diagonal of the base shape
  std::size_t degenerate_triangles = 0;  ///< mesh base: zero-area triangles skipped
  double noise_sigma = 0.0;              ///< the noise standard deviation used, in model units
};

/// Throw std::invalid_argument with a sentence naming the parameter, its
/// value and its valid range when params are out of range.
void validate_synth_params(const SynthParams& params);

/// Sample the textured shape and its ground truth. Validates params first.
SynthesizedShape synthesize_shape(const SynthParams& params);

/// synthesize_shape for clouds too large to hold: the textured points go to
/// `points` in blocks of at most `block` (positions, normals,
/// texture_heights and is_texture of rows 0.. filled; `first` is the index
/// of row 0), then the ground truth to `ground_truth` the same way
/// (ground_truth_positions, ground_truth_normals). The values are those of
/// synthesize_shape bit for bit, since every point is seeded by its index.
/// Returns the summary fields (feature_count, feature centres, area,
/// diagonal, noise_sigma, degenerate_triangles).
SynthesizedShape synthesize_shape_blocks(
    const SynthParams& params, std::int64_t block,
    const std::function<void(const SynthesizedShape& block, std::int64_t first)>& points,
    const std::function<void(const SynthesizedShape& block, std::int64_t first)>& ground_truth);

struct TexturedSamples {
  Positions positions;          ///< #B by 3 b + h(b) n(b)
  Normals normals;              ///< #B by 3 exact normals of the textured surface
  std::vector<double> heights;  ///< #B heights h(b)
};

/// Evaluate the textured surface of params at points B (#B by 3) lying on the
/// base shape (within ~1e-9; each is assigned to the patch it lies on). The
/// features are those synthesize_shape(params) places, so this reproduces
/// its samples; it exists to test normals against finite differences and to
/// probe the surface anywhere.
TexturedSamples evaluate_texture(const SynthParams& params, const Positions& B);

}  // namespace detexture
