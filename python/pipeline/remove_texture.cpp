// detexture.remove_texture and its result (pipeline/remove_texture.h), the
// texture fields (pipeline/texture_fields.h) and the parameter enums.
//
// The keywords of remove_texture are generated from RemoveTextureParams
// (extract_docs.py: for_each_remove_texture_param), their defaults read from a
// default-constructed struct and their docs from the header comments.
#include "detexture/pipeline/remove_texture.h"

#include <pybind11/stl.h>

#include <algorithm>
#include <atomic>
#include <cctype>
#include <exception>
#include <map>
#include <memory>
#include <mutex>
#include <sstream>

#include "detexture/io/read_point_cloud.h"
#include "detexture/pipeline/texture_fields.h"
#include "module.h"
#include "params.h"

namespace detexture::python {
namespace {

std::string remove_texture_doc(const py::module_& m) {
  const auto [keywords, params] = params_doc<RemoveTextureParams>(m);
  std::string signature = "remove_texture(points, normals=None, *" + keywords;
  signature += ", progress=None) -> RemoveTextureResult\n\n";
  return signature +
         wrap(
             "Remove the geometric texture from a point cloud (the whole method; see "
             "README, The method). points: (N, 3) array of any float or int dtype and any "
             "layout, or a PointCloud (its normals are used). normals: (N, 3) or None to "
             "estimate them; normalized as the readers do. The work runs without the GIL; "
             "progress(stage, fraction) is called from time to time (with the GIL), and an "
             "exception raised in it cancels the run when the stage in progress ends and "
             "propagates. Warnings of the "
             "library arrive as UserWarning. Raises ValueError for bad parameters or arrays "
             "(the command line's messages), detexture.ResourceLimitError (a MemoryError) "
             "when the neighborhoods would exceed memory_limit.",
             "") +
         "\n" +
         wrap(
             "Keywords are the members of the C++ RemoveTextureParams, with the stage "
             "structs' members as <stage>_<member> (texture_delta is params.texture.delta); "
             "lengths are numbers in the cloud's units or strings '0.02d' (of the "
             "bounding-box diagonal), '0.5r' (of r), '1.5t' (of the estimated texture "
             "radius, r only). Defaults and texts below come from the C++ header.",
             "") +
         "\nC++: " + wrap(doc("remove_texture"), "") + "\nParameters\n----------\n" + params;
}

// ---- observer: progress, cancellation, warnings ----------------------------

struct Cancelled : std::exception {
  const char* what() const noexcept override { return "cancelled by the progress callback"; }
};

struct ObserverState {
  py::object progress;  // may be None
  std::mutex mutex;
  std::atomic<bool> cancelled{false};
  std::exception_ptr error;  // the Python exception that cancelled the run
  std::vector<std::string> warnings;
};

// Call progress(stage, fraction) with the GIL, and check for Ctrl-C; a Python
// exception is kept and cancels the run at the next stage.
void report_progress(ObserverState& st, const std::string& stage, double fraction) {
  if (st.cancelled) return;
  py::gil_scoped_acquire gil;
  try {
    if (PyErr_CheckSignals() != 0) throw py::error_already_set();
    if (!st.progress.is_none()) st.progress(stage, fraction);
  } catch (...) {
    st.error = std::current_exception();
    st.cancelled = true;
  }
}

PipelineObserver make_observer(ObserverState& st) {
  PipelineObserver o;
  // begin runs on the calling thread, outside parallel loops: where the run
  // can stop cleanly (an exception may not leave an OpenMP region).
  o.begin = [&st](const std::string& stage) {
    report_progress(st, stage, 0.0);
    if (st.cancelled) throw Cancelled();
  };
  o.progress = [&st](const std::string& stage, double fraction) {
    report_progress(st, stage, fraction);
  };
  o.warning = [&st](const std::string& message) {
    std::lock_guard<std::mutex> lock(st.mutex);
    st.warnings.push_back(message);
  };
  return o;
}

RemoveTextureResult run(py::handle points, const py::object& normals_arg,
                        const py::kwargs& kwargs) {
  py::object progress = py::none();
  if (kwargs.contains("progress")) {
    progress = kwargs["progress"];
    if (!progress.is_none() && !PyCallable_Check(progress.ptr()))
      throw py::type_error("progress must be a callable (stage, fraction) or None");
  }
  const auto params =
      params_from_kwargs<RemoveTextureParams>(kwargs, "remove_texture", {"progress"});
  validate(params);  // std::invalid_argument -> ValueError, with the library's sentence
  Positions P;
  Normals N;
  if (py::isinstance<PointCloud>(points)) {
    const auto& cloud = points.cast<const PointCloud&>();
    if (!normals_arg.is_none())
      throw py::value_error("pass normals with a PointCloud through its normals attribute");
    P = cloud.positions;
    if (cloud.has_normals()) N = cloud.normals;
  } else {
    P = to_matrix3(points, "points");
    if (!normals_arg.is_none()) {
      N = to_matrix3(normals_arg, "normals", true);
      if (N.rows() != P.rows())
        throw py::value_error("normals must have as many rows as points (" +
                              std::to_string(P.rows()) + "), got " + std::to_string(N.rows()));
      normalize_normals(N);
    }
  }
  if (P.rows() == 0) throw py::value_error("the point cloud is empty");

  ObserverState st;
  st.progress = progress;
  const PipelineObserver observer = make_observer(st);
  RemoveTextureResult result;
  bool cancelled = false;
  {
    py::gil_scoped_release release;
    try {
      result = remove_texture(std::move(P), std::move(N), params, observer);
    } catch (const Cancelled&) {
      cancelled = true;
    }
  }
  if (st.error) std::rethrow_exception(st.error);
  if (cancelled) throw std::runtime_error("the run was cancelled");  // error is set: not reached
  for (const std::string& w : st.warnings)
    if (PyErr_WarnEx(PyExc_UserWarning, w.c_str(), 2) != 0) throw py::error_already_set();
  return result;
}

// ---- result and report -----------------------------------------------------

template <class Class, class T>
void readonly(
    py::class_<Class>& c,
    std::vector<std::pair<std::string, std::function<py::object(const Class&)>>>& dict_fields,
    const char* name, T Class::*member, const std::string& doc_key) {
  c.def_readonly(name, member, doc(doc_key).c_str());
  dict_fields.emplace_back(name, [member](const Class& x) { return py::cast(x.*member); });
}

template <class Class>
using DictFields = std::vector<std::pair<std::string, std::function<py::object(const Class&)>>>;

template <class Class>
py::dict to_dict(const Class& x, const DictFields<Class>& fields) {
  py::dict d;
  for (const auto& [name, get] : fields) d[py::str(name)] = get(x);
  return d;
}

py::array bool_view(const std::vector<std::uint8_t>& v, py::handle owner) {
  return py::array(py::dtype("bool"), {static_cast<py::ssize_t>(v.size())}, {py::ssize_t(1)},
                   v.data(), owner);
}
py::array rows_view(const Matrix3& m, py::handle owner) {
  return py::array_t<double>({static_cast<py::ssize_t>(m.rows()), py::ssize_t(3)}, m.data(), owner);
}

}  // namespace

void bind_remove_texture(py::module_& m) {
  py::enum_<UnderlyingSurface>(m, "UnderlyingSurface")
      .value("Plane", UnderlyingSurface::Plane)
      .value("Quadric", UnderlyingSurface::Quadric);
  py::enum_<SubneighborhoodMode>(m, "SubneighborhoodMode")
      .value("Hard", SubneighborhoodMode::Hard)
      .value("Soft", SubneighborhoodMode::Soft);
  py::enum_<NormalSide>(m, "NormalSide")
      .value("Auto", NormalSide::Auto)
      .value("Outward", NormalSide::Outward)
      .value("Inward", NormalSide::Inward)
      .value("PlusX", NormalSide::PlusX)
      .value("MinusX", NormalSide::MinusX)
      .value("PlusY", NormalSide::PlusY)
      .value("MinusY", NormalSide::MinusY)
      .value("PlusZ", NormalSide::PlusZ)
      .value("MinusZ", NormalSide::MinusZ);
  py::enum_<GuidanceMode>(m, "GuidanceMode")
      .value("PatchShift", GuidanceMode::PatchShift)
      .value("Plain", GuidanceMode::Plain);
  py::enum_<NormalDifference>(m, "NormalDifference")
      .value("Angle", NormalDifference::Angle)
      .value("OneMinusCos", NormalDifference::OneMinusCos);
  py::enum_<UpdateMode>(m, "UpdateMode")
      .value("Global", UpdateMode::Global)
      .value("Isotropic", UpdateMode::Isotropic)
      .value("Eq9", UpdateMode::Eq9);
  py::enum_<FaceWeighting>(m, "FaceWeighting")
      .value("Angle", FaceWeighting::Angle)
      .value("Area", FaceWeighting::Area);

  static DictFields<TextureScaleEstimate> scale_fields;
  py::class_<TextureScaleEstimate> scale(m, "TextureScaleEstimate",
                                         doc("estimate_texture_scale").c_str());
  for (auto [name, member] :
       std::initializer_list<std::pair<const char*, double TextureScaleEstimate::*>>{
           {"spacing", &TextureScaleEstimate::spacing},
           {"noise", &TextureScaleEstimate::noise},
           {"texture_radius", &TextureScaleEstimate::texture_radius},
           {"texture_height", &TextureScaleEstimate::texture_height},
           {"thin_radius", &TextureScaleEstimate::thin_radius}})
    readonly(scale, scale_fields, name, member, std::string("TextureScaleEstimate.") + name);
  readonly(scale, scale_fields, "samples", &TextureScaleEstimate::samples,
           "TextureScaleEstimate.samples");
  readonly(scale, scale_fields, "texture_found", &TextureScaleEstimate::texture_found,
           "TextureScaleEstimate.texture_found");
  readonly(scale, scale_fields, "reason", &TextureScaleEstimate::reason,
           "TextureScaleEstimate.reason");
  readonly(scale, scale_fields, "radii", &TextureScaleEstimate::radii,
           "TextureScaleEstimate.radii");
  readonly(scale, scale_fields, "residual", &TextureScaleEstimate::residual,
           "TextureScaleEstimate.residual");
  readonly(scale, scale_fields, "relief", &TextureScaleEstimate::relief,
           "TextureScaleEstimate.relief");
  scale.def("to_dict", [](const TextureScaleEstimate& s) { return to_dict(s, scale_fields); });

  static DictFields<NeighborhoodStats> stats_fields;
  py::class_<NeighborhoodStats> stats(m, "NeighborhoodStats",
                                      "Neighbors per point (self included).");
  readonly(stats, stats_fields, "min", &NeighborhoodStats::min, "NeighborhoodStats.min");
  readonly(stats, stats_fields, "max", &NeighborhoodStats::max, "NeighborhoodStats.max");
  readonly(stats, stats_fields, "mean", &NeighborhoodStats::mean, "NeighborhoodStats.mean");
  readonly(stats, stats_fields, "sparse_points", &NeighborhoodStats::sparse_points,
           "NeighborhoodStats.sparse_points");
  stats.def("to_dict", [](const NeighborhoodStats& s) { return to_dict(s, stats_fields); });

  static DictFields<RemoveTextureReport> report_fields;
  py::class_<RemoveTextureReport> report(m, "RemoveTextureReport",
                                         "What a run of remove_texture found and did: counts, "
                                         "resolved lengths, seconds per stage. to_dict() gives "
                                         "it all as a dict.");
#define DETEXTURE_REPORT(name) \
  readonly(report, report_fields, #name, &RemoveTextureReport::name, "RemoveTextureReport." #name)
  DETEXTURE_REPORT(diagonal);
  DETEXTURE_REPORT(radius_choice);
  DETEXTURE_REPORT(radius_reason);
  DETEXTURE_REPORT(scale_estimated);
  DETEXTURE_REPORT(radius);
  DETEXTURE_REPORT(lambda);
  DETEXTURE_REPORT(sigma_s);
  DETEXTURE_REPORT(sigma_p);
  DETEXTURE_REPORT(normals_estimated);
  DETEXTURE_REPORT(normals_ignored);
  DETEXTURE_REPORT(normals_reestimated);
  DETEXTURE_REPORT(normals_degenerate);
  DETEXTURE_REPORT(normals_flipped);
  DETEXTURE_REPORT(orientation_inconsistency);
  DETEXTURE_REPORT(opposite_neighbors);
  DETEXTURE_REPORT(surface_split_neighbors);
  DETEXTURE_REPORT(thin_part_points);
  DETEXTURE_REPORT(thin_part_neighbors);
  DETEXTURE_REPORT(mesh_path_points);
  DETEXTURE_REPORT(mesh_path_neighbors);
  DETEXTURE_REPORT(texture_points);
  DETEXTURE_REPORT(no_plane);
  DETEXTURE_REPORT(ransac_mean_iterations);
  DETEXTURE_REPORT(empty_subneighborhoods);
  DETEXTURE_REPORT(rolling_iterations);
  DETEXTURE_REPORT(update_isolated);
  DETEXTURE_REPORT(update_iterations);
  DETEXTURE_REPORT(mean_displacement);
  DETEXTURE_REPORT(texture_height);
  DETEXTURE_REPORT(max_move);
  DETEXTURE_REPORT(moves_limited);
  DETEXTURE_REPORT(relief_lean);
  DETEXTURE_REPORT(counter_moves_limited);
  DETEXTURE_REPORT(tip_moves_limited);
  DETEXTURE_REPORT(sink_moves_limited);
  DETEXTURE_REPORT(raised_cells_lowered);
  DETEXTURE_REPORT(raised_cells_limited);
  DETEXTURE_REPORT(raised_cells_turned);
  DETEXTURE_REPORT(normals_not_fitted);
  DETEXTURE_REPORT(normals_blended);
  DETEXTURE_REPORT(input_normals_kept);
  DETEXTURE_REPORT(input_normals_updated);
  DETEXTURE_REPORT(waves_flagged);
  DETEXTURE_REPORT(waves_released);
  DETEXTURE_REPORT(duplicates_merged);
  DETEXTURE_REPORT(estimated_bytes);
#undef DETEXTURE_REPORT
  report.def_property_readonly(
      "scale", [](const RemoveTextureReport& r) { return r.scale; },
      "The texture-scale estimate (when scale_estimated)");
  report.def_property_readonly(
      "neighbors", [](const RemoveTextureReport& r) { return r.neighbors; },
      doc("RemoveTextureReport.neighbors").c_str());
  report.def_property_readonly(
      "timings",
      [](const RemoveTextureReport& r) {
        py::dict d;
        for (const StageTiming& t : r.timings) d[py::str(t.stage)] = t.seconds;
        return d;
      },
      "Seconds per stage, stage name -> seconds, in the order they ran");
  report.def("to_dict", [](py::object self) {
    const auto& r = self.cast<const RemoveTextureReport&>();
    py::dict d = to_dict(r, report_fields);
    d["scale"] = r.scale_estimated ? py::object(to_dict(r.scale, scale_fields)) : py::none();
    d["neighbors"] = to_dict(r.neighbors, stats_fields);
    d["timings"] = self.attr("timings");
    return d;
  });

  py::class_<RemoveTextureResult>(m, "RemoveTextureResult",
                                  "What remove_texture returns: numpy arrays (views into the "
                                  "result, no copies) and the report.")
      .def_property_readonly(
          "positions",
          [](py::object self) {
            return rows_view(self.cast<RemoveTextureResult&>().positions, self);
          },
          doc("RemoveTextureResult.positions").c_str())
      .def_property_readonly(
          "normals",
          [](py::object self) {
            return rows_view(self.cast<RemoveTextureResult&>().normals, self);
          },
          doc("RemoveTextureResult.normals").c_str())
      .def_property_readonly(
          "input_normals",
          [](py::object self) {
            return rows_view(self.cast<RemoveTextureResult&>().input_normals, self);
          },
          doc("RemoveTextureResult.input_normals").c_str())
      .def_property_readonly(
          "is_texture",
          [](py::object self) {
            return bool_view(self.cast<RemoveTextureResult&>().is_texture, self);
          },
          (doc("RemoveTextureResult.is_texture") + " (bool)").c_str())
      .def_property_readonly(
          "texture_height",
          [](py::object self) {
            const auto& h = self.cast<RemoveTextureResult&>().texture_height;
            return py::array_t<double>({static_cast<py::ssize_t>(h.size())}, h.data(), self);
          },
          doc("RemoveTextureResult.texture_height").c_str())
      .def_readonly("report", &RemoveTextureResult::report, "The RemoveTextureReport")
      .def("__len__", [](const RemoveTextureResult& r) { return r.positions.rows(); })
      .def("__repr__", [](const RemoveTextureResult& r) {
        return "<detexture.RemoveTextureResult: " + std::to_string(r.positions.rows()) +
               " points, " + std::to_string(r.report.texture_points) +
               " texture, r = " + number_text(r.report.radius) + ">";
      });

  // The docstring names the enums registered above.
  static const std::string remove_doc = remove_texture_doc(m);
  m.def(
      "remove_texture",
      [](py::handle points, const py::object& normals, const py::kwargs& kwargs) {
        return run(points, normals, kwargs);
      },
      py::arg("points"), py::arg("normals") = py::none(), remove_doc.c_str());

  m.def(
      "default_parameters", [] { return default_params<RemoveTextureParams>(); },
      "default_parameters() -> dict\n\nThe keywords of remove_texture and their defaults, read "
      "from a default-constructed C++ RemoveTextureParams.");

  m.def(
      "detextured_cloud",
      [](const PointCloud& cloud, const RemoveTextureResult& result, bool texture_fields) {
        return detextured_cloud(cloud, result, texture_fields);
      },
      py::arg("cloud"), py::arg("result"), py::arg("texture_fields") = false,
      ("detextured_cloud(cloud, result, texture_fields=False) -> PointCloud\n\n" +
       doc("detextured_cloud") + "\n\n" + doc("add_texture_fields"))
          .c_str());
  m.def(
      "texture_layer",
      [](const PointCloud& cloud, const RemoveTextureResult& result) {
        return texture_layer(cloud, result);
      },
      py::arg("cloud"), py::arg("result"),
      ("texture_layer(cloud, result) -> PointCloud\n\n" + doc("texture_layer")).c_str());
}

}  // namespace detexture::python
