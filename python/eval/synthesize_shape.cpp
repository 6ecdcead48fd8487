// detexture.synthesize (eval/synthesize_shape.h) and detexture.compare
// (eval/compare_to_ground_truth.h): the command line's synth and compare.
#include "detexture/eval/synthesize_shape.h"

#include <pybind11/stl.h>

#include "detexture/eval/compare_to_ground_truth.h"
#include "module.h"

namespace detexture::python {

void bind_synthesize_shape(py::module_& m) {
  py::class_<SynthesizedShape>(m, "SynthesizedShape",
                               "A textured shape with its exact ground truth (arrays are copies).")
      .def_property_readonly("positions",
                             [](const SynthesizedShape& s) { return to_array(s.positions); })
      .def_property_readonly("normals",
                             [](const SynthesizedShape& s) { return to_array(s.normals); })
      .def_property_readonly("texture_heights",
                             [](const SynthesizedShape& s) { return to_array(s.texture_heights); })
      .def_property_readonly("is_texture",
                             [](const SynthesizedShape& s) {
                               return py::array(to_array(s.is_texture)).attr("astype")("bool");
                             })
      .def_property_readonly("base_positions",
                             [](const SynthesizedShape& s) { return to_array(s.base_positions); })
      .def_property_readonly("base_normals",
                             [](const SynthesizedShape& s) { return to_array(s.base_normals); })
      .def_property_readonly(
          "ground_truth_positions",
          [](const SynthesizedShape& s) { return to_array(s.ground_truth_positions); })
      .def_property_readonly(
          "ground_truth_normals",
          [](const SynthesizedShape& s) { return to_array(s.ground_truth_normals); })
      .def_readonly("feature_count", &SynthesizedShape::feature_count)
      .def_readonly("area", &SynthesizedShape::area)
      .def_readonly("diagonal", &SynthesizedShape::diagonal)
      .def_readonly("noise_sigma", &SynthesizedShape::noise_sigma);

  const SynthParams d;  // the defaults shown are the library's
  m.def(
      "synthesize",
      [](const std::string& shape, const std::string& texture, const std::string& layout,
         double size, double amplitude, bool mixed_signs, std::int64_t points,
         std::int64_t ground_truth_points, double noise, bool noise_absolute, std::uint64_t seed) {
        SynthParams p;
        p.shape = parse_base_shape(shape);
        p.texture = parse_texture_kind(texture);
        p.layout = parse_texture_layout(layout);
        p.size = size;
        p.amplitude = amplitude;
        p.mixed_signs = mixed_signs;
        p.points = points;
        p.ground_truth_points = ground_truth_points;
        p.noise = noise;
        p.noise_absolute = noise_absolute;
        p.seed = seed;
        validate_synth_params(p);
        py::gil_scoped_release release;
        return synthesize_shape(p);
      },
      py::kw_only(), py::arg("shape") = base_shape_name(d.shape),
      py::arg("texture") = texture_kind_name(d.texture),
      py::arg("layout") = texture_layout_name(d.layout), py::arg("size") = d.size,
      py::arg("amplitude") = d.amplitude, py::arg("mixed_signs") = d.mixed_signs,
      py::arg("points") = d.points, py::arg("ground_truth_points") = d.ground_truth_points,
      py::arg("noise") = d.noise, py::arg("noise_absolute") = d.noise_absolute,
      py::arg("seed") = d.seed,
      ("synthesize(*, shape='" + std::string(base_shape_name(d.shape)) + "', texture='" +
       texture_kind_name(d.texture) + "', layout='" + texture_layout_name(d.layout) +
       "', size=" + number_text(d.size) + ", amplitude=" + number_text(d.amplitude) +
       ", mixed_signs=False, points=" + std::to_string(d.points) +
       ", ground_truth_points=" + std::to_string(d.ground_truth_points) +
       ", noise=0, noise_absolute=False, seed=" + std::to_string(d.seed) +
       ") -> SynthesizedShape\n\nThe command line's `detexture synth` (its --help explains "
       "every option; the names are the same). " +
       doc("synthesize_shape"))
          .c_str());

  m.def(
      "compare",
      [](const py::object& result, const py::object& result_normals, const py::object& ground_truth,
         const py::object& ground_truth_normals) {
        const Positions R = to_matrix3(result, "result");
        const Normals RN = result_normals.is_none()
                               ? Normals()
                               : to_matrix3(result_normals, "result_normals", true);
        const Positions G = to_matrix3(ground_truth, "ground_truth");
        const Normals GN = to_matrix3(ground_truth_normals, "ground_truth_normals");
        std::string json;
        {
          py::gil_scoped_release release;
          json = comparison_to_json(compare_to_ground_truth(R, RN, G, GN));
        }
        return py::module_::import("json").attr("loads")(json);
      },
      py::arg("result"), py::arg("result_normals"), py::arg("ground_truth"),
      py::arg("ground_truth_normals"),
      ("compare(result, result_normals, ground_truth, ground_truth_normals) -> dict\n\nThe "
       "command line's `detexture compare --json`, as a dict with the same keys. "
       "result_normals may be None.\n\n" +
       doc("compare_to_ground_truth") + "\n\nKeys: " + doc("comparison_to_json"))
          .c_str());
}

}  // namespace detexture::python
