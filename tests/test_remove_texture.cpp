// The whole method on shapes with known answers (Sun et al. 2019, Fig. 5
// setting: separated bumps on a sphere and a cube).
#include "detexture/pipeline/remove_texture.h"

#include <gtest/gtest.h>
#include <omp.h>

#include <array>
#include <cmath>
#include <memory>
#include <vector>

#include "detexture/eval/synthesize_shape.h"
#include "test_support.h"

namespace detexture {
namespace {

RemoveTextureParams params_for(double radius, double lambda) {
  RemoveTextureParams p;
  p.radius = {radius, Length::Unit::Absolute};
  p.lambda = {lambda, Length::Unit::Absolute};
  return p;
}

// Height of each output point above the base surface, along the base normal
// (exact on flat faces).
Eigen::VectorXd height_above_base(const Positions& out, const SynthesizedShape& s) {
  return (out - s.base_positions).cwiseProduct(s.base_normals).rowwise().sum();
}

double rms(const Eigen::VectorXd& v) { return std::sqrt(v.squaredNorm() / v.size()); }

// A textured shape of `points` points with default texture (and a token
// ground truth: these tests compare runs, not against the truth).
SynthesizedShape small_shape(BaseShape shape, int points) {
  SynthParams sp;
  sp.shape = shape;
  sp.points = points;
  sp.ground_truth_points = 10;
  return synthesize_shape(sp);
}

TEST(RemoveTexture, BumpOnPlaneGoesBackToThePlane) {
  const auto s = test::bumpy_plane(101, 0.03, 0.015);
  const RemoveTextureResult r = remove_texture(s.P, s.N, params_for(0.06, 0.002));
  for (int i = 0; i < s.P.rows(); ++i)
    if (s.height(i) > 0.004) EXPECT_TRUE(r.is_texture[i]) << "point " << i;
  // Within a tenth of the bump's height everywhere; the border rows, whose
  // neighborhoods are half empty, included.
  EXPECT_LT(r.positions.col(2).cwiseAbs().maxCoeff(), 0.003);
  double bump_in = 0.0, bump_out = 0.0;
  for (int i = 0; i < s.P.rows(); ++i)
    if (s.height(i) > 0.003) {
      bump_in += s.height(i) * s.height(i);
      bump_out += r.positions(i, 2) * r.positions(i, 2);
    }
  EXPECT_LT(std::sqrt(bump_out), 0.1 * std::sqrt(bump_in));
  // texture_height is what was removed.
  EXPECT_LT((r.texture_height - (s.P.col(2) - r.positions.col(2))).cwiseAbs().maxCoeff(), 1e-3);
}

// Creases at the defaults: a plane folded by 75°, 90° and 105°, no texture.
// The rolling filter alone would leave them blurred at the default σr
// (FilterNormalsRolling.RecoversCreaseBlurredByGaussian); the surface split
// parts the two faces' neighborhoods, so every normal off the crease line is
// its face's, with the filtered output normals as with the default blend.
// Without the split (the paper's R_i) the crease blurs; σr = 30° brings the
// 90° and 105° creases back.
TEST(RemoveTexture, FoldKeepsItsCreaseAtTheDefaults) {
  for (const double fold : {75.0, 90.0, 105.0}) {
    SCOPED_TRACE("fold " + std::to_string(fold));
    const auto s = test::folded_plane(81, fold);
    auto worst_error = [&](const RemoveTextureParams& p) {
      const RemoveTextureResult r = remove_texture(s.P, s.N, p);
      double worst = 0.0;
      for (int i = 0; i < s.P.rows(); ++i)
        if (std::abs(s.P(i, 0) - 0.5) >= 0.005)
          worst = std::max(worst, test::angle_deg(r.normals.row(i), s.N.row(i)));
      return worst;
    };
    RemoveTextureParams p = params_for(0.06, 0.003);
    EXPECT_LT(worst_error(p), 1.0) << "defaults";
    p.fit_normals = false;
    EXPECT_LT(worst_error(p), 1.0) << "filtered output normals";
    p.surface_split.max_angle_deg = 180.0;
    EXPECT_GT(worst_error(p), 5.0) << "filtered output normals, no split";
    p.rolling.sigma_r_deg = 30.0;
    if (fold >= 90.0) EXPECT_LT(worst_error(p), 3.0) << "σr 30°, filtered, no split";
  }
}

// A thin plate: the bumpy sheet above (bump 0.02 high, 0.015 wide) and a flat
// sheet 0.03 below facing down. r = 0.06 reaches through, so without
// separating the sheets every filter averages opposite normals and the
// position update pulls the sheets together; with it each sheet is as if
// alone: back to z = 0 and z = -0.03, normals +z and -z.
TEST(RemoveTexture, ThinPlateKeepsBothSheets) {
  const auto top = test::bumpy_plane(81, 0.02, 0.015);
  const Eigen::Index n = top.P.rows();
  Positions P(2 * n, 3);
  Normals N(2 * n, 3);
  P.topRows(n) = top.P;
  N.topRows(n) = top.N;
  for (Eigen::Index i = 0; i < n; ++i) {
    P.row(n + i) << top.P(i, 0), top.P(i, 1), -0.03;
    N.row(n + i) << 0, 0, -1;
  }
  auto worst = [&](const RemoveTextureResult& r) {
    double dz = 0.0, angle = 0.0;
    for (Eigen::Index i = 0; i < 2 * n; ++i) {
      const bool upper = i < n;
      const double x = P(i, 0), y = P(i, 1);
      if (std::min({x, y, 1 - x, 1 - y}) < 0.1) continue;  // half-empty border rows
      dz = std::max(dz, std::abs(r.positions(i, 2) - (upper ? 0.0 : -0.03)));
      angle = std::max(angle,
                       test::angle_deg(r.normals.row(i), Eigen::RowVector3d(0, 0, upper ? 1 : -1)));
    }
    return std::pair<double, double>(dz, angle);
  };
  RemoveTextureParams p = params_for(0.06, 0.002);
  const auto [dz, angle] = worst(remove_texture(P, N, p));
  EXPECT_LT(dz, 0.002);
  EXPECT_LT(angle, 2.5);
  // The split after texture detection (drop_neighbors_across_surfaces.h)
  // alone keeps the filters on their own sheet (detection has already
  // fitted its models across both, so the positions need the first split).
  // The normals read are the blend's own (blend_share_high 0): with the
  // open window, a bump left in the positions here tilts the worst by 7.7°.
  p.sheets.max_angle_deg = 180.0;
  p.blend_share_high = 0.0;
  const RemoveTextureResult surface_only = remove_texture(P, N, p);
  EXPECT_GT(surface_only.report.surface_split_neighbors, 0u);
  const auto [surface_dz, surface_angle] = worst(surface_only);
  EXPECT_LT(surface_angle, 2.5);
  p.surface_split.max_angle_deg = 180.0;  // the paper: both sheets in R_i
  const auto [mixed_dz, mixed_angle] = worst(remove_texture(P, N, p));
  EXPECT_GT(mixed_dz, 2 * dz);
  EXPECT_GT(mixed_angle, 2 * angle);
  EXPECT_LT(surface_angle, mixed_angle / 2);
}

TEST(RemoveTexture, CubeLosesItsDomesAndKeepsSharpEdges) {
  SynthParams sp;
  sp.shape = BaseShape::Cube;
  sp.texture = TextureKind::Domes;
  sp.size = 0.05;
  sp.amplitude = 0.05;  // hemispheres
  sp.points = 40000;
  sp.ground_truth_points = 10;
  const SynthesizedShape s = synthesize_shape(sp);
  const RemoveTextureResult r = remove_texture(s.positions, s.normals, params_for(0.08, 0.004));

  const Eigen::VectorXd before = height_above_base(s.positions, s);
  const Eigen::VectorXd after = height_above_base(r.positions, s);
  EXPECT_LT(rms(after), 0.25 * rms(before)) << "the domes are gone";

  // Normals next to an edge (1.5 to 4 sample spacings away) stay within a few
  // degrees of their own face's normal. Closer in, a point may end up on the
  // other side of the recovered edge: its place is only known to a spacing.
  const double spacing = std::sqrt(6.0 / sp.points);
  double sum = 0.0;
  int count = 0, off = 0;
  for (int i = 0; i < s.positions.rows(); ++i) {
    Eigen::Vector3d a = s.base_positions.row(i).cwiseAbs();
    std::sort(a.data(), a.data() + 3);
    const double to_edge = 0.5 - a(1);
    if (to_edge < 1.5 * spacing || to_edge > 4 * spacing) continue;
    const double angle = test::angle_deg(r.normals.row(i), s.base_normals.row(i));
    sum += angle;
    off += angle > 10.0;
    ++count;
  }
  ASSERT_GT(count, 1000);
  EXPECT_LT(sum / count, 3.5);
  EXPECT_LT(off, count / 100) << "99% within 10 degrees";
}

TEST(RemoveTexture, SphereKeepsItsRadius) {
  SynthParams sp;
  sp.shape = BaseShape::Sphere;
  sp.texture = TextureKind::Bumps;
  sp.size = 0.05;
  sp.amplitude = 0.02;
  sp.points = 20000;
  sp.ground_truth_points = 10;
  const SynthesizedShape s = synthesize_shape(sp);
  const RemoveTextureResult r = remove_texture(s.positions, s.normals, params_for(0.08, 0.003));
  const double mean_radius = r.positions.rowwise().norm().mean();
  EXPECT_NEAR(mean_radius, 0.5, 0.5e-3) << "within 0.1% of the underlying sphere";
  const Eigen::VectorXd before = s.positions.rowwise().norm().array() - 0.5;
  const Eigen::VectorXd after = r.positions.rowwise().norm().array() - 0.5;
  EXPECT_LT(rms(after), 0.5 * rms(before));
}

TEST(RemoveTexture, IdenticalForAnyThreadCount) {
  const SynthesizedShape s = small_shape(BaseShape::Cube, 20000);
  const RemoveTextureParams p = params_for(0.08, 0.004);
  omp_set_num_threads(1);
  const RemoveTextureResult a = remove_texture(s.positions, Normals(), p);
  omp_set_num_threads(2);
  const RemoveTextureResult b = remove_texture(s.positions, Normals(), p);
  EXPECT_TRUE(a.positions == b.positions);
  EXPECT_TRUE(a.normals == b.normals);
  EXPECT_EQ(a.is_texture, b.is_texture);
  EXPECT_TRUE(a.report.normals_estimated);
}

// ignore_input_normals runs as if the cloud had none: normals turned at
// random give the same result as no normals at all, and a different one
// without the option.
TEST(RemoveTexture, IgnoredInputNormalsAreEstimatedFromThePositions) {
  const SynthesizedShape s = small_shape(BaseShape::Cube, 8000);
  Normals scrambled = s.normals;
  for (Eigen::Index i = 0; i < scrambled.rows(); ++i)
    scrambled.row(i) = Eigen::RowVector3d(std::sin(3.0 * i), std::cos(5.0 * i), 0.5).normalized();
  RemoveTextureParams p = params_for(0.08, 0.004);
  const RemoveTextureResult none = remove_texture(s.positions, Normals(), p);
  const RemoveTextureResult kept = remove_texture(s.positions, scrambled, p);
  p.ignore_input_normals = true;
  const RemoveTextureResult ignored = remove_texture(s.positions, scrambled, p);
  EXPECT_TRUE(ignored.positions == none.positions);
  EXPECT_TRUE(ignored.normals == none.normals);
  EXPECT_TRUE(ignored.input_normals == none.input_normals);
  EXPECT_FALSE(kept.positions == none.positions) << "the scrambled normals matter without it";
  EXPECT_TRUE(ignored.report.normals_ignored);
  EXPECT_TRUE(ignored.report.normals_estimated);
  EXPECT_FALSE(kept.report.normals_ignored);
  EXPECT_FALSE(none.report.normals_ignored) << "nothing to ignore";
}

// Positions and normals moved in come back unchanged, in the caller's order.
TEST(RemoveTexture, HandsTheInputBack) {
  const SynthesizedShape s = small_shape(BaseShape::Sphere, 5000);
  Positions P = s.positions;
  Normals N = s.normals;
  const RemoveTextureResult r = remove_texture(std::move(P), std::move(N), params_for(0.15, 0.004));
  EXPECT_TRUE(r.input_positions == s.positions);
  EXPECT_TRUE(r.input_normals.isApprox(s.normals, 1e-12));
  EXPECT_EQ(r.positions.rows(), s.positions.rows());
}

// An icosahedron's faces split in four and pushed out to the sphere of
// radius 0.5: 80 flat facets about 0.3 across, meeting at edges that turn by
// about 20°, a low-poly base like the spot check's coarse models.
std::shared_ptr<const BaseMesh> faceted_ball() {
  const double t = (1.0 + std::sqrt(5.0)) / 2.0;
  std::vector<Eigen::Vector3d> v = {{-1, t, 0}, {1, t, 0}, {-1, -t, 0}, {1, -t, 0},
                                    {0, -1, t}, {0, 1, t}, {0, -1, -t}, {0, 1, -t},
                                    {t, 0, -1}, {t, 0, 1}, {-t, 0, -1}, {-t, 0, 1}};
  const int faces[20][3] = {{0, 11, 5}, {0, 5, 1},  {0, 1, 7},   {0, 7, 10}, {0, 10, 11},
                            {1, 5, 9},  {5, 11, 4}, {11, 10, 2}, {10, 7, 6}, {7, 1, 8},
                            {3, 9, 4},  {3, 4, 2},  {3, 2, 6},   {3, 6, 8},  {3, 8, 9},
                            {4, 9, 5},  {2, 4, 11}, {6, 2, 10},  {8, 6, 7},  {9, 8, 1}};
  std::vector<std::array<int, 3>> tris;
  const auto middle = [&](int a, int b) {
    v.push_back((v[a] + v[b]) / 2.0);
    return static_cast<int>(v.size()) - 1;
  };
  for (const auto& f : faces) {
    const int ab = middle(f[0], f[1]), bc = middle(f[1], f[2]), ca = middle(f[2], f[0]);
    tris.push_back({f[0], ab, ca});
    tris.push_back({f[1], bc, ab});
    tris.push_back({f[2], ca, bc});
    tris.push_back({ab, bc, ca});
  }
  auto mesh = std::make_shared<BaseMesh>();
  mesh->vertices.resize(static_cast<Eigen::Index>(v.size()), 3);
  for (std::size_t i = 0; i < v.size(); ++i)
    mesh->vertices.row(static_cast<Eigen::Index>(i)) = 0.5 * v[i].normalized().transpose();
  mesh->triangles.resize(static_cast<Eigen::Index>(tris.size()), 3);
  for (std::size_t k = 0; k < tris.size(); ++k)
    mesh->triangles.row(static_cast<Eigen::Index>(k)) << tris[k][0], tris[k][1], tris[k][2];
  return mesh;
}

// The faceted ball with `texture` (R 0.04, amplitude A, 8000 points), run at
// r = 0.06 with update_input_normals on (held) and off (filtered).
struct HeldAndFiltered {
  SynthesizedShape shape;
  RemoveTextureResult held, filtered;
};

HeldAndFiltered faceted_ball_runs(TextureKind texture, double amplitude) {
  SynthParams sp;
  sp.shape = BaseShape::Mesh;
  sp.mesh = faceted_ball();
  sp.texture = texture;
  sp.size = 0.04;
  sp.amplitude = amplitude;
  sp.points = 8000;
  sp.ground_truth_points = 10;
  HeldAndFiltered out;
  out.shape = synthesize_shape(sp);
  RemoveTextureParams p;
  p.radius = {0.06, Length::Unit::Absolute};
  p.threads = 2;
  out.held = remove_texture(out.shape.positions, out.shape.normals, p);
  p.update_input_normals = false;
  out.filtered = remove_texture(out.shape.positions, out.shape.normals, p);
  return out;
}

// The update fits the exact input normals of facets that the filters round
// (update_input_normals): on a faceted ball with separated bumps, the points
// the texture never touched stay closer to their facets (their height above
// the base is exact there), and so does the whole cloud; false is the
// update before (the filtered normals everywhere).
TEST(RemoveTexture, TheUpdateFitsExactFacetNormals) {
  const HeldAndFiltered r = faceted_ball_runs(TextureKind::Bumps, 0.015);
  const SynthesizedShape& s = r.shape;
  EXPECT_GT(r.held.report.input_normals_updated, s.positions.rows() / 4);
  EXPECT_EQ(r.filtered.report.input_normals_updated, 0u);
  const auto plain_rms = [&](const RemoveTextureResult& out) {
    const Eigen::VectorXd h = height_above_base(out.positions, s);
    double sum = 0.0;
    int count = 0;
    for (Eigen::Index i = 0; i < h.size(); ++i) {
      if (s.is_texture[static_cast<std::size_t>(i)]) continue;
      sum += h(i) * h(i);
      ++count;
    }
    return std::sqrt(sum / count);
  };
  EXPECT_LT(plain_rms(r.held), 0.9 * plain_rms(r.filtered));
  EXPECT_LT(rms(height_above_base(r.held.positions, s)),
            rms(height_above_base(r.filtered.positions, s)));
}

// ... except where the relief reads as sparse engraving (V grooves, whose
// flat walls are as exact as facets): there the update runs again with the
// filtered normals, and the output is the one without them.
TEST(RemoveTexture, SparseEngravingKeepsTheFilteredNormals) {
  const HeldAndFiltered r = faceted_ball_runs(TextureKind::VGrooves, 0.012);
  EXPECT_LE(r.held.report.relief_lean, -LimitCounterMovesParams().engraved_min_lean);
  EXPECT_EQ(r.held.report.input_normals_updated, 0u);
  EXPECT_TRUE(r.held.positions == r.filtered.positions);
  EXPECT_TRUE(r.held.normals == r.filtered.normals);
}

TEST(RemoveTexture, RejectsBadInput) {
  const auto s = test::bumpy_plane(11, 0.0, 0.1);
  RemoveTextureParams p = params_for(0.2, 0.01);
  EXPECT_THROW(remove_texture(Positions(0, 3), Normals(), p), std::invalid_argument);
  EXPECT_THROW(remove_texture(s.P, s.N.topRows(5), p), std::invalid_argument);
  Positions same(4, 3);
  same.setOnes();
  EXPECT_THROW(remove_texture(same, Normals(), p), std::invalid_argument);
  p.radius = parse_length("0.5r");
  EXPECT_THROW(remove_texture(s.P, s.N, p), std::invalid_argument);
  p.radius = parse_length("0.2");
  p.texture.delta = 1.5;
  EXPECT_THROW(remove_texture(s.P, s.N, p), std::invalid_argument);
}

TEST(Length, ParsesAbsoluteAndRelative) {
  EXPECT_DOUBLE_EQ(parse_length("0.5").resolve(10.0, 3.0), 0.5);
  EXPECT_DOUBLE_EQ(parse_length("0.02d").resolve(10.0, 3.0), 0.2);
  EXPECT_DOUBLE_EQ(parse_length("0.5r").resolve(10.0, 3.0), 1.5);
  EXPECT_EQ(to_string(parse_length("0.5r")), "0.5r");
  EXPECT_THROW(parse_length("abc"), std::invalid_argument);
  EXPECT_THROW(parse_length("-1"), std::invalid_argument);
  EXPECT_THROW(parse_length("0d"), std::invalid_argument);
  EXPECT_THROW(parse_length(""), std::invalid_argument);
  EXPECT_EQ(to_string(parse_length("0.02d")), "0.02d");
}

}  // namespace
}  // namespace detexture
