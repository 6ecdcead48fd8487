// Shared pieces of the Python module: numpy <-> Eigen conversion, errors,
// and the docstrings generated from the headers.
#pragma once

#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>

#include <cstdint>
#include <string>
#include <utility>
#include <vector>

#include "detexture/types.h"

namespace detexture::python {

namespace py = pybind11;

/// The `///` documentation of a header entry ("remove_texture",
/// "RemoveTextureParams.radius"), or "" when it has none.
std::string doc(const std::string& key);

/// An (N, 3) array of any float or int dtype and any strides (converted
/// once, without a per-point Python loop) as a #N by 3 matrix. Throws
/// ValueError naming `what` for another shape, and for NaN or Inf values
/// unless allow_nonfinite.
Matrix3 to_matrix3(py::handle array, const char* what, bool allow_nonfinite = false);

/// The matrix as an (N, 3) float64 array that owns it (no copy).
py::array to_array(Matrix3 matrix);
/// A vector as an (N,) array of T that owns it (no copy).
template <class T>
py::array to_array(std::vector<T> values) {
  auto* owner = new std::vector<T>(std::move(values));
  py::capsule free(owner, [](void* p) { delete static_cast<std::vector<T>*>(p); });
  return py::array_t<T>({static_cast<py::ssize_t>(owner->size())}, owner->data(), free);
}
py::array to_array(Eigen::VectorXd values);

/// A 1-D array of n values (any numeric dtype, cast to T) as a vector;
/// ValueError naming `what` otherwise.
template <class T>
std::vector<T> to_vector(py::handle array, const char* what, std::size_t n) {
  auto a = py::array_t<T, py::array::c_style | py::array::forcecast>::ensure(array);
  if (!a || a.ndim() != 1 || static_cast<std::size_t>(a.shape(0)) != n) {
    PyErr_Clear();
    throw py::value_error(std::string(what) + " must be a 1-D array of " + std::to_string(n) +
                          " values, one per point");
  }
  return std::vector<T>(a.data(), a.data() + n);
}

/// Positions and optional normals of the same cloud, with the sizes checked
/// against each other and against neighborhoods built on it.
void check_rows(const Matrix3& P, const Matrix3& other, const char* what);

/// Run f, turning the library's file errors (std::runtime_error other than
/// invalid_argument and ResourceLimitError) into OSError with the same message.
[[noreturn]] void throw_os_error(const char* message);
bool is_resource_limit(const std::exception& e);

template <class F>
auto with_file_errors(F&& f) -> decltype(f()) {
  try {
    return f();
  } catch (const std::invalid_argument&) {
    throw;
  } catch (const py::error_already_set&) {
    throw;
  } catch (const std::runtime_error& e) {
    if (is_resource_limit(e)) throw;
    throw_os_error(e.what());
  }
}

void bind_point_cloud(py::module_& m);
void bind_remove_texture(py::module_& m);
void bind_synthesize_shape(py::module_& m);
void bind_neighborhoods(py::module_& m);
void bind_stages(py::module_& m);

}  // namespace detexture::python
