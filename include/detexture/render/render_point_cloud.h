// Pictures of point clouds and meshes, drawn in software: no display, no GPU.
//
// An orthographic view fitted to all clouds at once (one scale for every
// panel, so a before/after pair is comparable pixel for pixel), a z-buffer,
// and Lambert shading with a little ambient light from the normals. Shading
// is two-sided (|n·l|), so the sign of the normals does not matter: unoriented
// PCA normals shade like oriented ones. Points are drawn as screen-space
// discs; triangles, when given, are rasterized with the vertex normals
// interpolated across them (and the points themselves are not drawn).
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <string>
#include <vector>

#include "detexture/types.h"

namespace detexture {

/// An 8-bit RGB picture, rows top to bottom, 3 bytes per pixel.
struct Image {
  int width = 0;
  int height = 0;
  std::vector<std::uint8_t> rgb;  ///< width * height * 3 bytes

  /// The colour of pixel (x, y), x to the right and y down from the top left.
  std::array<std::uint8_t, 3> pixel(int x, int y) const {
    const std::size_t i = 3 * (static_cast<std::size_t>(y) * width + x);
    return {rgb[i], rgb[i + 1], rgb[i + 2]};
  }
};

/// #T by 3 vertex indices of triangles (rows of RenderCloud::positions).
using Triangles = Eigen::Matrix<std::uint32_t, Eigen::Dynamic, 3, Eigen::RowMajor>;

/// One cloud (one panel) to draw.
struct RenderCloud {
  Positions positions;  ///< #P by 3
  /// #P by 3 normals of any sign and length, or 0 rows: then the vertex
  /// normals of the triangles (area-weighted) if there are triangles, else PCA
  /// normals of the RenderParams::normal_neighbors nearest points.
  Normals normals;
  std::vector<double> scalar;  ///< #P values to colour by, or empty for the plain surface colour
  Triangles triangles;         ///< #T by 3; empty: draw the points
  std::string label;           ///< UTF-8 text above the panel (e.g. the file name); may be empty
};

/// Where the camera looks from. The up axis of the scene points up in the
/// picture (except looking straight along it). With up = z: azimuth 0 and
/// elevation 0 look from -y towards +y with +x to the right ("front"),
/// azimuth 90 from +x ("right"), elevation 90 from +z down ("top", +y up in
/// the picture).
struct ViewAngles {
  double azimuth_deg =
      35.0;  ///< turn about the up axis, degrees, counter-clockwise seen from above
  double elevation_deg = 25.0;  ///< degrees above the horizontal plane, in [-90, 90]
};

/// "AZIMUTH,ELEVATION" in degrees ("30,20") or a name: front (0,0), back
/// (180,0), right (90,0), left (-90,0), top (0,90), bottom (0,-90), iso
/// (45,35.26: the cube's diagonal). Throws std::invalid_argument with a
/// sentence for anything else, or an elevation outside [-90, 90].
ViewAngles parse_view(const std::string& text);

enum class UpAxis { X, Y, Z };
/// Parse "x", "y" or "z"; throws std::invalid_argument otherwise.
UpAxis parse_up_axis(const std::string& text);
const char* up_axis_name(UpAxis axis);

enum class ColorMap {
  Auto,       ///< Diverging when the range has both signs, Viridis otherwise
  Viridis,    ///< dark blue -> green -> yellow, for fields of one sign
  Diverging,  ///< blue -> white (the range's middle, 0 by default) -> red, for signed fields
};
/// Parse "auto", "viridis" or "diverging"; throws std::invalid_argument otherwise.
ColorMap parse_color_map(const std::string& text);
const char* color_map_name(ColorMap map);

/// The colour of t in [0, 1] (clamped) on a map (Viridis or Diverging), as
/// 8-bit RGB: t = 0 is the low end, 1 the high end.
std::array<std::uint8_t, 3> color_map_rgb(ColorMap map, double t);

struct RenderParams {
  int width = 1200;       ///< image width in pixels, in [16, 16384]
  int height = 600;       ///< image height in pixels, in [16, 16384]
  ViewAngles view;        ///< camera direction, shared by all panels
  UpAxis up = UpAxis::Z;  ///< the scene's up axis
  /// Diameter of a point's disc in pixels, in [0, 64]; 0 = automatic: 1.5
  /// times the median distance to the 8th nearest point, on screen, at least
  /// 1. On a grid of spacing s the discs then have radius 1.06 s and close
  /// the grid; on uniformly random samples (density ρ) the chance that a
  /// pixel is left uncovered is exp(-πR²ρ) = exp(-4.5·(r8/r̄8)²) ≈ 1%,
  /// with r̄8 = sqrt(8/(πρ)) the mean 8th-neighbour distance.
  double point_size = 0.0;
  int normal_neighbors = 16;  ///< k of the PCA normals of clouds without normals, in [3, 256]
  /// Share of the light that reaches every surface whatever its normal, in
  /// [0, 1]; the rest is Lambertian, so a surface facing the light is drawn
  /// in its full colour and one edge-on at `ambient` times it.
  double ambient = 0.25;
  /// Direction of the light from the surface, relative to the view: degrees
  /// to the left of and above the viewing direction, in [-89, 89]. (0, 0) is
  /// a headlight. Slightly off-axis light shows relief better.
  double light_left_deg = 30.0;
  double light_up_deg = 45.0;
  std::array<std::uint8_t, 3> background = {255, 255, 255};
  std::array<std::uint8_t, 3> surface_color = {200, 200, 205};  ///< when not coloured by a scalar
  int margin = 12;  ///< pixels left empty around each panel's drawing, >= 0
  ColorMap color_map = ColorMap::Auto;
  /// Scalar values mapped to the ends of the colour map; NaN = from the data
  /// (over all clouds; made symmetric about 0 for the diverging map when
  /// both are NaN). Values outside are clamped to the end colours. The
  /// diverging map's white is the middle of the range.
  double range_min = std::numeric_limits<double>::quiet_NaN();
  double range_max = std::numeric_limits<double>::quiet_NaN();
  bool color_bar = true;  ///< draw a colour bar with the range's labels when colouring
  bool labels = true;     ///< print each cloud's label above its panel
  /// Size in pixels of a dot of the 5x7 font, in [0, 8]; 0 = 2 for images
  /// taller than 500 px, else 1.
  int text_scale = 0;
};

/// Throws std::invalid_argument with a sentence naming the parameter if any
/// is out of its range (render_point_clouds calls it first; callers may call
/// it before reading their inputs).
void validate(const RenderParams& params);

struct RenderReport {
  std::vector<double> point_size;  ///< disc diameter used for each cloud, pixels; 0 for a mesh
  std::vector<std::size_t> estimated_normals;  ///< per cloud: normals computed (0 if given)
  ColorMap color_map = ColorMap::Auto;         ///< the map used (Auto resolved), when colouring
  double range_min = 0.0, range_max = 0.0;     ///< the scalar range used, when colouring
  double pixels_per_unit = 0.0;                ///< the common scale of the panels
};

/// Draw the clouds side by side, one panel each from left to right, in one
/// image of params.width x params.height. Every panel shares the view and the
/// scale: the projection of all points of all clouds, centred, fills the
/// panel less its margins (and the label line). When any cloud has a scalar,
/// the clouds with one are coloured by it on one common range and a colour
/// bar is drawn at the right edge; the others get the surface colour.
/// Scalars that are NaN or infinite are drawn in the surface colour.
///
/// Throws std::invalid_argument with a sentence for parameters out of range,
/// no clouds, an empty cloud, sizes that disagree (normals, scalar), a
/// triangle index out of range, non-finite coordinates, an empty range
/// (range_min >= range_max when both are given, or one end given beyond the
/// data's other end), or panels too narrow for their margins.
Image render_point_clouds(const std::vector<RenderCloud>& clouds, const RenderParams& params = {},
                          RenderReport* report = nullptr);

/// One cloud alone: render_point_clouds({cloud}, params, report).
Image render_point_cloud(const RenderCloud& cloud, const RenderParams& params = {},
                         RenderReport* report = nullptr);

}  // namespace detexture
