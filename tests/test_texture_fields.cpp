// The clouds a run gives back to a file (texture_fields.h): what
// --texture-fields and --texture-layer write.
#include "detexture/pipeline/texture_fields.h"

#include <gtest/gtest.h>

#include <stdexcept>

namespace detexture {
namespace {

// Two points with a colour; a result that moved the second one down by 0.25.
struct Case {
  PointCloud input;
  RemoveTextureResult result;
};
Case two_points() {
  Case c;
  c.input.positions.resize(2, 3);
  c.input.positions << 0, 0, 0, 1, 0, 0.25;
  c.input.extras.push_back({"red", ScalarType::UInt8, {10, 20}});
  c.input.comments = {"made by hand"};
  c.result.positions.resize(2, 3);
  c.result.positions << 0, 0, 0, 1, 0, 0;
  c.result.normals.resize(2, 3);
  c.result.normals << 0, 0, 1, 0, 0, 1;
  c.result.input_normals.resize(2, 3);
  c.result.input_normals << 0, 0, 1, 0, 1, 0;
  c.result.is_texture = {0, 1};
  c.result.texture_height.resize(2);
  c.result.texture_height << 0.0, 0.25;
  return c;
}

const PointProperty* find(const PointCloud& c, const std::string& name) {
  for (const auto& e : c.extras)
    if (e.name == name) return &e;
  return nullptr;
}

TEST(TextureFields, DetexturedCloudCarriesTheInputAndTheFields) {
  const Case c = two_points();
  const PointCloud plain = detextured_cloud(c.input, c.result);
  EXPECT_TRUE(plain.positions == c.result.positions);
  EXPECT_TRUE(plain.normals == c.result.normals);
  ASSERT_EQ(plain.extras.size(), 1u);  // only the input's colour
  EXPECT_EQ(plain.comments, c.input.comments);

  const PointCloud out = detextured_cloud(c.input, c.result, true);
  const PointProperty* texture = find(out, "texture");
  const PointProperty* height = find(out, "texture_height");
  ASSERT_TRUE(texture && height);
  EXPECT_EQ(texture->type, ScalarType::UInt8);
  EXPECT_EQ(texture->values, (std::vector<double>{0, 1}));
  EXPECT_EQ(height->type, ScalarType::Float32);
  EXPECT_EQ(height->values, (std::vector<double>{0.0, 0.25}));
  EXPECT_EQ(find(out, "red")->values, (std::vector<double>{10, 20}));
}

TEST(TextureFields, FieldsAlreadyPresentAreOverwrittenNotRepeated) {
  Case c = two_points();
  c.input.extras.push_back({"texture", ScalarType::Float64, {7, 7}});
  const PointCloud out = detextured_cloud(c.input, c.result, true);
  int count = 0;
  for (const auto& e : out.extras) count += e.name == "texture";
  EXPECT_EQ(count, 1);
  EXPECT_EQ(find(out, "texture")->type, ScalarType::UInt8);
  EXPECT_EQ(find(out, "texture")->values, (std::vector<double>{0, 1}));
}

TEST(TextureFields, TextureLayerIsTheInputWithItsHeight) {
  const Case c = two_points();
  const PointCloud layer = texture_layer(c.input, c.result);
  EXPECT_TRUE(layer.positions == c.input.positions);
  EXPECT_TRUE(layer.normals == c.result.input_normals);
  EXPECT_EQ(find(layer, "texture_height")->values, (std::vector<double>{0.0, 0.25}));
  EXPECT_EQ(find(layer, "texture"), nullptr);
}

TEST(TextureFields, SizeMismatchIsRefused) {
  Case c = two_points();
  c.input.positions.conservativeResize(1, 3);
  c.input.extras.clear();
  EXPECT_THROW(detextured_cloud(c.input, c.result, true), std::invalid_argument);
  EXPECT_THROW(texture_layer(c.input, c.result), std::invalid_argument);
}

}  // namespace
}  // namespace detexture
