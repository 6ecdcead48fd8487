#include "detexture/render/render_point_cloud.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <stdexcept>
#include <string>

#include "bitmap_font.h"
#include "detexture/geometry/estimate_normals.h"
#include "detexture/geometry/point_index.h"
#include "detexture/geometry/radius_neighborhoods.h"

namespace detexture {
namespace {

using Eigen::Vector3d;
using Rgb = std::array<std::uint8_t, 3>;
constexpr double kDegree = M_PI / 180.0;

std::string lower(std::string s) {
  for (char& c : s) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return s;
}

// Camera axes in the scene's frame: `toward` points from the scene to the
// camera, `right` and `up` span the picture.
struct Camera {
  Vector3d right, up, toward, light;
};

Camera make_camera(const RenderParams& p) {
  const double az = p.view.azimuth_deg * kDegree, el = p.view.elevation_deg * kDegree;
  // In a z-up frame; then turned so that frame z is the scene's up axis.
  Vector3d c(std::sin(az) * std::cos(el), -std::cos(az) * std::cos(el), std::sin(el));
  Vector3d r(std::cos(az), std::sin(az), 0.0);
  Vector3d u = c.cross(r);
  Eigen::Matrix3d frame = Eigen::Matrix3d::Identity();  // columns: the frame's x, y, z
  switch (p.up) {
    case UpAxis::Z:
      frame.setIdentity();
      break;
    case UpAxis::Y:
      frame << 1, 0, 0, 0, 0, 1, 0, -1, 0;
      break;  // front looks along -z
    case UpAxis::X:
      frame << 0, 0, 1, 1, 0, 0, 0, 1, 0;
      break;  // front looks along +z
  }
  Camera cam;
  cam.toward = frame * c;
  cam.right = frame * r;
  cam.up = frame * u;
  const double left = p.light_left_deg * kDegree, high = p.light_up_deg * kDegree;
  cam.light = (std::cos(high) * std::cos(left) * cam.toward -
               std::cos(high) * std::sin(left) * cam.right + std::sin(high) * cam.up)
                  .normalized();
  return cam;
}

}  // namespace

void validate(const RenderParams& p) {
  auto bad = [](const std::string& what) { throw std::invalid_argument(what); };
  if (p.width < 16 || p.width > 16384 || p.height < 16 || p.height > 16384)
    bad("the image size must be between 16 and 16384 pixels each way, not " +
        std::to_string(p.width) + " x " + std::to_string(p.height));
  if (!(p.view.elevation_deg >= -90 && p.view.elevation_deg <= 90) ||
      !std::isfinite(p.view.azimuth_deg))
    bad("the view's elevation must be in [-90, 90] degrees and its azimuth finite");
  if (!(p.point_size >= 0 && p.point_size <= 64))
    bad("the point size must be in [0, 64] pixels (0 = automatic), not " +
        number_text(p.point_size));
  if (p.normal_neighbors < 3 || p.normal_neighbors > 256)
    bad("the neighbors for normals must be in [3, 256], not " + std::to_string(p.normal_neighbors));
  if (!(p.ambient >= 0 && p.ambient <= 1))
    bad("the ambient light must be in [0, 1], not " + number_text(p.ambient));
  if (!(std::abs(p.light_left_deg) <= 89 && std::abs(p.light_up_deg) <= 89))
    bad("the light's angles from the view must be in [-89, 89] degrees");
  if (p.margin < 0) bad("the margin cannot be negative");
  if (p.text_scale < 0 || p.text_scale > 8)
    bad("the text scale must be in [0, 8], not " + std::to_string(p.text_scale));
  const bool has_min = !std::isnan(p.range_min), has_max = !std::isnan(p.range_max);
  if ((has_min && !std::isfinite(p.range_min)) || (has_max && !std::isfinite(p.range_max)))
    bad("the colour range must be finite");
  if (has_min && has_max && !(p.range_min < p.range_max))
    bad("the colour range must have min < max, not " + number_text(p.range_min) + ", " +
        number_text(p.range_max));
}

namespace {

std::string cloud_name(const RenderCloud& c, std::size_t k) {
  return "cloud " + std::to_string(k + 1) + (c.label.empty() ? "" : " (" + c.label + ")");
}

void validate(const RenderCloud& c, std::size_t k) {
  const std::string name = cloud_name(c, k);
  const auto n = c.positions.rows();
  if (n == 0) throw std::invalid_argument(name + " has no points");
  if (c.normals.rows() != 0 && c.normals.rows() != n)
    throw std::invalid_argument(name + " has " + std::to_string(n) + " points but " +
                                std::to_string(c.normals.rows()) + " normals");
  if (!c.scalar.empty() && c.scalar.size() != static_cast<std::size_t>(n))
    throw std::invalid_argument(name + " has " + std::to_string(n) + " points but " +
                                std::to_string(c.scalar.size()) + " values to colour by");
  if (!c.positions.allFinite())
    throw std::invalid_argument(name + " has a NaN or infinite coordinate");
  if (c.triangles.size() > 0 && c.triangles.maxCoeff() >= static_cast<std::uint32_t>(n))
    throw std::invalid_argument(name + " has a triangle with a vertex index beyond its " +
                                std::to_string(n) + " points");
}

// Area-weighted vertex normals of a mesh: the sum of the (unnormalized)
// normals of the triangles around each vertex.
Normals mesh_normals(const RenderCloud& c) {
  Normals N = Normals::Zero(c.positions.rows(), 3);
  for (Eigen::Index t = 0; t < c.triangles.rows(); ++t) {
    const Eigen::RowVector3d a = c.positions.row(c.triangles(t, 0)),
                             b = c.positions.row(c.triangles(t, 1)),
                             d = c.positions.row(c.triangles(t, 2));
    const Eigen::RowVector3d n = (b - a).cross(d - a);
    for (int k = 0; k < 3; ++k) N.row(c.triangles(t, k)) += n;
  }
  return N;
}

// Median distance from a point to its 8th nearest other point, over a fixed
// subsample of at most ~4000 points (0 for fewer than 9 points). The 8th
// rather than the 1st: it measures the density whatever the sampling
// pattern (on a grid it is 1.4 spacings, on random samples a little more),
// where the nearest neighbour of random samples is often much closer than
// the gaps between them. knn: the k-nearest neighborhoods of P if already
// computed (rows sorted by distance, self first), else null.
double median_spacing8(const Positions& P, const Neighborhoods* knn) {
  constexpr std::size_t k = 8;
  const auto n = static_cast<std::size_t>(P.rows());
  if (n < k + 1) return 0.0;
  const std::size_t stride = std::max<std::size_t>(1, n / 4000);
  std::vector<double> d;
  if (knn && knn->size() == n && knn->count(0) > k) {
    for (std::size_t i = 0; i < n; i += stride)
      d.push_back((P.row(knn->begin(i)[k]) - P.row(i)).norm());
  } else {
    const PointIndex index(P);
    std::vector<std::uint32_t> found;
    std::vector<double> found_sq;
    for (std::size_t i = 0; i < n; i += stride) {
      const double q[3] = {P(i, 0), P(i, 1), P(i, 2)};
      index.nearest(q, k + 1, found, found_sq);  // the point itself comes first
      d.push_back(std::sqrt(found_sq.back()));
    }
  }
  std::nth_element(d.begin(), d.begin() + d.size() / 2, d.end());
  return d[d.size() / 2];
}

std::string number_label(double v) {
  char text[32];
  std::snprintf(text, sizeof text, "%.3g", v);
  return text;
}

// The image, its z-buffer (larger = nearer the camera) and a clip rectangle.
class Canvas {
 public:
  Canvas(int width, int height, const Rgb& background)
      : depth_(static_cast<std::size_t>(width) * height, -INFINITY) {
    image_.width = width;
    image_.height = height;
    image_.rgb.resize(3 * static_cast<std::size_t>(width) * height);
    for (std::size_t i = 0; i < image_.rgb.size(); i += 3)
      std::copy(background.begin(), background.end(), image_.rgb.begin() + i);
  }

  void clip(int x0, int y0, int x1, int y1) {
    x0_ = std::max(x0, 0);
    y0_ = std::max(y0, 0);
    x1_ = std::min(x1, image_.width);
    y1_ = std::min(y1, image_.height);
  }

  void plot(int x, int y, float depth, const Rgb& color) {
    if (x < x0_ || x >= x1_ || y < y0_ || y >= y1_) return;
    const std::size_t i = static_cast<std::size_t>(y) * image_.width + x;
    if (!(depth > depth_[i])) return;
    depth_[i] = depth;
    std::copy(color.begin(), color.end(), image_.rgb.begin() + 3 * i);
  }

  // A disc of diameter `size` centred at (x, y): the pixels whose centres lie
  // within it, and always the pixel holding the centre.
  void disc(double x, double y, double size, float depth, const Rgb& color) {
    const double r = 0.5 * size, r_sq = r * r;
    plot(static_cast<int>(std::floor(x)), static_cast<int>(std::floor(y)), depth, color);
    const int ya = static_cast<int>(std::floor(y - r)), yb = static_cast<int>(std::ceil(y + r));
    const int xa = static_cast<int>(std::floor(x - r)), xb = static_cast<int>(std::ceil(x + r));
    for (int py = std::max(ya, y0_); py <= std::min(yb, y1_ - 1); ++py)
      for (int px = std::max(xa, x0_); px <= std::min(xb, x1_ - 1); ++px) {
        const double dx = px + 0.5 - x, dy = py + 0.5 - y;
        if (dx * dx + dy * dy <= r_sq) plot(px, py, depth, color);
      }
  }

  void fill(int x0, int y0, int x1, int y1, const Rgb& color) {
    for (int y = std::max(y0, 0); y < std::min(y1, image_.height); ++y)
      for (int x = std::max(x0, 0); x < std::min(x1, image_.width); ++x)
        std::copy(color.begin(), color.end(),
                  image_.rgb.begin() + 3 * (static_cast<std::size_t>(y) * image_.width + x));
  }

  int clip_x0() const { return x0_; }
  int clip_x1() const { return x1_; }
  int clip_y0() const { return y0_; }
  int clip_y1() const { return y1_; }
  Image& image() { return image_; }

 private:
  Image image_;
  std::vector<float> depth_;
  int x0_ = 0, y0_ = 0, x1_ = 0, y1_ = 0;
};

// How a surface element is coloured: by its scalar on the range, or plainly.
struct Coloring {
  bool active = false;
  ColorMap map = ColorMap::Viridis;
  double lo = 0.0, hi = 1.0;
  Rgb surface{};

  Rgb base(double s) const {
    if (!active || !std::isfinite(s)) return surface;
    return color_map_rgb(map, hi > lo ? (s - lo) / (hi - lo) : 0.5);
  }
};

Rgb shade(const Rgb& base, const Vector3d& n, const Vector3d& light, double ambient) {
  const double length = n.norm();
  const double lambert = length > 0 ? std::abs(n.dot(light)) / length : 0.0;
  const double i = ambient + (1.0 - ambient) * std::min(lambert, 1.0);
  Rgb out;
  for (int k = 0; k < 3; ++k)
    out[k] = static_cast<std::uint8_t>(std::clamp(std::lround(base[k] * i), 0L, 255L));
  return out;
}

}  // namespace

ViewAngles parse_view(const std::string& text) {
  const std::string t = lower(text);
  if (t == "front") return {0, 0};
  if (t == "back") return {180, 0};
  if (t == "right") return {90, 0};
  if (t == "left") return {-90, 0};
  if (t == "top") return {0, 90};
  if (t == "bottom") return {0, -90};
  if (t == "iso") return {45, std::atan(1.0 / std::sqrt(2.0)) / kDegree};
  const std::size_t comma = t.find(',');
  if (comma != std::string::npos) {
    const std::string a = t.substr(0, comma), e = t.substr(comma + 1);
    char* end_a = nullptr;
    char* end_e = nullptr;
    const double az = std::strtod(a.c_str(), &end_a), el = std::strtod(e.c_str(), &end_e);
    if (!a.empty() && !e.empty() && *end_a == '\0' && *end_e == '\0' && std::isfinite(az) &&
        std::isfinite(el)) {
      if (!(el >= -90 && el <= 90))
        throw std::invalid_argument("the view's elevation must be in [-90, 90] degrees, not " + e);
      return {az, el};
    }
  }
  throw std::invalid_argument(
      "the view must be AZIMUTH,ELEVATION in degrees (e.g. 30,20) or "
      "one of front, back, left, right, top, bottom, iso; not '" +
      text + "'");
}

UpAxis parse_up_axis(const std::string& text) {
  const std::string t = lower(text);
  if (t == "x") return UpAxis::X;
  if (t == "y") return UpAxis::Y;
  if (t == "z") return UpAxis::Z;
  throw std::invalid_argument("the up axis must be x, y or z, not '" + text + "'");
}

const char* up_axis_name(UpAxis axis) {
  switch (axis) {
    case UpAxis::X:
      return "x";
    case UpAxis::Y:
      return "y";
    case UpAxis::Z:
      return "z";
  }
  return "?";
}

ColorMap parse_color_map(const std::string& text) {
  const std::string t = lower(text);
  if (t == "auto") return ColorMap::Auto;
  if (t == "viridis") return ColorMap::Viridis;
  if (t == "diverging") return ColorMap::Diverging;
  throw std::invalid_argument("the colour map must be auto, viridis or diverging, not '" + text +
                              "'");
}

const char* color_map_name(ColorMap map) {
  switch (map) {
    case ColorMap::Auto:
      return "auto";
    case ColorMap::Viridis:
      return "viridis";
    case ColorMap::Diverging:
      return "diverging";
  }
  return "?";
}

std::array<std::uint8_t, 3> color_map_rgb(ColorMap map, double t) {
  // Viridis (matplotlib) sampled at ten even steps; blue-white-red from
  // ColorBrewer's RdBu (9 classes, reversed). Linear in between.
  static const Rgb viridis[] = {{68, 1, 84},    {72, 40, 120},  {62, 74, 137},  {49, 104, 142},
                                {38, 130, 142}, {31, 158, 137}, {53, 183, 121}, {109, 205, 89},
                                {180, 222, 44}, {253, 231, 37}};
  static const Rgb diverging[] = {{33, 102, 172},  {67, 147, 195},  {146, 197, 222},
                                  {209, 229, 240}, {247, 247, 247}, {253, 219, 199},
                                  {244, 165, 130}, {214, 96, 77},   {178, 24, 43}};
  const Rgb* stops = map == ColorMap::Diverging ? diverging : viridis;
  const int n = map == ColorMap::Diverging ? 9 : 10;
  if (!(t >= 0)) t = 0;  // NaN too
  if (t > 1) t = 1;
  const double x = t * (n - 1);
  const int i = std::min(static_cast<int>(x), n - 2);
  const double f = x - i;
  Rgb out;
  for (int k = 0; k < 3; ++k)
    out[k] =
        static_cast<std::uint8_t>(std::lround(stops[i][k] + f * (stops[i + 1][k] - stops[i][k])));
  return out;
}

Image render_point_clouds(const std::vector<RenderCloud>& clouds, const RenderParams& params,
                          RenderReport* report) {
  validate(params);
  if (clouds.empty()) throw std::invalid_argument("there is no cloud to draw");
  for (std::size_t k = 0; k < clouds.size(); ++k) validate(clouds[k], k);
  RenderReport local;
  RenderReport& rep = report ? *report : local;
  rep = RenderReport();
  const Camera cam = make_camera(params);
  const int W = params.width, H = params.height;
  const int ts = params.text_scale > 0 ? params.text_scale : (H > 500 ? 2 : 1);
  const int text_h = render_detail::kGlyphHeight * ts;

  // The colour range, over every cloud that has a scalar.
  Coloring coloring;
  coloring.surface = params.surface_color;
  {
    double lo = INFINITY, hi = -INFINITY;
    bool any = false;
    for (const RenderCloud& c : clouds)
      for (double s : c.scalar)
        if (std::isfinite(s)) {
          lo = std::min(lo, s);
          hi = std::max(hi, s);
          any = true;
        }
    const bool given_lo = !std::isnan(params.range_min), given_hi = !std::isnan(params.range_max);
    if (any || (given_lo && given_hi)) {
      bool any_scalar = false;
      for (const RenderCloud& c : clouds) any_scalar = any_scalar || !c.scalar.empty();
      if (any_scalar) {
        if (given_lo) lo = params.range_min;
        if (given_hi) hi = params.range_max;
        if (lo > hi)
          throw std::invalid_argument(
              "the colour range's " + std::string(given_lo ? "min " : "max ") +
              number_text(given_lo ? lo : hi) + " lies beyond the data's other end, " +
              number_text(given_lo ? hi : lo) + "; give both ends");
        ColorMap map = params.color_map;
        if (map == ColorMap::Auto) map = lo < 0 && hi > 0 ? ColorMap::Diverging : ColorMap::Viridis;
        if (map == ColorMap::Diverging && !given_lo && !given_hi) {
          const double m = std::max(std::abs(lo), std::abs(hi));
          lo = -m;
          hi = m;
        }
        coloring.active = true;
        coloring.map = map;
        coloring.lo = lo;
        coloring.hi = hi;
        rep.color_map = map;
        rep.range_min = lo;
        rep.range_max = hi;
      }
    }
  }

  // Layout: panels side by side, a label line above them, the colour bar at
  // the right.
  bool any_label = false;
  for (const RenderCloud& c : clouds) any_label = any_label || !c.label.empty();
  const int label_h =
      params.labels && any_label ? text_h + render_detail::kGlyphDescent * ts + 2 * 3 * ts : 0;
  const bool bar = coloring.active && params.color_bar;
  std::vector<std::string> bar_labels;
  int bar_w = 0, bar_width = 0;
  if (bar) {
    bar_labels = {number_label(coloring.hi), number_label(coloring.lo)};
    if (coloring.map == ColorMap::Diverging)  // the white middle
      bar_labels.push_back(number_label(0.5 * (coloring.lo + coloring.hi)));
    int label_w = 0;
    for (const auto& s : bar_labels) label_w = std::max(label_w, render_detail::text_width(s, ts));
    bar_width = 10 * ts;
    bar_w = 6 * ts + bar_width + 4 * ts + label_w + 6 * ts;
  }
  const int n = static_cast<int>(clouds.size());
  const int panel_w = (W - bar_w) / n;
  const int draw_w = panel_w - 2 * params.margin, draw_h = H - label_h - 2 * params.margin;
  if (draw_w < 1 || draw_h < 1)
    throw std::invalid_argument("a " + std::to_string(W) + " x " + std::to_string(H) +
                                " image has no room left for " + std::to_string(n) +
                                " panels with their margins");

  // One scale for all panels: the projected extent of every point.
  double x_lo = INFINITY, x_hi = -INFINITY, y_lo = INFINITY, y_hi = -INFINITY;
  for (const RenderCloud& c : clouds) {
    const Eigen::VectorXd sx = c.positions * cam.right, sy = c.positions * cam.up;
    x_lo = std::min(x_lo, sx.minCoeff());
    x_hi = std::max(x_hi, sx.maxCoeff());
    y_lo = std::min(y_lo, sy.minCoeff());
    y_hi = std::max(y_hi, sy.maxCoeff());
  }
  const double x_range = x_hi - x_lo, y_range = y_hi - y_lo;
  double scale = INFINITY;
  if (x_range > 0) scale = std::min(scale, draw_w / x_range);
  if (y_range > 0) scale = std::min(scale, draw_h / y_range);
  if (!std::isfinite(scale)) scale = 1.0;  // a single point, or all in one place
  rep.pixels_per_unit = scale;
  const double xc = 0.5 * (x_lo + x_hi), yc = 0.5 * (y_lo + y_hi);
  // Depth is stored as float, measured from the first point, so that clouds
  // far from the origin keep its precision.
  const double zc = clouds[0].positions.row(0).dot(cam.toward.transpose());

  // Normals for the clouds that came without (after the checks above: it
  // is the slow part).
  std::vector<Normals> estimated(clouds.size());
  std::vector<double> spacing(clouds.size(), -1.0);  // for the point size; < 0: not yet known
  for (std::size_t k = 0; k < clouds.size(); ++k) {
    const RenderCloud& c = clouds[k];
    std::size_t count = 0;
    if (c.normals.rows() == 0) {
      if (c.triangles.rows() > 0) {
        estimated[k] = mesh_normals(c);
      } else {
        const Neighborhoods N = knn_neighborhoods(c.positions, params.normal_neighbors);
        estimated[k] = estimate_normals(c.positions, N).normals;
        spacing[k] = median_spacing8(c.positions, &N);
      }
      count = static_cast<std::size_t>(c.positions.rows());
    }
    rep.estimated_normals.push_back(count);
  }

  Canvas canvas(W, H, params.background);
  const double ambient = params.ambient;
  for (int k = 0; k < n; ++k) {
    const RenderCloud& c = clouds[k];
    const Normals& N = c.normals.rows() > 0 ? c.normals : estimated[k];
    const int x0 = k * panel_w;
    canvas.clip(x0, label_h, x0 + panel_w, H);
    const double cx = x0 + 0.5 * panel_w, cy = label_h + 0.5 * (H - label_h);
    const Eigen::Index count = c.positions.rows();
    // Screen positions and depth of every vertex.
    Eigen::Matrix<double, Eigen::Dynamic, 3, Eigen::RowMajor> S(count, 3);
    S.col(0) = ((c.positions * cam.right).array() - xc) * scale + cx;
    S.col(1) = cy - ((c.positions * cam.up).array() - yc) * scale;
    S.col(2) = (c.positions * cam.toward).array() - zc;
    const bool scalar = coloring.active && !c.scalar.empty();
    auto base = [&](double s) { return scalar ? coloring.base(s) : coloring.surface; };

    if (c.triangles.rows() == 0) {
      double size = params.point_size;
      if (size == 0)
        size = std::clamp(
            1.5 * (spacing[k] >= 0 ? spacing[k] : median_spacing8(c.positions, nullptr)) * scale,
            1.0, 64.0);
      rep.point_size.push_back(size);
      for (Eigen::Index i = 0; i < count; ++i) {
        const Rgb color =
            shade(base(scalar ? c.scalar[i] : 0.0), N.row(i).transpose(), cam.light, ambient);
        canvas.disc(S(i, 0), S(i, 1), size, static_cast<float>(S(i, 2)), color);
      }
      continue;
    }
    rep.point_size.push_back(0.0);
    for (Eigen::Index t = 0; t < c.triangles.rows(); ++t) {
      const std::uint32_t v[3] = {c.triangles(t, 0), c.triangles(t, 1), c.triangles(t, 2)};
      const double ax = S(v[0], 0), ay = S(v[0], 1), bx = S(v[1], 0), by = S(v[1], 1),
                   dx = S(v[2], 0), dy = S(v[2], 1);
      const double area = (bx - ax) * (dy - ay) - (by - ay) * (dx - ax);
      if (!(std::abs(area) > 0)) continue;  // edge-on: nothing to fill
      const int px0 =
          std::max(static_cast<int>(std::floor(std::min({ax, bx, dx}))), canvas.clip_x0());
      const int px1 =
          std::min(static_cast<int>(std::ceil(std::max({ax, bx, dx}))), canvas.clip_x1() - 1);
      const int py0 =
          std::max(static_cast<int>(std::floor(std::min({ay, by, dy}))), canvas.clip_y0());
      const int py1 =
          std::min(static_cast<int>(std::ceil(std::max({ay, by, dy}))), canvas.clip_y1() - 1);
      bool finite_scalar = scalar;
      for (int j = 0; j < 3 && scalar; ++j)
        finite_scalar = finite_scalar && std::isfinite(c.scalar[v[j]]);
      for (int py = py0; py <= py1; ++py)
        for (int px = px0; px <= px1; ++px) {
          const double qx = px + 0.5, qy = py + 0.5;
          // Barycentric weights of the pixel centre (any winding).
          const double w0 = ((bx - qx) * (dy - qy) - (by - qy) * (dx - qx)) / area;
          const double w1 = ((dx - qx) * (ay - qy) - (dy - qy) * (ax - qx)) / area;
          const double w2 = 1.0 - w0 - w1;
          if (w0 < 0 || w1 < 0 || w2 < 0) continue;
          const double depth = w0 * S(v[0], 2) + w1 * S(v[1], 2) + w2 * S(v[2], 2);
          // Blend unit normals, so that a long and a short input normal count alike.
          Vector3d normal = Vector3d::Zero();
          const double w[3] = {w0, w1, w2};
          for (int j = 0; j < 3; ++j) {
            const Vector3d nj = N.row(v[j]).transpose();
            const double len = nj.norm();
            if (len > 0) normal += w[j] * nj / len;
          }
          Rgb b = coloring.surface;
          if (finite_scalar)
            b = coloring.base(w0 * c.scalar[v[0]] + w1 * c.scalar[v[1]] + w2 * c.scalar[v[2]]);
          else if (scalar)
            b = coloring.base(NAN);
          canvas.plot(px, py, static_cast<float>(depth), shade(b, normal, cam.light, ambient));
        }
    }
  }

  Image& image = canvas.image();
  const Rgb ink = {40, 40, 40};
  if (label_h > 0)
    for (int k = 0; k < n; ++k) {
      const int x0 = k * panel_w;
      const int w = render_detail::text_width(clouds[k].label, ts);
      const int x = w <= panel_w - 4 * ts ? x0 + (panel_w - w) / 2 : x0 + 2 * ts;
      render_detail::draw_text(image, x, 3 * ts, clouds[k].label, ts, ink, x0, x0 + panel_w);
    }
  if (bar) {
    const int bx0 = W - bar_w + 6 * ts, bx1 = bx0 + bar_width;
    const int top = label_h + params.margin + text_h, bottom = H - params.margin - text_h;
    if (bottom - top >= 2) {
      canvas.fill(bx0 - 1, top - 1, bx1 + 1, bottom + 1, ink);  // a 1-pixel frame
      for (int y = top; y < bottom; ++y) {
        const double t = static_cast<double>(bottom - 1 - y) / (bottom - 1 - top);
        canvas.fill(bx0, y, bx1, y + 1, color_map_rgb(coloring.map, t));
      }
      const int lx = bx1 + 4 * ts;
      render_detail::draw_text(image, lx, top - text_h / 2, bar_labels[0], ts, ink, 0, W);
      render_detail::draw_text(image, lx, bottom - 1 - text_h / 2, bar_labels[1], ts, ink, 0, W);
      if (bar_labels.size() > 2) {
        const int y0 = static_cast<int>(std::lround(bottom - 1 - 0.5 * (bottom - 1 - top)));
        render_detail::draw_text(image, lx, y0 - text_h / 2, bar_labels[2], ts, ink, 0, W);
      }
    }
  }
  return std::move(image);
}

Image render_point_cloud(const RenderCloud& cloud, const RenderParams& params,
                         RenderReport* report) {
  return render_point_clouds({cloud}, params, report);
}

}  // namespace detexture
