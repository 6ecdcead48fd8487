// A small case of the ground-truth quality benchmark (bench/quality), run
// through the library: synthesize a textured cube, remove the texture with the
// benchmark's parameter rule (r = σs = 1.5 R, everything else at its default),
// and score the result against the exact underlying cube.
#include <gtest/gtest.h>

#include "detexture/eval/compare_to_ground_truth.h"
#include "detexture/eval/synthesize_shape.h"
#include "detexture/pipeline/remove_texture.h"

namespace detexture {
namespace {

// Separated bumps on a cube: the texture is known exactly and stays R away
// from the edges, so the clean cube is the answer.
SynthesizedShape small_textured_cube() {
  SynthParams sp;
  sp.shape = BaseShape::Cube;
  sp.texture = TextureKind::Bumps;
  sp.layout = TextureLayout::Sparse;
  sp.size = 0.06;       // R
  sp.amplitude = 0.02;  // A: well above the default λ = 0.002 d ≈ 0.0035
  sp.points = 25000;    // ≈ 110 neighbours within r = 1.5 R
  sp.ground_truth_points = 60000;
  sp.seed = 1;
  return synthesize_shape(sp);
}

// bench/README.md: r = 1.5 R, σs = r, all other parameters at their defaults.
RemoveTextureParams benchmark_rule(double feature_size) {
  RemoveTextureParams p;
  p.radius = {1.5 * feature_size, Length::Unit::Absolute};
  p.sigma_s = {1.5 * feature_size, Length::Unit::Absolute};
  return p;
}

class QualitySmoke : public ::testing::Test {
 protected:
  // One synthesis and one run of the full method, shared by the tests.
  static void SetUpTestSuite() {
    shape_ = new SynthesizedShape(small_textured_cube());
    full_ = new RemoveTextureResult(
        remove_texture(shape_->positions, shape_->normals, benchmark_rule(0.06)));
  }
  static void TearDownTestSuite() {
    delete full_;
    delete shape_;
    full_ = nullptr;
    shape_ = nullptr;
  }
  static GroundTruthComparison score(const Positions& P, const Normals& N) {
    return compare_to_ground_truth(P, N, shape_->ground_truth_positions,
                                   shape_->ground_truth_normals);
  }
  static SynthesizedShape* shape_;
  static RemoveTextureResult* full_;
};
SynthesizedShape* QualitySmoke::shape_ = nullptr;
RemoveTextureResult* QualitySmoke::full_ = nullptr;

TEST_F(QualitySmoke, RemovesAtLeastHalfTheTextureHeight) {
  const SynthesizedShape& s = *shape_;
  // The input's signed distances to the cube are the bump heights themselves,
  // so their standard deviation is the texture's RMS height (about its mean).
  const GroundTruthComparison in = score(s.positions, s.normals);
  ASSERT_GT(in.std_signed_distance, 0.002) << "the synthesized texture is too faint to test";

  const GroundTruthComparison out = score(full_->positions, full_->normals);
  EXPECT_LT(out.std_signed_distance, 0.5 * in.std_signed_distance)
      << "residual texture " << out.std_signed_distance << " vs input " << in.std_signed_distance;
  // Normals closer to the cube's than the input's. (Dmean is not checked: on
  // sparse bumps most input points lie exactly on the cube, so the input's
  // Dmean is already small and any smoothing of the flat part raises it.)
  EXPECT_LT(out.mean_angle_degrees, in.mean_angle_degrees);
}

TEST_F(QualitySmoke, SubNeighborhoodBeatsPlainGaussianOnNormals) {
  const SynthesizedShape& s = *shape_;
  RemoveTextureParams plain = benchmark_rule(0.06);  // paper Fig. 4: filter over all of R_i
  plain.gaussian.use_subneighborhood = false;
  plain.rolling.use_subneighborhood = false;

  const RemoveTextureResult b = remove_texture(s.positions, s.normals, plain);
  const GroundTruthComparison ca = score(full_->positions, full_->normals);
  const GroundTruthComparison cb = score(b.positions, b.normals);
  EXPECT_LT(ca.mean_angle_degrees, cb.mean_angle_degrees)
      << "full method " << ca.mean_angle_degrees << "°, plain Gaussian " << cb.mean_angle_degrees
      << "°";
}

}  // namespace
}  // namespace detexture
