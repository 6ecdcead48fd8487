// prepare_mesh: turns a model of Debian's assimp-testmodels (any format assimp
// reads) into the base mesh of a real-shape case of bench/quality_real: one
// welded, consistently and outward oriented triangle mesh, optionally made
// smooth by Loop subdivision, centred at the origin with its largest
// bounding-box extent 1, written as PLY (vertex x y z, face vertex_indices).
//
// Steps (bench/README.md, "Real base meshes"):
//  1. assimp with aiProcess_Triangulate | aiProcess_JoinIdenticalVertices |
//     aiProcess_PreTransformVertices (every mesh of the scene in world
//     coordinates); point and line primitives are dropped.
//  2. Weld by exact position (assimp only joins vertices whose normals and
//     texture coordinates agree too, so a UV seam would stay open), then drop
//     degenerate triangles (a repeated vertex, or zero area) and duplicates
//     (the same three vertices in any order).
//  3. Components are edge-connected sets of triangles. --components largest
//     (default) keeps the one of largest area; all keeps every one.
//  4. CGAL: orient_polygon_soup (consistent orientation per component; a
//     non-manifold vertex or edge is split, which leaves a crack there), then a
//     Surface_mesh. Each component whose signed volume (from its own vertex
//     centroid) is negative is reversed, so closed parts have outward normals.
//  5. --subdivide N: N levels of CGAL's Loop subdivision
//     (Subdivision_method_3::Loop_subdivision), so the base is smooth at the
//     scale of the texture rather than faceted.
//  6. Centre the bounding box at the origin and scale its largest extent to 1.
//
// Prints what it found (components, boundary edges, signed volume, area,
// flips) as `key: value` lines; `area:` is the final surface area.
#include <CGAL/Polygon_mesh_processing/connected_components.h>
#include <CGAL/Polygon_mesh_processing/measure.h>
#include <CGAL/Polygon_mesh_processing/orient_polygon_soup.h>
#include <CGAL/Polygon_mesh_processing/orientation.h>
#include <CGAL/Polygon_mesh_processing/polygon_soup_to_polygon_mesh.h>
#include <CGAL/Simple_cartesian.h>
#include <CGAL/Subdivision_method_3/subdivision_methods_3.h>
#include <CGAL/Surface_mesh.h>
#include <CGAL/boost/graph/helpers.h>

#include <CLI/CLI.hpp>
#include <algorithm>
#include <array>
#include <assimp/Importer.hpp>
#include <assimp/postprocess.h>
#include <assimp/scene.h>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <map>
#include <numeric>
#include <set>
#include <stdexcept>
#include <string>
#include <vector>

#include "detexture/io/point_cloud.h"
#include "detexture/io/write_point_cloud.h"
#include "peer_common.h"

namespace {

using Kernel = CGAL::Simple_cartesian<double>;
using Point = Kernel::Point_3;
using Mesh = CGAL::Surface_mesh<Point>;
using Triangle = std::array<std::size_t, 3>;
namespace PMP = CGAL::Polygon_mesh_processing;
namespace peers = detexture::peers;

const char* kProgram = "prepare_mesh";

struct Params {
  std::string input;
  std::string output;
  std::string components = "largest";  ///< "largest" (by area) or "all"
  int subdivide = 0;                    ///< levels of Loop subdivision
};

/// Disjoint sets over triangle indices (path halving, union by size).
class DisjointSets {
 public:
  explicit DisjointSets(std::size_t n) : parent_(n), size_(n, 1) {
    std::iota(parent_.begin(), parent_.end(), std::size_t{0});
  }
  std::size_t find(std::size_t i) {
    while (parent_[i] != i) i = parent_[i] = parent_[parent_[i]];
    return i;
  }
  void unite(std::size_t a, std::size_t b) {
    a = find(a);
    b = find(b);
    if (a == b) return;
    if (size_[a] < size_[b]) std::swap(a, b);
    parent_[b] = a;
    size_[a] += size_[b];
  }

 private:
  std::vector<std::size_t> parent_, size_;
};

double triangle_area(const std::vector<Point>& P, const Triangle& t) {
  return std::sqrt(CGAL::squared_area(P[t[0]], P[t[1]], P[t[2]]));
}

/// Six times the signed volume enclosed by the triangles (exact for a closed
/// surface; for an open one, the volume of the cone from the origin).
double signed_volume6(const std::vector<Point>& P, const std::vector<Triangle>& T) {
  double v = 0.0;
  for (const Triangle& t : T) {
    const auto a = P[t[0]] - CGAL::ORIGIN, b = P[t[1]] - CGAL::ORIGIN, c = P[t[2]] - CGAL::ORIGIN;
    v += CGAL::scalar_product(a, CGAL::cross_product(b, c));
  }
  return v;
}

struct EdgeCounts {
  std::size_t boundary = 0;       ///< edges of one triangle
  std::size_t non_manifold = 0;   ///< edges of three or more
  std::size_t inconsistent = 0;   ///< edges of two triangles that traverse it the same way
};

EdgeCounts count_edges(const std::vector<Triangle>& T) {
  std::map<std::pair<std::size_t, std::size_t>, std::array<int, 2>> uses;  // forward, backward
  for (const Triangle& t : T)
    for (int k = 0; k < 3; ++k) {
      const std::size_t a = t[k], b = t[(k + 1) % 3];
      auto& u = uses[{std::min(a, b), std::max(a, b)}];
      ++u[a < b ? 0 : 1];
    }
  EdgeCounts c;
  for (const auto& [edge, u] : uses) {
    const int n = u[0] + u[1];
    if (n == 1) ++c.boundary;
    if (n > 2) ++c.non_manifold;
    if (n == 2 && u[0] != 1) ++c.inconsistent;
  }
  return c;
}

/// Every triangle of the scene in world coordinates, welded by exact position,
/// without degenerate or duplicate triangles.
void load_scene(const std::string& path, std::vector<Point>& P, std::vector<Triangle>& T) {
  Assimp::Importer importer;
  const aiScene* scene = importer.ReadFile(
      path, aiProcess_Triangulate | aiProcess_JoinIdenticalVertices | aiProcess_PreTransformVertices);
  if (scene == nullptr)
    throw std::runtime_error("assimp could not read '" + path + "': " + importer.GetErrorString());
  std::map<std::array<double, 3>, std::size_t> index;
  std::set<Triangle> seen;
  std::size_t non_triangles = 0, degenerate = 0, duplicate = 0, raw = 0;
  for (unsigned int m = 0; m < scene->mNumMeshes; ++m) {
    const aiMesh* mesh = scene->mMeshes[m];
    std::vector<std::size_t> welded(mesh->mNumVertices);
    for (unsigned int v = 0; v < mesh->mNumVertices; ++v) {
      const aiVector3D& p = mesh->mVertices[v];
      const std::array<double, 3> key{p.x, p.y, p.z};
      const auto [it, inserted] = index.emplace(key, P.size());
      if (inserted) P.emplace_back(key[0], key[1], key[2]);
      welded[v] = it->second;
    }
    for (unsigned int f = 0; f < mesh->mNumFaces; ++f) {
      const aiFace& face = mesh->mFaces[f];
      if (face.mNumIndices != 3) {
        ++non_triangles;
        continue;
      }
      ++raw;
      const Triangle t{welded[face.mIndices[0]], welded[face.mIndices[1]],
                       welded[face.mIndices[2]]};
      if (t[0] == t[1] || t[1] == t[2] || t[0] == t[2] || triangle_area(P, t) == 0.0) {
        ++degenerate;
        continue;
      }
      Triangle sorted = t;
      std::sort(sorted.begin(), sorted.end());
      if (!seen.insert(sorted).second) {
        ++duplicate;
        continue;
      }
      T.push_back(t);
    }
  }
  std::printf("input: %s\n", path.c_str());
  std::printf("assimp meshes: %u, triangles: %zu (dropped: %zu points/lines, %zu degenerate, "
              "%zu duplicate)\n",
              scene->mNumMeshes, raw, non_triangles, degenerate, duplicate);
  std::printf("welded vertices: %zu\n", P.size());
  if (T.empty()) throw std::runtime_error("'" + path + "' has no non-degenerate triangle.");
}

/// Triangles grouped by edge-connected component, largest area first.
std::vector<std::vector<std::size_t>> components_by_area(const std::vector<Point>& P,
                                                         const std::vector<Triangle>& T) {
  DisjointSets sets(T.size());
  std::map<std::pair<std::size_t, std::size_t>, std::size_t> first_triangle;
  for (std::size_t i = 0; i < T.size(); ++i)
    for (int k = 0; k < 3; ++k) {
      const std::size_t a = T[i][k], b = T[i][(k + 1) % 3];
      const auto [it, inserted] = first_triangle.emplace(std::make_pair(std::min(a, b), std::max(a, b)), i);
      if (!inserted) sets.unite(i, it->second);
    }
  std::map<std::size_t, std::vector<std::size_t>> groups;
  for (std::size_t i = 0; i < T.size(); ++i) groups[sets.find(i)].push_back(i);
  std::vector<std::pair<double, std::vector<std::size_t>>> by_area;
  for (auto& [root, faces] : groups) {
    double area = 0.0;
    for (std::size_t f : faces) area += triangle_area(P, T[f]);
    by_area.emplace_back(area, std::move(faces));
  }
  std::stable_sort(by_area.begin(), by_area.end(),
                   [](const auto& a, const auto& b) { return a.first > b.first; });
  std::vector<std::vector<std::size_t>> out;
  for (auto& [area, faces] : by_area) out.push_back(std::move(faces));
  return out;
}

/// The triangles `faces` of (P, T) with their vertices renumbered from 0.
void extract(const std::vector<Point>& P, const std::vector<Triangle>& T,
             const std::vector<std::size_t>& faces, std::vector<Point>& P_out,
             std::vector<std::vector<std::size_t>>& T_out) {
  std::vector<std::size_t> renumber(P.size(), SIZE_MAX);
  for (std::size_t f : faces) {
    std::vector<std::size_t> poly;
    for (std::size_t v : T[f]) {
      if (renumber[v] == SIZE_MAX) {
        renumber[v] = P_out.size();
        P_out.push_back(P[v]);
      }
      poly.push_back(renumber[v]);
    }
    T_out.push_back(std::move(poly));
  }
}

}  // namespace

int main(int argc, char** argv) {
  Params params;
  CLI::App app{
      "Prepares a base mesh for bench/quality_real from a model assimp reads: welded, one\n"
      "edge-connected component (or all), consistently oriented with outward normals,\n"
      "optionally Loop-subdivided, centred with largest bounding-box extent 1; writes a PLY\n"
      "mesh (vertex x y z, face vertex_indices).",
      kProgram};
  peers::add_input_output_options(app, params.input, params.output,
                                  "Input model (any format assimp 5 reads)");
  app.add_option("--components", params.components,
                 "largest: keep the edge-connected component of largest area; all: keep every "
                 "component")
      ->capture_default_str()
      ->check(CLI::IsMember({"largest", "all"}));
  app.add_option("--subdivide", params.subdivide, "Levels of Loop subdivision (0 to 5)")
      ->capture_default_str()
      ->check(CLI::Range(0, 5));
  if (const auto stop = peers::parse_command_line(app, argc, argv, kProgram)) return *stop;

  return peers::run_reporting_errors(kProgram, [&] {
    std::vector<Point> P;
    std::vector<Triangle> T;
    load_scene(params.input, P, T);
    const EdgeCounts welded_edges = count_edges(T);
    std::printf("welded edges: %zu boundary, %zu non-manifold, %zu inconsistently oriented\n",
                welded_edges.boundary, welded_edges.non_manifold, welded_edges.inconsistent);

    const auto components = components_by_area(P, T);
    double total_area = 0.0;
    for (const Triangle& t : T) total_area += triangle_area(P, t);
    const std::size_t kept = params.components == "largest" ? 1 : components.size();
    std::vector<std::size_t> faces;
    for (std::size_t c = 0; c < kept; ++c)
      faces.insert(faces.end(), components[c].begin(), components[c].end());
    double kept_area = 0.0;
    for (std::size_t f : faces) kept_area += triangle_area(P, T[f]);
    std::printf("components: %zu (edge-connected); kept %zu with %zu of %zu triangles, "
                "%.1f%% of the area\n",
                components.size(), kept, faces.size(), T.size(), 100.0 * kept_area / total_area);

    std::vector<Point> soup_points;
    std::vector<std::vector<std::size_t>> soup;
    extract(P, T, faces, soup_points, soup);
    const std::size_t soup_vertices = soup_points.size();
    const bool manifold = PMP::orient_polygon_soup(soup_points, soup);
    std::printf("orient_polygon_soup: %s (%zu vertices duplicated to split non-manifold places)\n",
                manifold ? "consistent" : "needed splits", soup_points.size() - soup_vertices);
    Mesh mesh;
    PMP::polygon_soup_to_polygon_mesh(soup_points, soup, mesh);
    if (mesh.number_of_faces() != soup.size())
      throw std::runtime_error("the triangles of '" + params.input +
                               "' could not be made into a surface mesh.");

    // Outward orientation: reverse each component whose signed volume is negative.
    auto fccmap = mesh.add_property_map<Mesh::Face_index, std::size_t>("f:cc").first;
    const std::size_t parts = PMP::connected_components(mesh, fccmap);
    // The volume is taken from each part's vertex centroid: exact for a closed
    // part, and for a part left open (a leg ending inside the body) the best
    // guess, where the origin could be anywhere.
    std::vector<Kernel::Vector_3> centroid(parts, CGAL::NULL_VECTOR);
    std::vector<double> corners(parts, 0.0);
    for (Mesh::Face_index f : mesh.faces())
      for (Mesh::Vertex_index u : CGAL::vertices_around_face(mesh.halfedge(f), mesh)) {
        centroid[fccmap[f]] = centroid[fccmap[f]] + (mesh.point(u) - CGAL::ORIGIN);
        corners[fccmap[f]] += 1.0;
      }
    std::vector<double> volume(parts, 0.0);
    for (Mesh::Face_index f : mesh.faces()) {
      const std::size_t c = fccmap[f];
      const Point o = CGAL::ORIGIN + centroid[c] / corners[c];
      std::array<Kernel::Vector_3, 3> v;
      int k = 0;
      for (Mesh::Vertex_index u : CGAL::vertices_around_face(mesh.halfedge(f), mesh))
        v[k++] = mesh.point(u) - o;
      volume[c] += CGAL::scalar_product(v[0], CGAL::cross_product(v[1], v[2]));
    }
    std::size_t flipped = 0;
    for (std::size_t c = 0; c < parts; ++c) {
      if (volume[c] >= 0.0) continue;
      std::vector<Mesh::Face_index> part;
      for (Mesh::Face_index f : mesh.faces())
        if (fccmap[f] == c) part.push_back(f);
      PMP::reverse_face_orientations(part, mesh);
      ++flipped;
    }
    mesh.remove_property_map(fccmap);
    std::printf("orientation: %zu of %zu parts reversed (negative signed volume)\n", flipped, parts);

    if (params.subdivide > 0)
      CGAL::Subdivision_method_3::Loop_subdivision(
          mesh, CGAL::parameters::number_of_iterations(params.subdivide));

    // Centre and scale.
    double lo[3] = {HUGE_VAL, HUGE_VAL, HUGE_VAL}, hi[3] = {-HUGE_VAL, -HUGE_VAL, -HUGE_VAL};
    for (Mesh::Vertex_index v : mesh.vertices())
      for (int k = 0; k < 3; ++k) {
        lo[k] = std::min(lo[k], mesh.point(v)[k]);
        hi[k] = std::max(hi[k], mesh.point(v)[k]);
      }
    const double extent = std::max({hi[0] - lo[0], hi[1] - lo[1], hi[2] - lo[2]});
    if (!(extent > 0.0)) throw std::runtime_error("'" + params.input + "' has zero extent.");

    detexture::PointCloud out;
    out.positions.resize(static_cast<Eigen::Index>(mesh.number_of_vertices()), 3);
    std::map<Mesh::Vertex_index, std::size_t> vindex;
    Eigen::Index row = 0;
    for (Mesh::Vertex_index v : mesh.vertices()) {
      vindex[v] = static_cast<std::size_t>(row);
      for (int k = 0; k < 3; ++k)
        out.positions(row, k) = (mesh.point(v)[k] - 0.5 * (lo[k] + hi[k])) / extent;
      ++row;
    }
    detexture::OtherElement face;
    face.name = "face";
    face.properties.push_back(
        {"vertex_indices", detexture::ScalarType::Int32, true, detexture::ScalarType::UInt8});
    face.row_offsets.push_back(0);
    std::vector<Point> final_points;
    std::vector<Triangle> final_triangles;
    for (Eigen::Index i = 0; i < out.positions.rows(); ++i)
      final_points.emplace_back(out.positions(i, 0), out.positions(i, 1), out.positions(i, 2));
    for (Mesh::Face_index f : mesh.faces()) {
      Triangle t;
      int k = 0;
      for (Mesh::Vertex_index u : CGAL::vertices_around_face(mesh.halfedge(f), mesh))
        t[k++] = vindex[u];
      final_triangles.push_back(t);
      face.values.push_back(3);
      for (std::size_t v : t) face.values.push_back(static_cast<double>(v));
      face.row_offsets.push_back(face.values.size());
    }
    out.other_elements.push_back(std::move(face));
    out.comments.push_back("base mesh made by bench/peers/prepare_mesh from " + params.input);
    out.comments.push_back("components " + params.components + ", Loop subdivision " +
                           std::to_string(params.subdivide) + ", centred, largest extent 1");

    double area = 0.0;
    for (const Triangle& t : final_triangles) area += triangle_area(final_points, t);
    const EdgeCounts final_edges = count_edges(final_triangles);
    std::printf("output: %zu vertices, %zu triangles\n", final_points.size(),
                final_triangles.size());
    std::printf("output edges: %zu boundary, %zu non-manifold, %zu inconsistently oriented\n",
                final_edges.boundary, final_edges.non_manifold, final_edges.inconsistent);
    std::printf("closed: %s\n", CGAL::is_closed(mesh) ? "yes" : "no");
    std::printf("extent: %.6g %.6g %.6g\n", (hi[0] - lo[0]) / extent, (hi[1] - lo[1]) / extent,
                (hi[2] - lo[2]) / extent);
    std::printf("signed volume: %.6g\n", signed_volume6(final_points, final_triangles) / 6.0);
    std::printf("area: %.6g\n", area);
    detexture::WriteOptions options;
    options.protect_path = params.input;
    detexture::write_point_cloud(params.output, out, options);
    return 0;
  });
}
