// detexture synth: write a textured point cloud whose underlying surface is
// known exactly, and a dense sample of that surface as ground truth.
#include <CLI/CLI.hpp>
#include <cmath>
#include <cstdio>
#include <exception>
#include <memory>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#include "commands.h"
#include "detexture/eval/synthesize_shape.h"
#include "detexture/io/output_file.h"
#include "detexture/io/ply_stream.h"
#include "detexture/io/read_point_cloud.h"
#include "detexture/io/write_point_cloud.h"

namespace detexture::app {
namespace {

template <class Enum>
std::vector<std::string> names(const char* (*to_name)(Enum), int count) {
  std::vector<std::string> v;
  for (int i = 0; i < count; ++i) v.emplace_back(to_name(static_cast<Enum>(i)));
  return v;
}

// "cube.ply" -> "cube.gt.ply"; the ".gt" goes before the last extension.
std::string ground_truth_path_for(const std::string& output) {
  const std::size_t slash = output.find_last_of("/\\");
  const std::size_t dot = output.find_last_of('.');
  if (dot == std::string::npos || (slash != std::string::npos && dot < slash))
    return output + ".gt";
  return output.substr(0, dot) + ".gt" + output.substr(dot);
}

std::string describe(const SynthParams& p, const std::string& base_mesh) {
  std::ostringstream s;
  s << "detexture synth shape=" << base_shape_name(p.shape);
  if (!base_mesh.empty()) s << " base_mesh=" << base_mesh;
  s << " texture=" << texture_kind_name(p.texture) << " layout=" << texture_layout_name(p.layout)
    << " size=" << p.size << " amplitude=" << p.amplitude << " mixed_signs=" << p.mixed_signs
    << " points=" << p.points << " ground_truth_points=" << p.ground_truth_points
    << " noise=" << p.noise << (p.noise_absolute ? " (absolute)" : " (of diagonal)")
    << " seed=" << p.seed;
  return s.str();
}

// A binary little-endian PLY written block by block: the same bytes as
// write_point_cloud would write for the whole cloud.
class BlockWriter {
 public:
  BlockWriter(const std::string& path, const PlyVertexLayout& layout)
      : file_(path), layout_(layout), path_(path) {
    const std::string header = ply_header_text(layout);
    put(header.data(), header.size());
  }
  void write(const Positions& P, const Normals& N, const std::vector<double>* heights,
             const std::vector<std::uint8_t>* labels) {
    const std::size_t size = layout_.record_size;
    buffer_.assign(size * static_cast<std::size_t>(P.rows()), 0);
    const bool normals = layout_.has_normals();
    for (Eigen::Index i = 0; i < P.rows(); ++i) {
      unsigned char* r = buffer_.data() + size * static_cast<std::size_t>(i);
      for (int d = 0; d < 3; ++d) {
        encode_field(layout_, d, P(i, d), r);
        if (normals) encode_field(layout_, 3 + d, N(i, d), r);
      }
      int f = normals ? 6 : 3;
      if (heights) encode_field(layout_, f++, (*heights)[static_cast<std::size_t>(i)], r);
      if (labels) encode_field(layout_, f, (*labels)[static_cast<std::size_t>(i)], r);
    }
    put(buffer_.data(), buffer_.size());
  }
  void commit() { file_.commit(); }

 private:
  void put(const void* data, std::size_t size) {
    if (std::fwrite(data, 1, size, file_.get()) != size)
      throw std::runtime_error("cannot write '" + path_ + "' (disk full?)");
  }
  OutputFile file_;
  PlyVertexLayout layout_;
  std::string path_;
  std::vector<unsigned char> buffer_;
};

}  // namespace

int run_synth(int argc, char** argv) {
  SynthParams params;
  std::string shape = base_shape_name(params.shape);
  std::string texture = texture_kind_name(params.texture);
  std::string layout = texture_layout_name(params.layout);
  std::string output, ground_truth, base_mesh;
  bool ascii = false;

  CLI::App app{
      "Write a point cloud of a base shape carrying a known surface texture, with exact normals\n"
      "and per-point texture_height / is_texture, plus a dense sample of the untextured base\n"
      "surface (the ground truth for 'detexture compare'). All shapes fit the box\n"
      "[-0.5, 0.5]^3; lengths are in those model units. See docs/synth_and_compare.md.",
      "detexture synth"};
  app.add_option("-o,--output", output,
                 "Textured cloud to write (.ply keeps texture_height and is_texture; .xyz "
                 "writes x y z nx ny nz)")
      ->required();
  app.add_option("--ground-truth", ground_truth,
                 "Where to write the ground truth [default: OUTPUT with .gt before the "
                 "extension, e.g. cube.gt.ply]");
  app.add_option("--shape", shape, "Base shape ('mesh' needs --base-mesh)")
      ->check(CLI::IsMember(names(base_shape_name, 12)))
      ->capture_default_str();
  app.add_option(
      "--base-mesh", base_mesh,
      "Use the triangle mesh of this file (.ply, .obj, .off, .stl: vertices and faces) as "
      "the base surface, coordinates as they are; implies --shape mesh");
  app.add_option("--texture", texture, "Texture on the base shape")
      ->check(CLI::IsMember(names(texture_kind_name, 8)))
      ->capture_default_str();
  app.add_option("--layout", layout, "sparse: separated features; dense: features touch")
      ->check(CLI::IsMember(names(texture_layout_name, 2)))
      ->capture_default_str();
  app.add_option("--size", params.size,
                 "Feature size R in model units: bump/dome radius, ridge or groove half-width, "
                 "scale cell radius; also the texture-free margin along edges; [0.005, 0.1]")
      ->capture_default_str();
  app.add_option("--amplitude", params.amplitude,
                 "Peak texture height A along the outward normal, model units; |A| <= size; "
                 "negative presses the texture in")
      ->capture_default_str();
  app.add_flag("--mixed-signs", params.mixed_signs,
               "Give each feature a random sign: bumps up and down");
  app.add_option("-n,--points", params.points, "Number of textured points")->capture_default_str();
  app.add_option("--ground-truth-points", params.ground_truth_points,
                 "Number of ground-truth points on the untextured base")
      ->capture_default_str();
  app.add_option("--noise", params.noise,
                 "Std dev of Gaussian noise on each coordinate of the textured positions, as a "
                 "fraction of the bounding-box diagonal; [0, 0.1]; normals stay clean")
      ->capture_default_str();
  app.add_flag("--noise-absolute", params.noise_absolute,
               "Read --noise in model units instead of as a fraction of the diagonal");
  app.add_option("--seed", params.seed,
                 "Random seed; the same seed gives the same files on any thread count")
      ->capture_default_str();
  app.add_flag("--ascii", ascii, "Write ASCII PLY instead of binary little endian");
  bool single = false, no_normals = false, at_vertices = false;
  app.add_flag("--at-vertices", at_vertices,
               "With --base-mesh: texture the base mesh's own vertices and keep its faces, so the "
               "output is a textured mesh in the format of -o (.ply, .obj, .off, .stl); the mesh "
               "should have several vertices per feature radius; --noise and -n do not apply");
  app.add_flag("--float", single,
               "Write positions, normals and texture_height in single precision (half the size)");
  app.add_flag("--no-normals", no_normals,
               "Leave the normals out of the textured cloud, as in a raw x y z scan (the ground "
               "truth keeps its normals)");

  std::int64_t block = 0;
  app.add_option("--block", block,
                 "Write the binary PLY cloud in blocks of this many points, never holding it "
                 "whole (0: at once up to 4M points, in blocks of 1M above); same bytes")
      ->capture_default_str();

  try {
    app.parse(argc, argv);
  } catch (const CLI::Success& e) {
    return app.exit(e);
  } catch (const CLI::ParseError& e) {
    std::fprintf(stderr, "detexture synth: %s (see --help)\n", e.what());
    return kExitUsage;
  }

  if (ground_truth.empty()) ground_truth = ground_truth_path_for(output);
  WriteOptions options;
  options.encoding = ascii ? PlyEncoding::Ascii : PlyEncoding::BinaryLittleEndian;
  SynthesizedShape synth;
  try {
    params.shape = parse_base_shape(shape);
    if (!base_mesh.empty()) {
      if (app.count("--shape") && params.shape != BaseShape::Mesh)
        throw std::invalid_argument("--base-mesh sets the shape to mesh; drop --shape " + shape);
      params.shape = BaseShape::Mesh;
    }
    params.texture = parse_texture_kind(texture);
    params.layout = parse_texture_layout(layout);
    format_from_extension(output);
    format_from_extension(ground_truth);
    if (ground_truth == output)
      throw std::invalid_argument("the ground truth and the output are the same file, " + output);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "detexture synth: %s\n", e.what());
    return kExitUsage;
  }
  if (at_vertices && base_mesh.empty()) {
    std::fprintf(stderr, "detexture synth: --at-vertices needs --base-mesh\n");
    return kExitUsage;
  }
  PointCloud mesh_cloud;
  if (!base_mesh.empty()) {
    try {
      mesh_cloud = read_point_cloud(base_mesh);  // its errors name the file
      try {
        params.mesh = std::make_shared<const BaseMesh>(base_mesh_from_cloud(mesh_cloud));
      } catch (const std::exception& e) {
        throw std::runtime_error(base_mesh + ": " + e.what());
      }
    } catch (const std::exception& e) {
      std::fprintf(stderr, "detexture synth: %s\n", e.what());
      return kExitInput;
    }
  }
  const bool ply_out = format_from_extension(output) == FileFormat::Ply &&
                       format_from_extension(ground_truth) == FileFormat::Ply;
  if (block == 0 && params.points > 4000000) block = 1000000;
  if (block > 0 && !ascii && ply_out) {
    try {
      const ScalarType real = single ? ScalarType::Float32 : ScalarType::Float64;
      BlockWriter cloud(
          output,
          make_layout(real, !no_normals,
                      {{"texture_height", real}, {"is_texture", ScalarType::UInt8}},
                      static_cast<std::uint64_t>(params.points), {describe(params, base_mesh)}));
      BlockWriter truth(
          ground_truth,
          make_layout(
              real, true, {}, static_cast<std::uint64_t>(params.ground_truth_points),
              {"ground truth (untextured base surface) of " + describe(params, base_mesh)}));
      std::size_t texture_points = 0;
      const SynthesizedShape summary = synthesize_shape_blocks(
          params, block,
          [&](const SynthesizedShape& b, std::int64_t) {
            cloud.write(b.positions, b.normals, &b.texture_heights, &b.is_texture);
            for (const std::uint8_t t : b.is_texture) texture_points += t;
          },
          [&](const SynthesizedShape& b, std::int64_t) {
            truth.write(b.ground_truth_positions, b.ground_truth_normals, nullptr, nullptr);
          });
      cloud.commit();
      truth.commit();
      std::printf(
          "wrote %lld points (%.1f%% texture, %zu features, noise sigma %.3g) to %s, in blocks "
          "of %lld\nwrote %lld ground-truth points of the untextured %s to %s\n"
          "base area %.6g diagonal %.6g\n",
          static_cast<long long>(params.points),
          100.0 * static_cast<double>(texture_points) / static_cast<double>(params.points),
          summary.feature_count, summary.noise_sigma, output.c_str(), static_cast<long long>(block),
          static_cast<long long>(params.ground_truth_points), base_shape_name(params.shape),
          ground_truth.c_str(), summary.area, summary.diagonal);
    } catch (const std::invalid_argument& e) {
      std::fprintf(stderr, "detexture synth: %s\n", e.what());
      return kExitUsage;
    } catch (const std::exception& e) {
      std::fprintf(stderr, "detexture synth: %s\n", e.what());
      return kExitOutput;
    }
    return kExitOk;
  }
  try {
    synth = synthesize_shape(params);
    if (at_vertices) {
      // The same features, evaluated at the mesh's vertices (which lie on the
      // base surface): a textured mesh whose faces are the base mesh's.
      TexturedSamples at = evaluate_texture(params, mesh_cloud.positions);
      synth.positions = std::move(at.positions);
      synth.normals = std::move(at.normals);
      synth.is_texture.assign(at.heights.size(), 0);
      for (std::size_t i = 0; i < at.heights.size(); ++i)
        synth.is_texture[i] = std::abs(at.heights[i]) > kTextureHeightEpsilon;
      synth.texture_heights = std::move(at.heights);
    }
  } catch (const std::exception& e) {
    std::fprintf(stderr, "detexture synth: %s\n", e.what());
    return kExitUsage;
  }

  try {
    PointCloud cloud;
    cloud.positions = std::move(synth.positions);
    if (!no_normals) cloud.normals = std::move(synth.normals);
    const ScalarType real = single ? ScalarType::Float32 : ScalarType::Float64;
    cloud.position_type = cloud.normal_type = real;
    cloud.extras.push_back({"texture_height", real, std::move(synth.texture_heights)});
    cloud.extras.push_back({"is_texture", ScalarType::UInt8,
                            std::vector<double>(synth.is_texture.begin(), synth.is_texture.end())});
    cloud.comments.push_back(describe(params, base_mesh) +
                             (at_vertices ? " (at the base mesh's vertices)" : ""));
    if (at_vertices) cloud.other_elements = mesh_cloud.other_elements;
    write_point_cloud(output, cloud, options);

    PointCloud truth;
    truth.positions = std::move(synth.ground_truth_positions);
    truth.normals = std::move(synth.ground_truth_normals);
    truth.position_type = truth.normal_type = real;
    truth.comments.push_back("ground truth (untextured base surface) of " +
                             describe(params, base_mesh));
    write_point_cloud(ground_truth, truth, options);

    std::size_t texture_points = 0;
    for (double v : cloud.extras[1].values) texture_points += v != 0.0;
    std::printf(
        "wrote %zu points (%.1f%% texture, %zu features, noise sigma %.3g) to %s\n"
        "wrote %zu ground-truth points of the untextured %s to %s\n"
        "base area %.6g diagonal %.6g\n",
        cloud.size(),
        100.0 * static_cast<double>(texture_points) / static_cast<double>(cloud.size()),
        synth.feature_count, synth.noise_sigma, output.c_str(), truth.size(),
        base_shape_name(params.shape), ground_truth.c_str(), synth.area, synth.diagonal);
    if (synth.degenerate_triangles > 0)
      std::printf("skipped %zu degenerate triangles of the base mesh\n",
                  synth.degenerate_triangles);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "detexture synth: %s\n", e.what());
    return kExitOutput;
  }
  return kExitOk;
}

}  // namespace detexture::app
