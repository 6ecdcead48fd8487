// The clouds a run of remove_texture gives back to a file: the detextured
// cloud, optionally carrying what Eq. 2 found as per-point fields, and the
// texture layer (the input with the height of the texture removed). What the
// command line's --texture-fields and --texture-layer write.
#pragma once

#include "detexture/io/point_cloud.h"
#include "detexture/pipeline/remove_texture.h"

namespace detexture {

/// Add (or overwrite) the per-point properties "texture" (uint8, 1 where Eq.
/// 2 labelled the point texture) and "texture_height" (float32, the signed
/// displacement removed along the output normal, result.texture_height) to
/// `cloud`, which must have as many points as the result. CloudCompare and
/// MeshLab show them as scalar fields. Throws std::invalid_argument on a size
/// mismatch.
void add_texture_fields(PointCloud& cloud, const RemoveTextureResult& result);

/// `input` (its extras, other elements and comments) with the result's
/// positions and normals; with `texture_fields`, also add_texture_fields.
/// Throws std::invalid_argument when the sizes differ.
PointCloud detextured_cloud(const PointCloud& input, const RemoveTextureResult& result,
                            bool texture_fields = false);

/// The texture layer: `input` at its own positions, with the normals the
/// filters started from (result.input_normals) and the "texture_height"
/// property (float32): the texture alone, as a scalar field on the input.
/// Throws std::invalid_argument when the sizes differ.
PointCloud texture_layer(const PointCloud& input, const RemoveTextureResult& result);

}  // namespace detexture
