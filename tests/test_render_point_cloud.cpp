// Pictures: what is drawn where, in which colour, checked against what the
// projection and the shading formula give by hand.
#include "detexture/render/render_point_cloud.h"

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <random>
#include <set>
#include <stdexcept>
#include <string>

#include "detexture/io/point_cloud.h"
#include "detexture/render/face_triangles.h"
#include "detexture/render/write_png.h"
#include "png_support.h"

namespace detexture {
namespace {

using Rgb = std::array<std::uint8_t, 3>;
const Rgb kWhite = {255, 255, 255};

// The unit square [0,1]² at height z, on a side x side grid, normals +z.
RenderCloud square(int side, double z = 0.0, double x0 = 0.0) {
  RenderCloud c;
  c.positions.resize(side * side, 3);
  c.normals.resize(side * side, 3);
  for (int a = 0; a < side; ++a)
    for (int b = 0; b < side; ++b) {
      c.positions.row(a * side + b) << x0 + a / (side - 1.0), b / (side - 1.0), z;
      c.normals.row(a * side + b) << 0, 0, 1;
    }
  return c;
}

// n points spread evenly over the unit sphere (Fibonacci lattice), normals
// radial.
RenderCloud sphere(int n) {
  RenderCloud c;
  c.positions.resize(n, 3);
  const double golden = M_PI * (3.0 - std::sqrt(5.0));
  for (int i = 0; i < n; ++i) {
    const double z = 1.0 - 2.0 * (i + 0.5) / n, r = std::sqrt(1.0 - z * z);
    c.positions.row(i) << r * std::cos(golden * i), r * std::sin(golden * i), z;
  }
  c.normals = c.positions;
  return c;
}

// 200 x 200, 10 px margins, no text, a headlight, 4 px points, looking down.
RenderParams plain_params() {
  RenderParams p;
  p.width = p.height = 200;
  p.margin = 10;
  p.labels = false;
  p.color_bar = false;
  p.light_left_deg = p.light_up_deg = 0.0;
  p.point_size = 4.0;
  p.view = parse_view("top");
  return p;
}

// First and last column of row y that is not background, or (-1, -1).
std::pair<int, int> row_extent(const Image& image, int y, const Rgb& background = kWhite) {
  int first = -1, last = -1;
  for (int x = 0; x < image.width; ++x)
    if (image.pixel(x, y) != background) {
      if (first < 0) first = x;
      last = x;
    }
  return {first, last};
}

int brightness(const Image& image, int x, int y) { return image.pixel(x, y)[0]; }

TEST(RenderPointCloud, PlaneFacingTheCameraIsAFilledSquare) {
  const RenderParams p = plain_params();
  RenderReport report;
  const Image image = render_point_cloud(square(101), p, &report);
  ASSERT_EQ(image.width, 200);
  ASSERT_EQ(image.height, 200);
  ASSERT_EQ(image.rgb.size(), 200u * 200u * 3u);
  // 180 px for one unit; point centres span pixels 10..190, and a 4 px disc
  // covers the pixels whose centres are within 2 px: columns 8..191 (pixel
  // 8's centre is 1.5 px from 10). In the outermost rows, 1.5 px from the
  // edge's points, a disc reaches only sqrt(2² - 1.5²) = 1.3 px sideways:
  // columns 9..190 there.
  EXPECT_DOUBLE_EQ(report.pixels_per_unit, 180.0);
  for (int y : {9, 50, 100, 150, 190}) {
    EXPECT_EQ(row_extent(image, y), std::make_pair(8, 191)) << "row " << y;
  }
  EXPECT_EQ(row_extent(image, 8), std::make_pair(9, 190));
  EXPECT_EQ(row_extent(image, 191), std::make_pair(9, 190));
  EXPECT_EQ(row_extent(image, 7).first, -1) << "rows above the square are background";
  EXPECT_EQ(row_extent(image, 192).first, -1);
  // Facing a headlight: ambient + (1 - ambient) · 1 = the full surface colour.
  for (int y = 9; y <= 190; ++y)
    for (int x = 8; x <= 191; ++x) ASSERT_EQ(image.pixel(x, y), p.surface_color) << x << "," << y;
}

TEST(RenderPointCloud, TiltedPlaneIsDimmedByLambert) {
  RenderParams p = plain_params();
  p.view = {0.0, 30.0};  // 60° from the plane's normal, light along the view
  const Image image = render_point_cloud(square(101), p);
  // 0.25 + 0.75 cos 60° = 0.625 of (200, 200, 205).
  EXPECT_EQ(image.pixel(100, 100), (Rgb{125, 125, 128}));
  // Seen at 30° elevation the square is 1 wide and sin 30° = 0.5 high: the
  // fit is limited by the width (180 px), so it is 90 px high.
  const int x = 100;
  int top = -1, bottom = -1;
  for (int y = 0; y < 200; ++y)
    if (image.pixel(x, y) != kWhite) {
      if (top < 0) top = y;
      bottom = y;
    }
  EXPECT_NEAR(bottom - top + 1, 90 + 4, 1);
}

TEST(RenderPointCloud, SphereIsBrighterAtItsCentreThanNearItsRim) {
  RenderParams p = plain_params();
  p.view = parse_view("front");
  p.point_size = 0.0;  // automatic
  RenderReport report;
  const Image image = render_point_cloud(sphere(40000), p, &report);
  // Radius 90 px around (100, 100). Lambert with a headlight: the centre
  // faces the light (full 200), at 0.9 of the radius n·l = sqrt(1 - 0.81).
  EXPECT_NEAR(brightness(image, 100, 100), 200, 3);
  const double rim = 0.25 + 0.75 * std::sqrt(1 - 0.81);
  for (auto [dx, dy] : {std::pair{81, 0}, {-81, 0}, {0, 81}, {0, -81}})
    EXPECT_NEAR(brightness(image, 100 + dx, 100 + dy), 200 * rim, 12) << dx << "," << dy;
  EXPECT_EQ(image.pixel(100 + 95, 100), kWhite) << "outside the disc";
  EXPECT_EQ(image.pixel(3, 3), kWhite);
  ASSERT_EQ(report.point_size.size(), 1u);
  EXPECT_GE(report.point_size[0], 1.0);
  EXPECT_LE(report.point_size[0], 6.0);
  // No holes: every pixel well inside the disc is drawn.
  for (int y = 20; y < 180; ++y)
    for (int x = 20; x < 180; ++x)
      if (std::hypot(x + 0.5 - 100, y + 0.5 - 100) < 85)
        ASSERT_NE(image.pixel(x, y), kWhite) << x << "," << y;
}

TEST(RenderPointCloud, LightFromUpperLeftBrightensTheUpperLeft) {
  RenderParams p = plain_params();
  p.view = parse_view("front");
  p.light_left_deg = 30;
  p.light_up_deg = 30;
  const Image image = render_point_cloud(sphere(40000), p);
  int best = -1, bx = 0, by = 0;
  for (int y = 0; y < 200; ++y)
    for (int x = 0; x < 200; ++x)
      if (image.pixel(x, y) != kWhite && brightness(image, x, y) > best) {
        best = brightness(image, x, y);
        bx = x;
        by = y;
      }
  EXPECT_LT(bx, 100 - 20);
  EXPECT_LT(by, 100 - 20);
  EXPECT_GE(best, 198);
}

TEST(RenderPointCloud, NearerSurfaceHidesFartherOneWhateverTheOrder) {
  RenderParams p = plain_params();
  // A small square above the big one, drawn first, its normals tilted by
  // 60° so that it is darker (125) than the big one (200).
  RenderCloud small = square(21, 0.5);
  small.positions.leftCols(2) = (small.positions.leftCols(2).array() * 0.2 + 0.4).matrix();
  for (Eigen::Index i = 0; i < small.normals.rows(); ++i)
    small.normals.row(i) << std::sin(M_PI / 3), 0, std::cos(M_PI / 3);
  const RenderCloud big = square(101);
  RenderCloud both;
  both.positions.resize(small.positions.rows() + big.positions.rows(), 3);
  both.positions << small.positions, big.positions;
  both.normals.resize(both.positions.rows(), 3);
  both.normals << small.normals, big.normals;
  const Image image = render_point_cloud(both, p);
  EXPECT_EQ(image.pixel(100, 100), (Rgb{125, 125, 128})) << "the nearer small square";
  EXPECT_EQ(image.pixel(30, 30), p.surface_color) << "the big square around it";
}

TEST(RenderPointCloud, TwoPanelsShareTheScaleAndTheSecondIsOnTheRight) {
  RenderParams p = plain_params();
  p.width = 400;
  // The second square is one unit to the right of the first: the common
  // extent is 2 x 1 units, 90 px per unit in 180 x 180 px panels.
  RenderReport report;
  const Image image = render_point_clouds({square(51), square(51, 0.0, 1.0)}, p, &report);
  EXPECT_DOUBLE_EQ(report.pixels_per_unit, 90.0);
  // Panel 1 (x < 200): its square spans x from 10 to 100 (+/- 2 px discs).
  EXPECT_EQ(row_extent(image, 100).first, 8);
  for (int x = 103; x < 298; ++x) EXPECT_EQ(image.pixel(x, 100), kWhite) << x;
  // Panel 2: the same place in the panel is empty, its square is at 300..390.
  EXPECT_EQ(row_extent(image, 100).second, 200 + 191);
  EXPECT_EQ(image.pixel(300, 100), p.surface_color);
  EXPECT_EQ(image.pixel(50, 100), p.surface_color);
  EXPECT_EQ(image.pixel(250, 100), kWhite);
}

TEST(RenderPointCloud, IdenticalCloudsGiveIdenticalPanels) {
  RenderParams p = plain_params();
  p.width = 400;
  p.view = parse_view("iso");
  const Image image = render_point_clouds({sphere(5000), sphere(5000)}, p);
  for (int y = 0; y < 200; ++y)
    for (int x = 0; x < 200; ++x) ASSERT_EQ(image.pixel(x, y), image.pixel(x + 200, y));
}

TEST(RenderPointCloud, ColorByMapsTheRangeToTheMapsEnds) {
  RenderParams p = plain_params();
  RenderCloud c = square(101);
  for (Eigen::Index i = 0; i < c.positions.rows(); ++i)
    c.scalar.push_back(c.positions(i, 0) < 0.5 ? 3.0 : 7.0);
  RenderReport report;
  Image image = render_point_cloud(c, p, &report);
  EXPECT_EQ(report.color_map, ColorMap::Viridis);
  EXPECT_EQ(report.range_min, 3.0);
  EXPECT_EQ(report.range_max, 7.0);
  EXPECT_EQ(image.pixel(30, 100), (Rgb{68, 1, 84})) << "viridis' dark blue end";
  EXPECT_EQ(image.pixel(170, 100), (Rgb{253, 231, 37})) << "viridis' yellow end";

  // Signed values: the diverging map on a range symmetric about 0.
  for (double& s : c.scalar) s = s == 3.0 ? -2.0 : 1.0;
  image = render_point_cloud(c, p, &report);
  EXPECT_EQ(report.color_map, ColorMap::Diverging);
  EXPECT_EQ(report.range_min, -2.0);
  EXPECT_EQ(report.range_max, 2.0);
  EXPECT_EQ(image.pixel(30, 100), color_map_rgb(ColorMap::Diverging, 0.0));
  EXPECT_EQ(image.pixel(30, 100), (Rgb{33, 102, 172})) << "blue end";
  EXPECT_EQ(image.pixel(170, 100), color_map_rgb(ColorMap::Diverging, 0.75));

  // A given range clamps: 1 is beyond [-1, 0.5], so it gets the red end.
  p.range_min = -1.0;
  p.range_max = 0.5;
  image = render_point_cloud(c, p, &report);
  EXPECT_EQ(image.pixel(170, 100), (Rgb{178, 24, 43})) << "red end";
  EXPECT_EQ(image.pixel(30, 100), (Rgb{33, 102, 172}));
}

TEST(RenderPointCloud, ColorBarRunsFromMinAtTheBottomToMaxAtTheTop) {
  RenderParams p = plain_params();
  p.width = 300;
  p.color_bar = true;
  p.range_min = 0.0;
  p.range_max = 10.0;
  RenderCloud c = square(51);
  c.scalar.assign(c.positions.rows(), 5.0);  // the cloud is mid-map; only the bar has the ends
  const Image image = render_point_cloud(c, p);
  const Rgb low = color_map_rgb(ColorMap::Viridis, 0.0),
            high = color_map_rgb(ColorMap::Viridis, 1.0);
  int low_y = -1, high_y = -1, bar_x = -1;
  for (int y = 0; y < image.height; ++y)
    for (int x = 0; x < image.width; ++x) {
      if (image.pixel(x, y) == low) low_y = y;
      if (image.pixel(x, y) == high && high_y < 0) {
        high_y = y;
        bar_x = x;
      }
    }
  ASSERT_GE(low_y, 0);
  ASSERT_GE(high_y, 0);
  EXPECT_LT(high_y, low_y);
  EXPECT_GT(low_y - high_y, 100) << "the bar spans most of the height";
  EXPECT_GT(bar_x, 200) << "right of the panel";
  // Labels: dark dots to the right of the bar (10 px) and its frame (1 px).
  int ink = 0;
  for (int y = 0; y < image.height; ++y)
    for (int x = bar_x + 12; x < image.width; ++x) ink += image.pixel(x, y) == Rgb{40, 40, 40};
  EXPECT_GT(ink, 20);
}

TEST(RenderPointCloud, FarFromTheOriginTheZBufferStillSortsSurfaces) {
  // The small-above-big scene of the z-buffer test, moved 1e6 away: float
  // depths measured from the origin would differ by less than a float's step.
  RenderParams p = plain_params();
  RenderCloud c = square(101);
  const Eigen::Index n = c.positions.rows();
  c.positions.conservativeResize(n + 1, 3);
  c.normals.conservativeResize(n + 1, 3);
  c.positions.row(n) << 0.5, 0.5, 0.01;  // a point 0.01 above the plane's centre
  c.normals.row(n) << std::sin(M_PI / 3), 0, std::cos(M_PI / 3);
  c.positions.col(2).array() += 1e6;
  p.point_size = 8;
  const Image image = render_point_cloud(c, p);
  EXPECT_EQ(image.pixel(100, 100), (Rgb{125, 125, 128}));
}

TEST(RenderPointCloud, MissingNormalsAreEstimatedAndShadeAlike) {
  const RenderParams p = plain_params();
  RenderCloud without = square(61);
  without.normals.resize(0, 3);
  RenderReport report;
  const Image a = render_point_cloud(without, p, &report);
  const Image b = render_point_cloud(square(61), p);
  ASSERT_EQ(report.estimated_normals.size(), 1u);
  EXPECT_EQ(report.estimated_normals[0], 61u * 61u);
  EXPECT_EQ(a.rgb, b.rgb) << "PCA normals of a plane are ±z, and shading is two-sided";
}

TEST(RenderPointCloud, FlippedNormalsShadeTheSame) {
  const RenderParams p = plain_params();
  RenderCloud flipped = sphere(3000);
  flipped.normals = -flipped.normals;
  EXPECT_EQ(render_point_cloud(flipped, p).rgb, render_point_cloud(sphere(3000), p).rgb);
}

TEST(RenderPointCloud, TrianglesFillTheirPixels) {
  const RenderParams p = plain_params();
  RenderCloud mesh;
  mesh.positions.resize(4, 3);
  mesh.positions << 0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0;
  mesh.triangles.resize(2, 3);
  mesh.triangles << 0, 1, 2, 0, 2, 3;  // no normals: taken from the faces
  const Image image = render_point_cloud(mesh, p);
  // Pixel centres 10.5 .. 189.5 lie inside [10, 190].
  for (int y : {10, 100, 189}) EXPECT_EQ(row_extent(image, y), std::make_pair(10, 189)) << y;
  EXPECT_EQ(row_extent(image, 9).first, -1);
  EXPECT_EQ(row_extent(image, 190).first, -1);
  for (int y = 10; y < 190; ++y)
    for (int x = 10; x < 190; ++x) ASSERT_EQ(image.pixel(x, y), p.surface_color) << x << "," << y;
}

TEST(RenderPointCloud, TriangleNormalsAndScalarsAreInterpolated) {
  RenderParams p = plain_params();
  RenderCloud mesh;
  mesh.positions.resize(4, 3);
  mesh.positions << 0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0;
  mesh.triangles.resize(2, 3);
  mesh.triangles << 0, 1, 2, 0, 2, 3;
  // Normals facing the light on the left edge, tilted 60° on the right.
  mesh.normals.resize(4, 3);
  const double s = std::sin(M_PI / 3), c = std::cos(M_PI / 3);
  mesh.normals << 0, 0, 1, s, 0, c, s, 0, c, 0, 0, 1;
  const Image shaded = render_point_cloud(mesh, p);
  EXPECT_EQ(brightness(shaded, 10, 100), 200);
  EXPECT_NEAR(brightness(shaded, 189, 100), 125, 2);
  const int middle = brightness(shaded, 100, 100);
  EXPECT_GT(middle, 130);
  EXPECT_LT(middle, 199);
  // A scalar from 0 on the left to 1 on the right: the map's middle halfway.
  mesh.normals.resize(0, 3);
  mesh.scalar = {0, 1, 1, 0};
  const Image coloured = render_point_cloud(mesh, p);
  EXPECT_EQ(coloured.pixel(10, 100), color_map_rgb(ColorMap::Viridis, 0.5 / 180));
  const Rgb mid = coloured.pixel(99, 100), want = color_map_rgb(ColorMap::Viridis, 89.5 / 180);
  for (int k = 0; k < 3; ++k) EXPECT_NEAR(mid[k], want[k], 1);
}

TEST(RenderPointCloud, BadInputsAreRefusedWithASentence) {
  const RenderParams p = plain_params();
  EXPECT_THROW(render_point_clouds({}, p), std::invalid_argument);
  RenderCloud c = square(5);
  c.scalar = {1, 2};
  EXPECT_THROW(render_point_cloud(c, p), std::invalid_argument);
  c = square(5);
  c.triangles.resize(1, 3);
  c.triangles << 0, 1, 25;
  EXPECT_THROW(render_point_cloud(c, p), std::invalid_argument);
  RenderParams q = p;
  q.width = 10;
  EXPECT_THROW(render_point_cloud(square(5), q), std::invalid_argument);
  q = p;
  q.range_min = 2;
  q.range_max = 1;
  EXPECT_THROW(render_point_cloud(square(5), q), std::invalid_argument);
  q = p;
  q.range_min = 5;  // only the min, above every value
  c = square(5);
  c.scalar.assign(25, 1.0);
  EXPECT_THROW(render_point_cloud(c, q), std::invalid_argument);
  q = p;
  q.width = 40;  // 8 panels of 5 px cannot hold 10 px margins
  try {
    render_point_clouds(std::vector<RenderCloud>(8, square(5)), q);
    FAIL() << "no room";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("8 panels"), std::string::npos) << e.what();
  }
}

TEST(RenderPointCloud, LabelsHaveAGlyphForEveryPrintableCharacter) {
  RenderParams p = plain_params();
  p.labels = true;
  RenderCloud c = square(11);
  auto label_strip = [&](const std::string& text) {
    c.label = text;
    const Image image = render_point_cloud(c, p);
    // The label line: 7 dots and 3 dots of padding above and below it.
    return std::vector<std::uint8_t>(image.rgb.begin(), image.rgb.begin() + 3 * 200 * 13);
  };
  const auto unknown = label_strip("?"), blank = label_strip(" ");
  EXPECT_NE(unknown, blank);
  EXPECT_EQ(label_strip("\x01"), unknown) << "no glyph: drawn as '?'";
  std::set<std::vector<std::uint8_t>> seen = {unknown, blank};
  for (char ch = '!'; ch <= '~'; ++ch) {
    if (ch == '?') continue;
    EXPECT_TRUE(seen.insert(label_strip(std::string(1, ch))).second) << "'" << ch << "'";
  }
  // Labels are UTF-8: the degree, times and micro signs have glyphs of
  // their own, the minus sign is the hyphen's, and any other character, or
  // a malformed byte, is one '?' (not one per byte).
  seen.insert(label_strip("??"));  // what a two-byte character was drawn as
  for (const char* own : {"\u00b0", "\u00d7", "\u00b5"})
    EXPECT_TRUE(seen.insert(label_strip(own)).second) << own;
  EXPECT_EQ(label_strip("\u2212"), label_strip("-"));
  for (const char* other : {"\u00e9", "\u4e2d", "\U0001F600", "\xff", "\xc3", "\xe2\x88"})
    EXPECT_EQ(label_strip(other), unknown) << other;
  EXPECT_EQ(label_strip("\xc0\xaf"), unknown) << "an overlong form";
  EXPECT_EQ(label_strip("\x88\x88"), label_strip("??")) << "two stray continuation bytes";
  EXPECT_EQ(label_strip("a\u00e9b"), label_strip("a?b"));
}

TEST(RenderPointCloud, ViewsByNameAndByAngles) {
  EXPECT_EQ(parse_view("front").azimuth_deg, 0);
  EXPECT_EQ(parse_view("Top").elevation_deg, 90);
  EXPECT_EQ(parse_view("right").azimuth_deg, 90);
  EXPECT_NEAR(parse_view("iso").elevation_deg, 35.264, 1e-3);
  const ViewAngles v = parse_view("30,-20.5");
  EXPECT_EQ(v.azimuth_deg, 30);
  EXPECT_EQ(v.elevation_deg, -20.5);
  for (const char* bad : {"sideways", "30", "30,", ",20", "30,95", "a,b", "30,20,10"})
    EXPECT_THROW(parse_view(bad), std::invalid_argument) << bad;
}

TEST(RenderPointCloud, UpAxisTurnsTheScene) {
  // A tall thin box along the up axis appears tall in the front view.
  RenderParams p = plain_params();
  p.view = parse_view("front");
  for (UpAxis up : {UpAxis::X, UpAxis::Y, UpAxis::Z}) {
    p.up = up;
    RenderCloud c;
    c.positions.resize(200, 3);
    c.positions.setZero();
    const int axis = up == UpAxis::X ? 0 : up == UpAxis::Y ? 1 : 2;
    for (int i = 0; i < 200; ++i) c.positions(i, axis) = i / 199.0;
    c.normals = Normals::Constant(200, 3, 1.0);
    const Image image = render_point_cloud(c, p);
    EXPECT_NE(image.pixel(100, 15), kWhite) << up_axis_name(up);
    EXPECT_NE(image.pixel(100, 185), kWhite) << up_axis_name(up);
    EXPECT_EQ(image.pixel(60, 100), kWhite) << up_axis_name(up);
  }
}

TEST(FaceTriangles, PolygonsBecomeFansAndBadIndicesAreRefused) {
  PointCloud cloud;
  cloud.positions.resize(5, 3);
  cloud.positions.setZero();
  OtherElement faces;
  faces.name = "face";
  faces.properties = {{"flags", ScalarType::UInt8, false, ScalarType::UInt8},
                      {"vertex_indices", ScalarType::Int32, true, ScalarType::UInt8}};
  // flags, count, corners...: a quad, a degenerate 2-gon, a triangle.
  faces.values = {7, 4, 0, 1, 2, 3, 7, 2, 0, 1, 7, 3, 1, 2, 4};
  faces.row_offsets = {0, 6, 10, 15};
  cloud.other_elements.push_back(faces);
  std::size_t skipped = 99;
  const Triangles t = face_triangles(cloud, &skipped);
  ASSERT_EQ(t.rows(), 3);
  EXPECT_EQ(t.row(0), (Eigen::Matrix<std::uint32_t, 1, 3>(0, 1, 2)));
  EXPECT_EQ(t.row(1), (Eigen::Matrix<std::uint32_t, 1, 3>(0, 2, 3)));
  EXPECT_EQ(t.row(2), (Eigen::Matrix<std::uint32_t, 1, 3>(1, 2, 4)));
  EXPECT_EQ(skipped, 1u);

  cloud.other_elements[0].values.back() = 5;  // vertex 5 of 5
  EXPECT_THROW(face_triangles(cloud), std::invalid_argument);
  cloud.other_elements.clear();
  EXPECT_EQ(face_triangles(cloud).rows(), 0);
}

class PngFile : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = std::filesystem::temp_directory_path() /
           ("detexture_png_" +
            std::string(::testing::UnitTest::GetInstance()->current_test_info()->name()));
    std::filesystem::remove_all(dir_);
    std::filesystem::create_directories(dir_);
  }
  void TearDown() override { std::filesystem::remove_all(dir_); }
  std::filesystem::path dir_;
};

TEST_F(PngFile, WrittenThenReadBackHasTheExactPixels) {
  Image image;
  image.width = 37;
  image.height = 23;
  std::mt19937 rng(5);
  for (int i = 0; i < 37 * 23 * 3; ++i) image.rgb.push_back(static_cast<std::uint8_t>(rng()));
  const std::string path = (dir_ / "random.png").string();
  write_png(path, image);
  const Image back = test::read_png(path);
  EXPECT_EQ(back.width, 37);
  EXPECT_EQ(back.height, 23);
  EXPECT_EQ(back.rgb, image.rgb);

  const Image picture = render_point_cloud(sphere(2000), plain_params());
  write_png(path, picture);  // over the first one
  EXPECT_EQ(test::read_png(path).rgb, picture.rgb);
  int entries = 0;
  for (const auto& e : std::filesystem::directory_iterator(dir_)) entries += !e.path().empty();
  EXPECT_EQ(entries, 1) << "no temporary file left behind";
}

TEST_F(PngFile, UnwritablePlacesAreNamedInTheError) {
  Image image;
  image.width = image.height = 2;
  image.rgb.assign(12, 0);
  const std::string missing = (dir_ / "no_such_folder" / "a.png").string();
  try {
    write_png(missing, image);
    FAIL() << "wrote into a missing folder";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find(missing), std::string::npos) << e.what();
  }
  EXPECT_THROW(write_png(dir_.string(), image), std::runtime_error) << "a folder";
  image.rgb.pop_back();
  EXPECT_THROW(write_png((dir_ / "b.png").string(), image), std::invalid_argument);
}

}  // namespace
}  // namespace detexture
