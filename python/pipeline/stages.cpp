// The stages of the method run alone, for callers who reuse neighborhoods or
// swap a stage: detect_texture (Eq. 2), drop_neighbors_across_surfaces,
// filter_normals_gaussian (Eq. 1), filter_normals_rolling (Eqs. 3-8),
// update_positions (Eqs. 9-10), limit_counter_moves, limit_tip_moves,
// limit_sink_moves and lower_raised_cells (after the update),
// fit_normals_to_positions and keep_input_normals (output normals).
// Keywords come from each stage's Params struct (params.h); results are
// dicts of arrays and counts, named as the C++ result members.
#include <pybind11/stl.h>

#include <utility>

#include "detexture/geometry/radius_neighborhoods.h"
#include "detexture/pipeline/detect_texture.h"
#include "detexture/pipeline/drop_neighbors_across_surfaces.h"
#include "detexture/pipeline/filter_normals_gaussian.h"
#include "detexture/pipeline/filter_normals_rolling.h"
#include "detexture/pipeline/fit_normals_to_positions.h"
#include "detexture/pipeline/keep_input_normals.h"
#include "detexture/pipeline/limit_counter_moves.h"
#include "detexture/pipeline/limit_sink_moves.h"
#include "detexture/pipeline/limit_tip_moves.h"
#include "detexture/pipeline/lower_raised_cells.h"
#include "detexture/pipeline/update_positions.h"
#include "module.h"
#include "params.h"

namespace detexture::python {
namespace {

void check_neighborhoods(const Matrix3& P, const Neighborhoods& R) {
  if (R.size() != static_cast<std::size_t>(P.rows()))
    throw py::value_error("the neighborhoods are of " + std::to_string(R.size()) +
                          " points but there are " + std::to_string(P.rows()) +
                          "; build them on these points (radius_neighborhoods)");
}

// Points and their normals for a stage run on neighborhoods R, checked
// against each other and against R.
std::pair<Positions, Normals> points_and_normals(const py::object& points,
                                                 const py::object& normals,
                                                 const Neighborhoods& R) {
  Positions P = to_matrix3(points, "points");
  Normals N = to_matrix3(normals, "normals");
  check_rows(P, N, "normals");
  check_neighborhoods(P, R);
  return {std::move(P), std::move(N)};
}

std::vector<float> omega_of(const py::object& omega, std::size_t n) {
  return omega.is_none() ? std::vector<float>() : to_vector<float>(omega, "omega", n);
}

template <class Params>
std::string stage_doc(const py::module_& m, const std::string& name, const std::string& args,
                      const std::string& returns, const std::string& params_struct) {
  const auto [keywords, list] = params_doc<Params>(m);
  return name + "(" + args + ", *" + keywords + ") -> dict\n\n" +
         wrap("Returns a dict: " + returns + ". Keywords are the members of the C++ " +
                  params_struct +
                  " (defaults and docs below, from the header); lengths are in "
                  "the cloud's units.",
              "") +
         "\nC++: " + wrap(doc(name), "") + "\nParameters\n----------\n" + list;
}

}  // namespace

void bind_stages(py::module_& m) {
  static const std::string detect_doc = stage_doc<DetectTextureParams>(
      m, "detect_texture", "points, neighborhoods, normals=None",
      "is_texture (bool), inliers, members, omega, height, surface_normal (with "
      "surface_normals=True), texture_points, no_plane, mean_iterations",
      "DetectTextureParams");
  m.def(
      "detect_texture",
      [](const py::object& points, const Neighborhoods& R, const py::object& normals,
         const py::kwargs& kwargs) {
        const auto params = params_from_kwargs<DetectTextureParams>(kwargs, "detect_texture");
        validate(params);
        const Positions P = to_matrix3(points, "points");
        check_neighborhoods(P, R);
        Normals N;
        if (!normals.is_none()) {
          N = to_matrix3(normals, "normals", true);
          check_rows(P, N, "normals");
        }
        TextureDetection t;
        {
          py::gil_scoped_release release;
          t = detect_texture(P, N, R, params);
        }
        py::dict d;
        d["is_texture"] = py::array(to_array(std::move(t.is_texture))).attr("astype")("bool");
        d["inliers"] = to_array(std::move(t.inliers));
        d["members"] = to_array(std::move(t.members));
        d["omega"] = to_array(std::move(t.omega));
        d["height"] = to_array(std::move(t.height));
        if (params.surface_normals) d["surface_normal"] = to_array(std::move(t.surface_normal));
        d["texture_points"] = t.texture_points;
        d["no_plane"] = t.no_plane;
        d["mean_iterations"] = t.mean_iterations;
        return d;
      },
      py::arg("points"), py::arg("neighborhoods"), py::arg("normals") = py::none(),
      detect_doc.c_str());

  m.def(
      "drop_neighbors_across_surfaces",
      [](const Neighborhoods& R, const py::object& normals, const py::object& surface_normals,
         const py::object& is_texture, double max_angle_deg) {
        const Normals N = to_matrix3(normals, "normals");
        const Normals S = to_matrix3(surface_normals, "surface_normals");
        const std::vector<std::uint8_t> t =
            to_vector<std::uint8_t>(is_texture, "is_texture", R.size());
        Neighborhoods kept = R;
        std::size_t removed = 0;
        {
          py::gil_scoped_release release;
          removed = drop_neighbors_across_surfaces(kept, N, S, t, {max_angle_deg});
        }
        return py::make_tuple(std::move(kept), removed);
      },
      py::arg("neighborhoods"), py::arg("normals"), py::arg("surface_normals"),
      py::arg("is_texture"),
      py::arg("max_angle_deg") = DropNeighborsAcrossSurfacesParams{}.max_angle_deg,
      ("drop_neighbors_across_surfaces(neighborhoods, normals, surface_normals, is_texture, "
       "max_angle_deg=" +
       number_text(DropNeighborsAcrossSurfacesParams{}.max_angle_deg) +
       ") -> (Neighborhoods, removed)\n\nReturns a copy of the neighborhoods without the pairs "
       "neither of which lies on the other's surface; surface_normals is detect_texture's "
       "surface_normal (surface_normals=True).\n\nC++: " +
       doc("drop_neighbors_across_surfaces") +
       "\nmax_angle_deg: " + doc("DropNeighborsAcrossSurfacesParams.max_angle_deg"))
          .c_str());

  static const std::string gaussian_doc = stage_doc<FilterNormalsGaussianParams>(
      m, "filter_normals_gaussian", "points, normals, neighborhoods, omega=None",
      "normals, empty_subneighborhoods, zero_sum", "FilterNormalsGaussianParams");
  m.def(
      "filter_normals_gaussian",
      [](const py::object& points, const py::object& normals, const Neighborhoods& R,
         const py::object& omega, const py::kwargs& kwargs) {
        const auto params =
            params_from_kwargs<FilterNormalsGaussianParams>(kwargs, "filter_normals_gaussian");
        validate(params);
        const auto [P, N] = points_and_normals(points, normals, R);
        const std::vector<float> w = omega_of(omega, R.size());
        if (w.empty() && params.use_subneighborhood)
          throw py::value_error("omega is needed when use_subneighborhood is True");
        GaussianFilterResult g;
        {
          py::gil_scoped_release release;
          g = filter_normals_gaussian(P, N, R, w, params);
        }
        py::dict d;
        d["normals"] = to_array(std::move(g.normals));
        d["empty_subneighborhoods"] = g.empty_subneighborhoods;
        d["zero_sum"] = g.zero_sum;
        return d;
      },
      py::arg("points"), py::arg("normals"), py::arg("neighborhoods"),
      py::arg("omega") = py::none(), gaussian_doc.c_str());

  static const std::string rolling_doc = stage_doc<FilterNormalsRollingParams>(
      m, "filter_normals_rolling",
      "points, input_normals, initial_normals, neighborhoods, omega=None",
      "normals, iterations, last_change_deg", "FilterNormalsRollingParams");
  m.def(
      "filter_normals_rolling",
      [](const py::object& points, const py::object& input, const py::object& initial,
         const Neighborhoods& R, const py::object& omega, const py::kwargs& kwargs) {
        const auto params =
            params_from_kwargs<FilterNormalsRollingParams>(kwargs, "filter_normals_rolling");
        validate(params);
        const Positions P = to_matrix3(points, "points");
        const Normals in = to_matrix3(input, "input_normals");
        Normals start = to_matrix3(initial, "initial_normals");
        check_rows(P, in, "input_normals");
        check_rows(P, start, "initial_normals");
        check_neighborhoods(P, R);
        const std::vector<float> w = omega_of(omega, R.size());
        if (w.empty() && params.use_subneighborhood)
          throw py::value_error("omega is needed when use_subneighborhood is True");
        RollingFilterResult r;
        {
          py::gil_scoped_release release;
          r = filter_normals_rolling(P, in, std::move(start), R, w, params);
        }
        py::dict d;
        d["normals"] = to_array(std::move(r.normals));
        d["iterations"] = r.iterations;
        d["last_change_deg"] = r.last_change_deg;
        return d;
      },
      py::arg("points"), py::arg("input_normals"), py::arg("initial_normals"),
      py::arg("neighborhoods"), py::arg("omega") = py::none(), rolling_doc.c_str());

  static const std::string update_doc = stage_doc<UpdatePositionsParams>(
      m, "update_positions", "points, normals, neighborhoods, is_texture=None",
      "positions, iterations, isolated, mean_displacement, limited", "UpdatePositionsParams");
  m.def(
      "update_positions",
      [](const py::object& points, const py::object& normals, const Neighborhoods& R,
         const py::object& is_texture, const py::kwargs& kwargs) {
        const auto params = params_from_kwargs<UpdatePositionsParams>(kwargs, "update_positions");
        validate(params);
        const auto [P, N] = points_and_normals(points, normals, R);
        const std::vector<std::uint8_t> t =
            is_texture.is_none() ? std::vector<std::uint8_t>()
                                 : to_vector<std::uint8_t>(is_texture, "is_texture", R.size());
        if (t.empty() && params.mode == UpdateMode::Global)
          throw py::value_error("is_texture is needed by the global update (update mode Global)");
        UpdatePositionsResult u;
        {
          py::gil_scoped_release release;
          u = update_positions(P, N, R, t, params);
        }
        py::dict d;
        d["positions"] = to_array(std::move(u.positions));
        d["iterations"] = u.iterations;
        d["isolated"] = u.isolated;
        d["mean_displacement"] = u.mean_displacement;
        d["limited"] = u.limited;
        return d;
      },
      py::arg("points"), py::arg("normals"), py::arg("neighborhoods"),
      py::arg("is_texture") = py::none(), update_doc.c_str());

  static const std::string fit_doc = stage_doc<FitNormalsToPositionsParams>(
      m, "fit_normals_to_positions", "points, normals, neighborhoods, range_normals=None",
      "normals, kept, blended, open, open_blended, waves", "FitNormalsToPositionsParams");
  m.def(
      "fit_normals_to_positions",
      [](const py::object& points, const py::object& normals, const Neighborhoods& R,
         const py::object& range_normals, const py::kwargs& kwargs) {
        const auto params =
            params_from_kwargs<FitNormalsToPositionsParams>(kwargs, "fit_normals_to_positions");
        validate(params);
        const auto [P, N] = points_and_normals(points, normals, R);
        // None: the range weights read the normals themselves.
        const Normals M = range_normals.is_none() ? N : to_matrix3(range_normals, "range_normals");
        check_rows(P, M, "range_normals");
        FitNormalsToPositionsResult f;
        {
          py::gil_scoped_release release;
          f = fit_normals_to_positions(P, N, M, R, params);
        }
        py::dict d;
        d["normals"] = to_array(std::move(f.normals));
        d["kept"] = f.kept;
        d["blended"] = f.blended;
        // The open window's output and the waves-left flags (None without
        // the blend, or with waves_min_deg 0).
        d["open"] = f.open.rows() ? py::object(to_array(std::move(f.open))) : py::none();
        d["open_blended"] = f.open_blended;
        d["waves"] =
            f.waves.empty()
                ? py::object(py::none())
                : py::object(py::array_t<bool>(static_cast<py::ssize_t>(f.waves.size()),
                                               reinterpret_cast<const bool*>(f.waves.data())));
        return d;
      },
      py::arg("points"), py::arg("normals"), py::arg("neighborhoods"),
      py::arg("range_normals") = py::none(), fit_doc.c_str());

  static const std::string keep_doc = stage_doc<KeepInputNormalsParams>(
      m, "keep_input_normals",
      "points, updated, input_normals, normals, neighborhoods, is_texture=None", "normals, kept",
      "KeepInputNormalsParams");
  m.def(
      "keep_input_normals",
      [](const py::object& points, const py::object& updated, const py::object& input_normals,
         const py::object& normals, const Neighborhoods& R, const py::object& is_texture,
         const py::kwargs& kwargs) {
        const auto params =
            params_from_kwargs<KeepInputNormalsParams>(kwargs, "keep_input_normals");
        validate(params);
        const auto [P, N] = points_and_normals(points, normals, R);
        const Positions Q = to_matrix3(updated, "updated");
        const Normals G = to_matrix3(input_normals, "input_normals");
        check_rows(P, Q, "updated");
        check_rows(P, G, "input_normals");
        const std::vector<std::uint8_t> t =
            is_texture.is_none() ? std::vector<std::uint8_t>()
                                 : to_vector<std::uint8_t>(is_texture, "is_texture", R.size());
        KeepInputNormalsResult k;
        {
          py::gil_scoped_release release;
          k = keep_input_normals(P, Q, G, N, t, R, params);
        }
        py::dict d;
        d["normals"] = to_array(std::move(k.normals));
        d["kept"] = k.kept;
        return d;
      },
      py::arg("points"), py::arg("updated"), py::arg("input_normals"), py::arg("normals"),
      py::arg("neighborhoods"), py::arg("is_texture") = py::none(), keep_doc.c_str());

  static const std::string counter_doc = stage_doc<LimitCounterMovesParams>(
      m, "limit_counter_moves", "points, updated, normals, is_texture, released=None",
      "positions, lean, side, limited", "LimitCounterMovesParams");
  m.def(
      "limit_counter_moves",
      [](const py::object& points, const py::object& updated, const py::object& normals,
         const py::object& is_texture, const py::object& released, const py::kwargs& kwargs) {
        const auto params =
            params_from_kwargs<LimitCounterMovesParams>(kwargs, "limit_counter_moves");
        validate(params);
        const Positions P = to_matrix3(points, "points");
        const Positions Q = to_matrix3(updated, "updated");
        const Normals N = to_matrix3(normals, "normals");
        check_rows(P, Q, "updated");
        check_rows(P, N, "normals");
        const std::vector<std::uint8_t> t =
            to_vector<std::uint8_t>(is_texture, "is_texture", static_cast<std::size_t>(P.rows()));
        const std::vector<std::uint8_t> r =
            released.is_none()
                ? std::vector<std::uint8_t>()
                : to_vector<std::uint8_t>(released, "released", static_cast<std::size_t>(P.rows()));
        LimitCounterMovesResult c;
        {
          py::gil_scoped_release release;
          c = limit_counter_moves(P, Q, N, t, params, r);
        }
        py::dict d;
        d["positions"] = to_array(std::move(c.positions));
        d["lean"] = c.lean;
        d["side"] = c.side;
        d["limited"] = c.limited;
        return d;
      },
      py::arg("points"), py::arg("updated"), py::arg("normals"), py::arg("is_texture"),
      py::arg("released") = py::none(), counter_doc.c_str());

  static const std::string tip_doc = stage_doc<LimitTipMovesParams>(
      m, "limit_tip_moves", "points, updated, normals, neighborhoods", "positions, limited",
      "LimitTipMovesParams");
  m.def(
      "limit_tip_moves",
      [](const py::object& points, const py::object& updated, const py::object& normals,
         const Neighborhoods& R, const py::kwargs& kwargs) {
        const auto params = params_from_kwargs<LimitTipMovesParams>(kwargs, "limit_tip_moves");
        validate(params);
        const auto [P, N] = points_and_normals(points, normals, R);
        const Positions Q = to_matrix3(updated, "updated");
        check_rows(P, Q, "updated");
        LimitTipMovesResult c;
        {
          py::gil_scoped_release release;
          c = limit_tip_moves(P, Q, N, R, params);
        }
        py::dict d;
        d["positions"] = to_array(std::move(c.positions));
        d["limited"] = c.limited;
        return d;
      },
      py::arg("points"), py::arg("updated"), py::arg("normals"), py::arg("neighborhoods"),
      tip_doc.c_str());

  static const std::string sink_doc = stage_doc<LimitSinkMovesParams>(
      m, "limit_sink_moves", "points, updated, normals, surface_height, neighborhoods, raised",
      "positions, limited", "LimitSinkMovesParams");
  m.def(
      "limit_sink_moves",
      [](const py::object& points, const py::object& updated, const py::object& normals,
         const py::object& surface_height, const Neighborhoods& R, bool raised,
         const py::kwargs& kwargs) {
        const auto params = params_from_kwargs<LimitSinkMovesParams>(kwargs, "limit_sink_moves");
        validate(params);
        const auto [P, N] = points_and_normals(points, normals, R);
        const Positions Q = to_matrix3(updated, "updated");
        check_rows(P, Q, "updated");
        const std::vector<float> h =
            to_vector<float>(surface_height, "surface_height", static_cast<std::size_t>(P.rows()));
        LimitSinkMovesResult c;
        {
          py::gil_scoped_release release;
          c = limit_sink_moves(P, Q, N, h, R, raised, params);
        }
        py::dict d;
        d["positions"] = to_array(std::move(c.positions));
        d["limited"] = c.limited;
        return d;
      },
      py::arg("points"), py::arg("updated"), py::arg("normals"), py::arg("surface_height"),
      py::arg("neighborhoods"), py::arg("raised"), sink_doc.c_str());

  static const std::string cells_doc = stage_doc<LowerRaisedCellsParams>(
      m, "lower_raised_cells", "points, updated, normals, is_texture, lean, neighborhoods",
      "positions, applied, lowered, limited, turned", "LowerRaisedCellsParams");
  m.def(
      "lower_raised_cells",
      [](const py::object& points, const py::object& updated, const py::object& normals,
         const py::object& is_texture, double lean, const Neighborhoods& R,
         const py::kwargs& kwargs) {
        const auto params =
            params_from_kwargs<LowerRaisedCellsParams>(kwargs, "lower_raised_cells");
        validate(params);
        const auto [P, N] = points_and_normals(points, normals, R);
        const Positions Q = to_matrix3(updated, "updated");
        check_rows(P, Q, "updated");
        const std::vector<std::uint8_t> t =
            to_vector<std::uint8_t>(is_texture, "is_texture", static_cast<std::size_t>(P.rows()));
        LowerRaisedCellsResult c;
        {
          py::gil_scoped_release release;
          c = lower_raised_cells(P, Q, N, t, lean, R, params);
        }
        py::dict d;
        d["positions"] = to_array(std::move(c.positions));
        d["applied"] = c.applied;
        d["lowered"] = c.lowered;
        d["limited"] = c.limited;
        d["turned"] = c.turned;
        return d;
      },
      py::arg("points"), py::arg("updated"), py::arg("normals"), py::arg("is_texture"),
      py::arg("lean"), py::arg("neighborhoods"), cells_doc.c_str());
}

}  // namespace detexture::python
