#include "detexture/pipeline/texture_fields.h"

#include <stdexcept>
#include <string>
#include <vector>

namespace detexture {
namespace {

void check_sizes(const PointCloud& cloud, const RemoveTextureResult& result) {
  const auto n = static_cast<std::size_t>(result.positions.rows());
  if (cloud.size() != n || result.is_texture.size() != n ||
      static_cast<std::size_t>(result.texture_height.size()) != n)
    throw std::invalid_argument("the cloud has " + std::to_string(cloud.size()) +
                                " points but the result " + std::to_string(n) +
                                "; pass the cloud the result was computed from");
}

template <class Values>
void set_property(PointCloud& cloud, const std::string& name, ScalarType type,
                  const Values& values) {
  PointProperty* prop = nullptr;
  for (auto& e : cloud.extras)
    if (e.name == name) prop = &e;
  if (!prop) {
    cloud.extras.push_back({name, type, {}});
    prop = &cloud.extras.back();
  }
  prop->type = type;
  prop->values.assign(values.begin(), values.end());
}

void set_texture_height(PointCloud& cloud, const RemoveTextureResult& result) {
  const Eigen::VectorXd& h = result.texture_height;
  set_property(cloud, "texture_height", ScalarType::Float32,
               std::vector<double>(h.data(), h.data() + h.size()));
}

}  // namespace

void add_texture_fields(PointCloud& cloud, const RemoveTextureResult& result) {
  check_sizes(cloud, result);
  set_property(cloud, "texture", ScalarType::UInt8, result.is_texture);
  set_texture_height(cloud, result);
}

PointCloud detextured_cloud(const PointCloud& input, const RemoveTextureResult& result,
                            bool texture_fields) {
  check_sizes(input, result);
  PointCloud out = input;
  out.positions = result.positions;
  out.normals = result.normals;
  if (texture_fields) add_texture_fields(out, result);
  return out;
}

PointCloud texture_layer(const PointCloud& input, const RemoveTextureResult& result) {
  check_sizes(input, result);
  PointCloud layer = input;
  layer.normals = result.input_normals;
  set_texture_height(layer, result);
  return layer;
}

}  // namespace detexture
