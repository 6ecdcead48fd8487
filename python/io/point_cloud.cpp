// detexture.PointCloud, read_point_cloud, write_point_cloud (io/*.h).
#include "detexture/io/point_cloud.h"

#include <pybind11/stl.h>

#include "detexture/io/read_point_cloud.h"
#include "detexture/io/write_point_cloud.h"
#include "module.h"

namespace detexture::python {
namespace {

py::dtype dtype_of(ScalarType t) {
  switch (t) {
    case ScalarType::Int8:
      return py::dtype::of<std::int8_t>();
    case ScalarType::UInt8:
      return py::dtype::of<std::uint8_t>();
    case ScalarType::Int16:
      return py::dtype::of<std::int16_t>();
    case ScalarType::UInt16:
      return py::dtype::of<std::uint16_t>();
    case ScalarType::Int32:
      return py::dtype::of<std::int32_t>();
    case ScalarType::UInt32:
      return py::dtype::of<std::uint32_t>();
    case ScalarType::Float32:
      return py::dtype::of<float>();
    case ScalarType::Float64:
      break;
  }
  return py::dtype::of<double>();
}

ScalarType scalar_type_of(const py::dtype& d, const std::string& name) {
  const char kind = d.kind();
  const auto size = d.itemsize();
  if (kind == 'b') return ScalarType::UInt8;
  if (kind == 'f' && size == 4) return ScalarType::Float32;
  if (kind == 'f' && size == 8) return ScalarType::Float64;
  if (kind == 'i' && size == 1) return ScalarType::Int8;
  if (kind == 'i' && size == 2) return ScalarType::Int16;
  if (kind == 'i' && size == 4) return ScalarType::Int32;
  if (kind == 'u' && size == 1) return ScalarType::UInt8;
  if (kind == 'u' && size == 2) return ScalarType::UInt16;
  if (kind == 'u' && size == 4) return ScalarType::UInt32;
  throw py::value_error("extra property '" + name + "' has dtype " +
                        py::str(py::object(d)).cast<std::string>() +
                        ", which a PLY file cannot hold; use int8-int32, uint8-uint32, "
                        "float32 or float64");
}

py::dict extras_of(const PointCloud& c) {
  py::dict out;
  for (const PointProperty& p : c.extras) {
    // Values are held as double, exact for every PLY type; numpy casts them back.
    py::array_t<double> as_double(static_cast<py::ssize_t>(p.values.size()), p.values.data());
    out[py::str(p.name)] = as_double.attr("astype")(dtype_of(p.type));
  }
  return out;
}

void set_extras(PointCloud& c, const py::dict& extras) {
  std::vector<PointProperty> props;
  for (const auto& [key, value] : extras) {
    PointProperty p;
    p.name = py::str(key).cast<std::string>();
    py::array a = py::array::ensure(value);
    if (!a || a.ndim() != 1)
      throw py::value_error("extra property '" + p.name + "' must be a 1-D array");
    if (static_cast<std::size_t>(a.shape(0)) != c.size())
      throw py::value_error("extra property '" + p.name + "' has " + std::to_string(a.shape(0)) +
                            " values for " + std::to_string(c.size()) + " points");
    p.type = scalar_type_of(a.dtype(), p.name);
    auto d = py::array_t<double, py::array::c_style | py::array::forcecast>::ensure(a);
    p.values.assign(d.data(), d.data() + d.size());
    props.push_back(std::move(p));
  }
  c.extras = std::move(props);
}

void set_normals(PointCloud& c, const py::object& normals) {
  if (normals.is_none()) {
    c.normals = Normals();
    return;
  }
  Normals n = to_matrix3(normals, "normals", true);
  if (n.rows() != c.positions.rows())
    throw py::value_error("normals must have as many rows as positions (" +
                          std::to_string(c.positions.rows()) + "), got " +
                          std::to_string(n.rows()));
  normalize_normals(n);
  c.normals = std::move(n);
}

std::string path_text(const py::object& path) {
  return py::str(py::module_::import("os").attr("fspath")(path)).cast<std::string>();
}

PlyEncoding parse_encoding(const std::string& e) {
  if (e == "binary") return PlyEncoding::BinaryLittleEndian;
  if (e == "ascii") return PlyEncoding::Ascii;
  if (e == "binary-big-endian") return PlyEncoding::BinaryBigEndian;
  throw std::invalid_argument("encoding must be binary, ascii or binary-big-endian");
}

}  // namespace

void bind_point_cloud(py::module_& m) {
  py::class_<PointCloud>(m, "PointCloud",
                         "A point cloud as read from or written to a file: positions, optional "
                         "normals, extra per-point properties (a dict of 1-D arrays) and what "
                         "else the file carried (faces, comments), kept for a round trip.\n\n"
                         "PointCloud(positions, normals=None, extras=None)")
      .def(py::init([](const py::object& positions, const py::object& normals,
                       const py::object& extras) {
             PointCloud c;
             c.positions = to_matrix3(positions, "positions");
             set_normals(c, normals);
             if (!extras.is_none()) set_extras(c, extras.cast<py::dict>());
             return c;
           }),
           py::arg("positions"), py::arg("normals") = py::none(), py::arg("extras") = py::none())
      .def_property(
          "positions", [](const PointCloud& c) { return to_array(c.positions); },
          [](PointCloud& c, const py::object& p) {
            Positions P = to_matrix3(p, "positions");
            if (P.rows() != c.positions.rows() && !c.extras.empty())
              throw py::value_error("positions must keep the number of points (" +
                                    std::to_string(c.positions.rows()) +
                                    ") while the cloud has extra properties");
            c.positions = std::move(P);
          },
          "(N, 3) float64 positions (a copy; assign to change them)")
      .def_property(
          "normals",
          [](const PointCloud& c) -> py::object {
            if (!c.has_normals()) return py::none();
            return to_array(c.normals);
          },
          &set_normals,
          "(N, 3) float64 unit normals, or None; assigned normals are normalized as the "
          "readers do (zero, NaN or Inf rows become zero and are re-estimated by "
          "remove_texture)")
      .def_property("extras", &extras_of, &set_extras,
                    "Other per-point properties, name -> 1-D array in the file's type "
                    "(uint8 colours, float32 intensity, ...); a copy, assign a dict to change them")
      .def_property_readonly(
          "comments", [](const PointCloud& c) { return c.comments; }, "The file's comment lines")
      .def("__len__", &PointCloud::size)
      .def("__repr__", [](const PointCloud& c) {
        return "<detexture.PointCloud: " + std::to_string(c.size()) + " points" +
               (c.has_normals() ? ", normals" : "") +
               (c.extras.empty() ? "" : ", " + std::to_string(c.extras.size()) + " extras") + ">";
      });

  m.def(
      "read_point_cloud",
      [](const py::object& path, const std::string& format) {
        const std::string p = path_text(path);
        const FileFormat f = parse_file_format(format);
        return with_file_errors([&] {
          py::gil_scoped_release release;
          return read_point_cloud(p, f);
        });
      },
      py::arg("path"), py::arg("format") = "auto",
      ("read_point_cloud(path, format='auto') -> PointCloud\n\nformat: 'auto' (by extension), "
       "'ply' or 'xyz'. Raises OSError with the command line's message for a bad file.\n\n" +
       doc("read_point_cloud"))
          .c_str());

  m.def(
      "write_point_cloud",
      [](const py::object& path, const PointCloud& cloud, const std::string& format,
         const std::string& encoding) {
        const std::string p = path_text(path);
        WriteOptions o;
        o.format = parse_file_format(format);
        o.encoding = parse_encoding(encoding);
        with_file_errors([&] {
          py::gil_scoped_release release;
          write_point_cloud(p, cloud, o);
        });
      },
      py::arg("path"), py::arg("cloud"), py::kw_only(), py::arg("format") = "auto",
      py::arg("encoding") = "binary",
      ("write_point_cloud(path, cloud, *, format='auto', encoding='binary')\n\ncloud: a "
       "PointCloud (detexture.PointCloud(positions, normals, extras) makes one from arrays). "
       "encoding: 'binary', 'ascii' or 'binary-big-endian' (PLY). Raises OSError for a file "
       "that cannot be written.\n\n" +
       doc("write_point_cloud"))
          .c_str());
}

}  // namespace detexture::python
