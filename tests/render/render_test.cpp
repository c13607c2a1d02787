// Tests of pnf/render.hpp: shading follows Lambert's law on a sphere, filtering visibly calms a
// noisy plane, the camera frames the model without clipping, the colour modes, determinism
// across thread counts, and argument checking.
#include "pnf/render.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <string>
#include <vector>

#include "pnf/error.hpp"
#include "pnf/normal_filter.hpp"
#include "test_clouds.hpp"

namespace pnf {
namespace {

using test::dot;
using test::kPi;
using test::normalized;

constexpr unsigned char kWhite = 255;

// Points spread evenly over a sphere (the Fibonacci lattice): about the same spacing everywhere,
// as a scanned surface would have, with exact outward normals.
PointCloud fibonacci_sphere(int points, double radius, const Vec3& centre) {
  PointCloud c;
  const double golden = kPi * (3 - std::sqrt(5.0));
  for (int i = 0; i < points; ++i) {
    const double y = 1 - 2 * (i + 0.5) / points;
    const double r = std::sqrt(1 - y * y);
    const Vec3 d = {r * std::cos(golden * i), y, r * std::sin(golden * i)};
    c.positions.push_back({centre[0] + radius * d[0], centre[1] + radius * d[1], centre[2] + radius * d[2]});
    c.normals.push_back(d);
  }
  return c;
}

// The surface of the box [0, sx] x [0, sy] x [0, sz] + offset, a grid of spacing h on each face.
PointCloud box_surface(double sx, double sy, double sz, double h, const Vec3& offset) {
  PointCloud c;
  const double size[3] = {sx, sy, sz};
  for (int axis = 0; axis < 3; ++axis) {
    const int a = (axis + 1) % 3, b = (axis + 2) % 3;
    const int na = int(std::round(size[a] / h)), nb = int(std::round(size[b] / h));
    for (int side = 0; side < 2; ++side)
      for (int i = 0; i <= na; ++i)
        for (int j = 0; j <= nb; ++j) {
          Vec3 p{}, n{};
          p[axis] = side * size[axis];
          p[a] = i * size[a] / na;
          p[b] = j * size[b] / nb;
          n[axis] = side ? 1 : -1;
          c.positions.push_back({p[0] + offset[0], p[1] + offset[1], p[2] + offset[2]});
          c.normals.push_back(n);
        }
  }
  return c;
}

const unsigned char* pixel(const Image& image, int x, int y) {
  return &image.rgb[3 * (std::size_t(y) * image.width + x)];
}
bool is_background(const Image& image, int x, int y) {
  const unsigned char* p = pixel(image, x, y);
  return p[0] == kWhite && p[1] == kWhite && p[2] == kWhite;
}

// The smallest pixel rectangle holding every non-background pixel of columns [0, width).
struct PixelBox {
  int x0 = 1 << 30, y0 = 1 << 30, x1 = -1, y1 = -1;
  bool empty() const { return x1 < 0; }
};
PixelBox foreground(const Image& image, int width) {
  PixelBox box;
  for (int y = 0; y < image.height; ++y)
    for (int x = 0; x < width; ++x)
      if (!is_background(image, x, y)) {
        box.x0 = std::min(box.x0, x);
        box.x1 = std::max(box.x1, x);
        box.y0 = std::min(box.y0, y);
        box.y1 = std::max(box.y1, y);
      }
  return box;
}

TEST(RenderPoints, SphereBrightnessFollowsLambertsLaw) {
  constexpr int kPoints = 80000;
  const PointCloud sphere = fibonacci_sphere(kPoints, 1.0, {0, 0, 0});
  RenderOptions options;
  options.width = options.height = 400;
  options.specular = 0;  // pure diffuse plus a known ambient term
  options.ambient = 0.1;
  options.diffuse = 0.8;
  options.light = {1.0, 0.5, 0.6};  // oblique, so part of the visible half is in shadow
  const Image image = render_points(sphere, options);
  const Vec3 light = normalized(options.light);

  // Where the sphere is in the picture, measured from the picture itself: the silhouette's
  // extents (pixel edges) give its centre and radius in pixels.
  const PixelBox disk = foreground(image, image.width);
  ASSERT_FALSE(disk.empty());
  const double cx = 0.5 * (disk.x0 + disk.x1 + 1), cy = 0.5 * (disk.y0 + disk.y1 + 1);
  const double radius_px = 0.25 * (disk.x1 - disk.x0 + 1 + disk.y1 - disk.y0 + 1);
  EXPECT_NEAR(disk.x1 - disk.x0, disk.y1 - disk.y0, 2) << "the sphere should be drawn round";

  // Tolerance, in grey levels. The pixel shows the flat disk of a nearby sample: its centre is
  // at most one surfel radius (about the spacing h = sqrt(4 pi / N)) away across the view,
  // i.e. at most h / cos(theta) along the sphere, so its normal is off by at most that angle
  // (radians, unit sphere); we allow 1.5 times it for the spacing estimate's spread. Measuring
  // the centre and radius to about a pixel adds 1.5 / (radius_px cos(theta)). Brightness moves by
  // at most diffuse * 255 per radian, plus 0.5 for rounding. Pixels are taken within 0.7 of the
  // radius, where cos(theta) >= 0.71.
  constexpr double kMaxRadial = 0.7;
  const double cos_min = std::sqrt(1 - kMaxRadial * kMaxRadial);
  const double spacing = std::sqrt(4 * kPi / kPoints);
  const double angle_bound = 1.5 * spacing / cos_min + 1.5 / (radius_px * cos_min);
  const double tolerance = 255 * options.diffuse * angle_bound + 0.5;

  int checked = 0, shadowed = 0;
  double total_error = 0;
  for (int y = 0; y < image.height; y += 3) {
    for (int x = 0; x < image.width; x += 3) {
      const double u = (x + 0.5 - cx) / radius_px, v = (cy - (y + 0.5)) / radius_px;
      if (u * u + v * v > kMaxRadial * kMaxRadial) continue;
      const Vec3 n = {u, v, std::sqrt(1 - u * u - v * v)};  // the sphere's normal under the pixel
      const double lambert = std::max(0.0, dot(n, light));
      const double expected = 255 * (options.ambient + options.diffuse * lambert);
      const unsigned char* p = pixel(image, x, y);
      ASSERT_EQ(p[0], p[1]);
      ASSERT_EQ(p[0], p[2]);
      ASSERT_NEAR(p[0], expected, tolerance) << "pixel (" << x << ", " << y << "), n.l = " << dot(n, light);
      total_error += std::fabs(p[0] - expected);
      ++checked;
      if (dot(n, light) < -angle_bound) {
        EXPECT_EQ(p[0], std::lround(255 * options.ambient)) << "a shadowed pixel shows only the ambient term";
        ++shadowed;
      }
    }
  }
  EXPECT_GT(checked, 2000);
  EXPECT_GT(shadowed, 100);
  // On average far inside the bound: the bound is for the worst pixel.
  EXPECT_LT(total_error / checked, tolerance / 3);
}

// The variance of grey levels in the middle half of the drawn region.
double interior_variance(const Image& image) {
  const PixelBox box = foreground(image, image.width);
  const int w = box.x1 - box.x0, h = box.y1 - box.y0;
  double sum = 0, sum2 = 0;
  int count = 0;
  for (int y = box.y0 + h / 4; y <= box.y1 - h / 4; ++y)
    for (int x = box.x0 + w / 4; x <= box.x1 - w / 4; ++x) {
      const double g = pixel(image, x, y)[0];
      sum += g;
      sum2 += g * g;
      ++count;
    }
  const double mean = sum / count;
  return sum2 / count - mean * mean;
}

TEST(RenderPoints, FilteringANoisyPlaneLowersPixelVariance) {
  PointCloud plane = test::jittered_grid(60, 1.0, 0.3, 7);
  std::mt19937 rng(11);
  constexpr double kNoiseDegrees = 15;
  for (Vec3& n : plane.normals) n = test::jitter_normal(n, kNoiseDegrees, rng);

  RenderOptions options;
  options.width = options.height = 300;
  options.light = {1, 0.5, 1};  // oblique: brightness moves with the normal's tilt to first order
  const double before = interior_variance(render_points(plane, options));

  FilterOptions filter_options;
  filter_options.device = Device::reference();
  PointCloud filtered = plane;
  filtered.normals = NormalFilter(filter_options).run(plane).normals;
  const double after = interior_variance(render_points(filtered, options));

  // Grey levels vary in proportion to the tilt, so their variance with its square; the default
  // filter (sigma_f = 4 spacings, 4 passes) averages dozens of neighbours, which cuts the tilt
  // of 15-degree noise well over in half. A quarter of the variance is thus a safe bar.
  EXPECT_GT(before, 50) << "the noise should show";
  EXPECT_LT(after, before / 4) << "before " << before << ", after " << after;
}

// Background pixels inside a drawn sheet, two spacings in from its drawn edges (where jitter
// makes the outline ragged), as a fraction of the pixels looked at. `cells` is the sheet's side
// in spacings.
double holes_inside(const Image& image, int cells) {
  const PixelBox fg = foreground(image, image.width);
  const int inset = 2 * (fg.y1 - fg.y0) / cells + 1;
  int holes = 0, pixels = 0;
  for (int y = fg.y0 + inset; y <= fg.y1 - inset; ++y)
    for (int x = fg.x0 + inset; x <= fg.x1 - inset; ++x) {
      holes += is_background(image, x, y);
      ++pixels;
    }
  return double(holes) / pixels;
}

TEST(RenderPoints, DefaultRadiusLeavesNoHolesInAUniformlySampledSurface) {
  constexpr int kCells = 60;
  // Jittered by up to half a spacing: uniform, but as irregular as a grid gets. Face on, oblique
  // and at 20 degrees to the sheet (about 6 pixels a spacing face on).
  const PointCloud plane = test::jittered_grid(kCells, 1.0, 0.5, 9);
  PointCloud noisy = test::jittered_grid(kCells, 1.0, 0.3, 9);
  std::mt19937 rng(13);
  for (Vec3& n : noisy.normals) n = test::jitter_normal(n, 15, rng);
  for (double azimuth : {0.0, 50.0, 70.0}) {
    RenderOptions options;
    options.width = options.height = 400;
    options.azimuth_degrees = azimuth;
    EXPECT_EQ(holes_inside(render_points(plane, options), kCells), 0.0) << "azimuth " << azimuth;
    // Normals noisy by 15 degrees tilt disks away from the sheet: isolated pixels at most, under
    // one in a thousand.
    EXPECT_LT(holes_inside(render_points(noisy, options), kCells), 1e-3) << "noisy normals, azimuth " << azimuth;
  }
}

TEST(RenderPoints, FramesTheBoxWithoutClippingAtAnyView) {
  // Far from the origin, as scans are, and not a cube, so that each view projects differently.
  const PointCloud box = box_surface(2, 1, 3, 0.05, {100, 200, 300});
  const double views[][2] = {{0, 0}, {30, 20}, {-60, 45}, {90, -30}, {0, 90}, {200, -90}, {45, 35.26}};
  for (const auto& size : {std::pair{320, 200}, std::pair{200, 320}}) {
    for (const auto& view : views) {
      RenderOptions options;
      options.width = size.first;
      options.height = size.second;
      options.azimuth_degrees = view[0];
      options.elevation_degrees = view[1];
      const Image image = render_points(box, options);
      ASSERT_EQ(image.width, size.first);
      ASSERT_EQ(image.height, size.second);
      ASSERT_EQ(image.rgb.size(), 3u * size.first * size.second);
      const std::string where = "view " + std::to_string(view[0]) + "," + std::to_string(view[1]) + ", " +
                                std::to_string(size.first) + " x " + std::to_string(size.second);
      const PixelBox fg = foreground(image, image.width);
      ASSERT_FALSE(fg.empty()) << where;
      // Nothing clipped: the border stays background.
      EXPECT_GT(fg.x0, 0) << where;
      EXPECT_GT(fg.y0, 0) << where;
      EXPECT_LT(fg.x1, image.width - 1) << where;
      EXPECT_LT(fg.y1, image.height - 1) << where;
      // The projected box (for a box, its silhouette) fills the image up to the 5% margins in
      // its tighter direction: 90%, less a little for the surfel radius the frame adds.
      const double fill = std::max(double(fg.x1 - fg.x0 + 1) / image.width, double(fg.y1 - fg.y0 + 1) / image.height);
      EXPECT_GT(fill, 0.85) << where;
      EXPECT_LT(fill, 0.91) << where;
      // Centred, to a pixel or two.
      EXPECT_NEAR(fg.x0 + fg.x1 + 1, image.width, 3) << where;
      EXPECT_NEAR(fg.y0 + fg.y1 + 1, image.height, 3) << where;
    }
  }
}

TEST(RenderPoints, AGivenFrameSetsTheCamera) {
  // A sphere of radius 1 in a frame twice as wide as itself: a disk half the frame's width.
  const PointCloud sphere = fibonacci_sphere(20000, 1.0, {0, 0, 0});
  RenderOptions options;
  options.width = options.height = 200;
  options.frame = BoundingBox{{-2, -2, -2}, {2, 2, 2}};
  const PixelBox fg = foreground(render_points(sphere, options), options.width);
  // The frame's 4 units span 90% of 200 pixels, so the sphere's diameter of 2 is 90 pixels.
  EXPECT_NEAR(fg.x1 - fg.x0 + 1, 90, 2);
  EXPECT_NEAR(fg.x0 + fg.x1 + 1, 200, 2);
}

// Surfels far outside a given frame (an outlier billions of pixels away, a frame of 1e-300)
// are clipped, not drawn: they once overflowed the pixel range's int (2^31 pixels a row, or a
// write outside the picture). The picture matches the one without the far surfels.
TEST(RenderPoints, SurfelsFarOutsideTheFrameAreClipped) {
  PointCloud sphere = fibonacci_sphere(2000, 1.0, {0, 0, 0});
  sphere.radii.assign(sphere.size(), 0.05);  // given, so that the outlier cannot move an estimate
  RenderOptions options;
  options.width = 64;
  options.height = 48;
  options.frame = BoundingBox{{-2, -2, -2}, {2, 2, 2}};
  const Image plain = render_points(sphere, options);
  for (double far : {1e9, -1e9, 1e20, -1e20, 1e300}) {
    PointCloud with_outlier = sphere;
    with_outlier.positions.push_back({far, far / 2, 0.5});
    with_outlier.normals.push_back({0, 0, 1});
    with_outlier.radii.push_back(0.05);
    const Image image = render_points(with_outlier, options);
    EXPECT_EQ(image.rgb, plain.rgb) << far;
  }
  options.frame = BoundingBox{{0, 0, 0}, {1e-300, 1e-300, 1e-300}};
  const Image tiny = render_points(sphere, options);
  EXPECT_EQ(tiny.width, options.width);
  EXPECT_EQ(tiny.height, options.height);
}

TEST(RenderPoints, NormalsModeColoursByTheNormal) {
  const PointCloud sphere = fibonacci_sphere(20000, 1.0, {5, 5, 5});
  RenderOptions options;
  options.mode = RenderMode::normals;
  options.width = options.height = 200;
  const Image image = render_points(sphere, options);
  // The middle of the disk faces the viewer: n = (0, 0, 1), colour (0.5, 0.5, 1) * 255, to
  // within the tilt of the sample under it (a few degrees: a few levels).
  const unsigned char* centre = pixel(image, 100, 100);
  EXPECT_NEAR(centre[0], 128, 4);
  EXPECT_NEAR(centre[1], 128, 4);
  EXPECT_EQ(centre[2], 255);
  // Right of centre the normal turns toward +x: more red.
  EXPECT_GT(pixel(image, 160, 100)[0], 200);
}

TEST(RenderPoints, ErrorModeColoursByAngleWithABar) {
  const PointCloud sphere = fibonacci_sphere(20000, 1.0, {0, 0, 0});
  RenderOptions options;
  options.mode = RenderMode::error;
  options.width = 300;
  options.height = 200;
  const int drawing = options.width - options.colour_bar_width;

  // Identical normals: every drawn pixel has the bottom colour of viridis.
  Image image = render_points(sphere, sphere.normals, options);
  ASSERT_EQ(image.width, 300);
  const PixelBox fg = foreground(image, drawing);
  ASSERT_FALSE(fg.empty());
  const int mx = (fg.x0 + fg.x1) / 2, my = (fg.y0 + fg.y1) / 2;
  EXPECT_EQ(pixel(image, mx, my)[0], 68);
  EXPECT_EQ(pixel(image, mx, my)[1], 1);
  EXPECT_EQ(pixel(image, mx, my)[2], 84);
  EXPECT_LT(fg.x1, drawing - 1) << "the points stay left of the colour bar";
  EXPECT_FALSE(foreground(image, image.width).x1 < drawing) << "the colour bar is drawn";

  // Flipped normals are 180 degrees off, past any scale: the top colour.
  std::vector<Vec3> flipped = sphere.normals;
  for (Vec3& n : flipped) n = {-n[0], -n[1], -n[2]};
  image = render_points(sphere, flipped, options);
  EXPECT_EQ(pixel(image, mx, my)[0], 253);
  EXPECT_EQ(pixel(image, mx, my)[1], 231);
  EXPECT_EQ(pixel(image, mx, my)[2], 37);
}

TEST(RenderPoints, SameImageForAnyThreadCount) {
  PointCloud plane = test::jittered_grid(80, 1.0, 0.4, 3);
  std::mt19937 rng(5);
  for (Vec3& n : plane.normals) n = test::jitter_normal(n, 20, rng);
  RenderOptions options;
  options.azimuth_degrees = 20;
  options.elevation_degrees = 40;
  options.radius_scale = 1.5;  // many overlapping disks: ties and races would show
  options.threads = 1;
  const Image one = render_points(plane, options);
  for (int threads : {2, 3, 8}) {
    options.threads = threads;
    EXPECT_EQ(render_points(plane, options).rgb, one.rgb) << threads << " threads";
  }
}

TEST(RenderPoints, EmptyCloudGivesTheBackground) {
  const Image image = render_points(PointCloud{}, RenderOptions{});
  EXPECT_EQ(image.width, 640);
  EXPECT_EQ(image.height, 480);
  EXPECT_TRUE(std::all_of(image.rgb.begin(), image.rgb.end(), [](unsigned char c) { return c == kWhite; }));
}

// Expects `call` to throw pnf::Error with `code` and a message containing `words`.
template <typename Call>
void expect_error(Call call, ErrorCode code, const std::string& words) {
  try {
    call();
    ADD_FAILURE() << "no error; expected one mentioning '" << words << "'";
  } catch (const Error& e) {
    EXPECT_EQ(e.code(), code) << e.what();
    EXPECT_NE(std::string(e.what()).find(words), std::string::npos) << e.what();
  }
}

TEST(RenderPoints, BadArgumentsAreNamed) {
  const PointCloud sphere = fibonacci_sphere(500, 1.0, {0, 0, 0});
  auto with = [&](auto change) {
    RenderOptions o;
    change(o);
    return [o, &sphere] { render_points(sphere, o); };
  };
  const ErrorCode arg = ErrorCode::invalid_argument;
  expect_error(with([](RenderOptions& o) { o.width = 0; }), arg, "width");
  expect_error(with([](RenderOptions& o) { o.width = 100000; }), arg, "width");
  expect_error(with([](RenderOptions& o) { o.height = -3; }), arg, "height");
  expect_error(with([](RenderOptions& o) { o.elevation_degrees = 91; }), arg, "elevation");
  expect_error(with([](RenderOptions& o) { o.azimuth_degrees = NAN; }), arg, "azimuth");
  expect_error(with([](RenderOptions& o) { o.light = {0, 0, 0}; }), arg, "light");
  expect_error(with([](RenderOptions& o) { o.radius_scale = 0; }), arg, "radius scale");
  expect_error(with([](RenderOptions& o) { o.error_max_degrees = 0; }), arg, "error max");
  expect_error(with([](RenderOptions& o) { o.threads = -1; }), arg, "threads");
  expect_error(with([](RenderOptions& o) { o.frame = BoundingBox{{1, 0, 0}, {0, 1, 1}}; }), arg, "frame");
  expect_error(with([](RenderOptions& o) { o.mode = RenderMode::error; }), arg, "reference normals");
  expect_error(with([](RenderOptions& o) {
                 o.mode = RenderMode::error;
                 o.width = 90;
               }),
               arg, "colour bar");

  RenderOptions error_mode;
  error_mode.mode = RenderMode::error;
  std::vector<Vec3> short_reference(sphere.normals.begin(), sphere.normals.end() - 1);
  expect_error([&] { render_points(sphere, short_reference, error_mode); }, ErrorCode::invalid_input, "499");
  std::vector<Vec3> zero_reference = sphere.normals;
  zero_reference[17] = {0, 0, 0};
  expect_error([&] { render_points(sphere, zero_reference, error_mode); }, ErrorCode::invalid_input, "17");

  PointCloud no_normals = sphere;
  no_normals.normals.clear();
  expect_error([&] { render_points(no_normals); }, ErrorCode::invalid_input, "no normals");
}

}  // namespace
}  // namespace pnf
