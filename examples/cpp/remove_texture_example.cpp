// Remove the texture from a point cloud file with the detexture library:
//   remove_texture_example INPUT OUTPUT [THREADS]
// writes OUTPUT with per-point "texture" and "texture_height" fields.
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <utility>

#include <detexture/io/read_point_cloud.h>
#include <detexture/io/write_point_cloud.h>
#include <detexture/pipeline/remove_texture.h>
#include <detexture/pipeline/texture_fields.h>

int main(int argc, char** argv) {
  if (argc < 3) {
    std::fprintf(stderr, "usage: %s INPUT OUTPUT [THREADS]\n", argv[0]);
    return 2;
  }
  try {
    const detexture::PointCloud cloud = detexture::read_point_cloud(argv[1]);

    detexture::RemoveTextureParams params;  // the defaults of the command line
    params.radius = detexture::parse_length("0.02d");
    params.threads = argc > 3 ? std::atoi(argv[3]) : 0;  // 0: all cores
    detexture::RemoveTextureResult result =
        detexture::remove_texture(cloud.positions, cloud.normals, params);

    detexture::write_point_cloud(argv[2], detexture::detextured_cloud(cloud, result, true));
    std::printf("%zu points, r = %g: %zu texture points, mean move %g\n", cloud.size(),
                result.report.radius, result.report.texture_points,
                result.report.mean_displacement);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "error: %s\n", e.what());
    return 1;
  }
  return 0;
}
