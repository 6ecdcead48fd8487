// The module `detexture`: what is shared by the bindings, and the module itself.
#include "module.h"

#include <cmath>
#include <stdexcept>

#include "detexture/geometry/estimate_neighborhoods_memory.h"
#include "header_docs.h"

namespace detexture::python {

std::string doc(const std::string& key) {
  const auto& docs = header_docs();
  const auto it = docs.find(key);
  return it == docs.end() ? std::string() : it->second;
}

Matrix3 to_matrix3(py::handle array, const char* what, bool allow_nonfinite) {
  using Array = py::array_t<double, py::array::c_style | py::array::forcecast>;
  Array a;
  try {
    a = py::cast<Array>(array);
  } catch (const py::error_already_set&) {
    throw py::value_error(std::string(what) + " must be a numeric array of shape (N, 3)");
  } catch (const py::cast_error&) {
    throw py::value_error(std::string(what) + " must be a numeric array of shape (N, 3)");
  }
  if (a.ndim() != 2 || a.shape(1) != 3) {
    std::string shape = "(";
    for (py::ssize_t k = 0; k < a.ndim(); ++k)
      shape += (k ? ", " : "") + std::to_string(a.shape(k));
    throw py::value_error(std::string(what) + " must have shape (N, 3), got " +
                          (a.ndim() == 1 ? shape + ",)" : shape + ")"));
  }
  Matrix3 m(a.shape(0), 3);
  if (m.size() > 0) std::copy(a.data(), a.data() + m.size(), m.data());
  if (!allow_nonfinite && !m.allFinite()) {
    Eigen::Index row = 0;
    while (m.row(row).allFinite()) ++row;
    throw py::value_error(std::string(what) + " row " + std::to_string(row) +
                          " has a NaN or Inf coordinate; remove or repair such points first");
  }
  return m;
}

py::array to_array(Matrix3 matrix) {
  auto* owner = new Matrix3(std::move(matrix));
  py::capsule free(owner, [](void* p) { delete static_cast<Matrix3*>(p); });
  return py::array_t<double>({static_cast<py::ssize_t>(owner->rows()), py::ssize_t(3)},
                             owner->data(), free);
}

py::array to_array(Eigen::VectorXd values) {
  auto* owner = new Eigen::VectorXd(std::move(values));
  py::capsule free(owner, [](void* p) { delete static_cast<Eigen::VectorXd*>(p); });
  return py::array_t<double>({static_cast<py::ssize_t>(owner->size())}, owner->data(), free);
}

void check_rows(const Matrix3& P, const Matrix3& other, const char* what) {
  if (other.rows() != P.rows())
    throw py::value_error(std::string(what) + " must have as many rows as points (" +
                          std::to_string(P.rows()) + "), got " + std::to_string(other.rows()));
}

void throw_os_error(const char* message) {
  PyErr_SetString(PyExc_OSError, message);
  throw py::error_already_set();
}

bool is_resource_limit(const std::exception& e) {
  return dynamic_cast<const ResourceLimitError*>(&e) != nullptr;
}

}  // namespace detexture::python

PYBIND11_MODULE(detexture, m) {
  namespace dp = detexture::python;
  // Every docstring starts with its own signature line (remove_texture's is
  // generated from the parameter struct).
  pybind11::options options;
  options.disable_function_signatures();
  m.doc() =
      "detexture: remove geometric surface texture (scales, knurls, engravings, bumps) from "
      "point clouds while keeping the underlying shape and its sharp edges (Sun et al., "
      "Reliable Rolling-guided Point Normal Filtering for Surface Texture Removal, PG 2019).\n\n"
      "remove_texture(points) is the whole method; read_point_cloud / write_point_cloud, "
      "synthesize and compare are the command line's other jobs. Arrays are numpy (N, 3) "
      "float64 (any float dtype and layout is accepted). Parameter errors raise ValueError, "
      "file errors OSError, with the command line's messages.";
  pybind11::register_exception<detexture::ResourceLimitError>(m, "ResourceLimitError",
                                                              PyExc_MemoryError);
  dp::bind_point_cloud(m);
  dp::bind_remove_texture(m);
  dp::bind_synthesize_shape(m);
  dp::bind_neighborhoods(m);
  dp::bind_stages(m);
}
