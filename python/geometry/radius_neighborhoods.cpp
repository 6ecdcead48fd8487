// detexture.Neighborhoods, radius_neighborhoods, knn_neighborhoods
// (geometry/radius_neighborhoods.h) and estimate_normals
// (geometry/estimate_normals.h): the first stages, for callers who run them alone.
#include "detexture/geometry/radius_neighborhoods.h"

#include "detexture/geometry/estimate_normals.h"
#include "module.h"

namespace detexture::python {

void bind_neighborhoods(py::module_& m) {
  py::class_<Neighborhoods>(m, "Neighborhoods", doc("Neighborhoods").c_str())
      .def_property_readonly(
          "offsets", [](const Neighborhoods& n) { return to_array(n.offsets); },
          "#P+1 uint64 row offsets (a copy)")
      .def_property_readonly(
          "indices", [](const Neighborhoods& n) { return to_array(n.indices); },
          "uint32 neighbor indices (a copy)")
      .def_readonly("symmetric", &Neighborhoods::symmetric, doc("Neighborhoods.symmetric").c_str())
      .def("__len__", &Neighborhoods::size)
      .def("__getitem__", [](const Neighborhoods& n, std::size_t i) {
        if (i >= n.size()) throw py::index_error("point index out of range");
        return to_array(std::vector<std::uint32_t>(n.begin(i), n.end(i)));
      });

  m.def(
      "radius_neighborhoods",
      [](const py::object& points, double radius, int max_neighbors) {
        const Positions P = to_matrix3(points, "points");
        py::gil_scoped_release release;
        return radius_neighborhoods(P, {radius, max_neighbors});
      },
      py::arg("points"), py::arg("radius"),
      py::arg("max_neighbors") = RadiusNeighborhoodsParams{}.max_neighbors,
      ("radius_neighborhoods(points, radius, max_neighbors=0) -> Neighborhoods\n\n" +
       doc("radius_neighborhoods") + "\nradius: " + doc("RadiusNeighborhoodsParams.radius") +
       "\nmax_neighbors: " + doc("RadiusNeighborhoodsParams.max_neighbors"))
          .c_str());
  m.def(
      "knn_neighborhoods",
      [](const py::object& points, int k) {
        const Positions P = to_matrix3(points, "points");
        if (k < 1) throw py::value_error("k must be at least 1");
        py::gil_scoped_release release;
        return knn_neighborhoods(P, k);
      },
      py::arg("points"), py::arg("k"),
      ("knn_neighborhoods(points, k) -> Neighborhoods\n\n" + doc("knn_neighborhoods")).c_str());
  m.def(
      "estimate_normals",
      [](const py::object& points, const Neighborhoods& neighborhoods) {
        const Positions P = to_matrix3(points, "points");
        EstimateNormalsResult r;
        {
          py::gil_scoped_release release;
          r = estimate_normals(P, neighborhoods);
        }
        return py::make_tuple(to_array(std::move(r.normals)), to_array(std::move(r.variation)),
                              r.degenerate);
      },
      py::arg("points"), py::arg("neighborhoods"),
      ("estimate_normals(points, neighborhoods) -> (normals, variation, degenerate)\n\n" +
       doc("estimate_normals"))
          .c_str());
}

}  // namespace detexture::python
