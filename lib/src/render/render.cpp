// The surfel renderer behind pnf::render_points.
//
// Why plain C++ and not OpenCL like the filter: splatting with a depth test means many surfels
// race for the same pixel, and the usual GPU answer is an atomic min on the depth (or a packed
// depth-and-id word). OpenCL 1.2, our target, has atomics only for 32-bit integers in global
// memory: no float atomics and no 64-bit atomic min, so a float depth with a surfel id cannot be
// updated in one step. Workarounds (compare-and-swap loops, several passes) cost more code than
// this whole file and break determinism. A picture of 10^5 to 10^6 surfels renders in a fraction
// of a second on the CPU, so the CPU it is: OpenMP over bands of image rows, each band drawing
// its surfels in index order, so that the image is the same for any thread count.
//
// Method: an orthographic camera; each surfel is the disk of radius R about its point,
// perpendicular to its normal. For each pixel centre inside the disk's projected ellipse, the
// ray along the view direction meets the disk's plane at a depth; the nearest disk wins (ties:
// the lower index). Each disk has one colour (flat, per-surfel shading), so the picture shows
// each normal as it is rather than an interpolation of several.
#include <omp.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <string>

#include "cloud_checks.hpp"
#include "colour_bar.hpp"
#include "geometry.hpp"
#include "pnf/error.hpp"
#include "pnf/mean_radius.hpp"
#include "pnf/render.hpp"

namespace pnf {
namespace {

using geometry::angle_degrees;
using geometry::cross;
using geometry::dot;
using geometry::kPi;

double length(const Vec3& v) { return geometry::norm(v); }
// Empty space around the framed box, as a fraction of the drawing area's size on each side: room
// for disks that reach past the box and for the eye.
constexpr double kFrameMargin = 0.05;
// Smallest surfel radius in pixels: a pixel centre is at most sqrt(2)/2 = 0.707 pixel from any
// point of its pixel, so a facing disk of 0.75 pixel always covers its own pixel's centre and a
// dense cloud drawn small has no holes.
constexpr double kMinPixelRadius = 0.75;
// A disk whose normal is this close to perpendicular to the view is a line seen edge on: it
// covers no pixel centre, and its depth equation would divide by ~0.
constexpr double kEdgeOn = 1e-6;
// Rows per band of the parallel rasteriser: small enough to share work among threads, large
// enough that few surfels straddle bands.
constexpr int kBandRows = 8;
// When the spacing cannot be estimated (fewer than 5 points, or all at one place), surfels get
// this fraction of the bounding box diagonal.
constexpr double kFallbackRadiusFraction = 0.01;
constexpr unsigned char kBackground = 255;  // white

Vec3 normalized(const Vec3& v) {
  const double l = length(v);
  return {v[0] / l, v[1] / l, v[2] / l};
}

// World to pixels: x = cx + (p.right - u_mid) * scale, y = cy - (p.up - v_mid) * scale (rows go
// down), depth = p.toward * scale (larger is nearer).
struct Camera {
  Vec3 right, up, toward;
  double u_mid = 0, v_mid = 0, scale = 1, cx = 0, cy = 0;
};

Camera make_camera(const BoundingBox& box, const RenderOptions& options, int drawing_width) {
  Camera cam;
  const double azimuth = options.azimuth_degrees * kPi / 180;
  const double elevation = options.elevation_degrees * kPi / 180;
  cam.toward = {std::sin(azimuth) * std::cos(elevation), std::sin(elevation), std::cos(azimuth) * std::cos(elevation)};
  // Built from the azimuth alone, so it stays defined looking straight up or down.
  cam.right = {std::cos(azimuth), 0, -std::sin(azimuth)};
  cam.up = cross(cam.toward, cam.right);
  double u_lo = 0, u_hi = 0, v_lo = 0, v_hi = 0;
  for (int corner = 0; corner < 8; ++corner) {
    const Vec3 p = {(corner & 1) ? box.max[0] : box.min[0], (corner & 2) ? box.max[1] : box.min[1],
                    (corner & 4) ? box.max[2] : box.min[2]};
    const double u = dot(p, cam.right), v = dot(p, cam.up);
    if (corner == 0 || u < u_lo) u_lo = u;
    if (corner == 0 || u > u_hi) u_hi = u;
    if (corner == 0 || v < v_lo) v_lo = v;
    if (corner == 0 || v > v_hi) v_hi = v;
  }
  double du = u_hi - u_lo, dv = v_hi - v_lo;
  // A box that projects to a point (one point, or all points on the view axis): a unit square.
  if (!(du > 0) && !(dv > 0)) du = dv = 1;
  const double room_x = drawing_width * (1 - 2 * kFrameMargin), room_y = options.height * (1 - 2 * kFrameMargin);
  cam.scale = std::min(du > 0 ? room_x / du : HUGE_VAL, dv > 0 ? room_y / dv : HUGE_VAL);
  cam.u_mid = 0.5 * (u_lo + u_hi);
  cam.v_mid = 0.5 * (v_lo + v_hi);
  cam.cx = 0.5 * drawing_width;
  cam.cy = 0.5 * options.height;
  return cam;
}

// A surfel in pixel units, ready to draw; x0 > x1 when it covers no pixel.
struct Splat {
  double x = 0, y = 0, depth = 0, radius = 0;
  Vec3 normal{0, 0, 1};  // camera coordinates, unit
  int x0 = 0, x1 = -1, y0 = 0, y1 = -1;
};

// The pixels [first, last] whose centres (index + 0.5) lie in [lo + 0.5, hi + 0.5], clipped to
// 0 .. count - 1 in double before the conversion to int: a surfel far outside a given frame
// (an outlier, a zoom) lies billions of pixels away, where the conversion would overflow (it
// ran 2^31 pixels a row, or wrote outside the picture). first > last when none is in the picture.
void pixel_span(double lo, double hi, int count, int& first, int& last) {
  first = int(std::clamp(std::ceil(lo), 0.0, double(count)));
  last = int(std::clamp(std::floor(hi), -1.0, count - 1.0));
}

void check_reference(const CloudView& cloud, const Vec3ArrayView& reference) {
  if (reference.count != cloud.size()) {
    throw Error(ErrorCode::invalid_input, "the reference normals number " + std::to_string(reference.count) +
                                              " but the cloud has " + std::to_string(cloud.size()) + " points");
  }
  for (std::size_t i = 0; i < reference.count; ++i) {
    const Vec3 n = reference.at(i);
    if (!(std::isfinite(n[0]) && std::isfinite(n[1]) && std::isfinite(n[2]) && length(n) > 0)) {
      throw Error(ErrorCode::invalid_input, "reference normal " + std::to_string(i) + " is zero, NaN or infinite");
    }
  }
}

render_detail::Rgb shade(const Vec3& normal_camera, const Vec3& light, const Vec3& half, const RenderOptions& o) {
  Vec3 n = normal_camera;
  if (n[2] < 0) n = {-n[0], -n[1], -n[2]};  // two-sided: a disk seen from behind faces us
  const double lambert = dot(n, light);
  double value = o.ambient;
  if (lambert > 0) {
    value += o.diffuse * lambert + o.specular * std::pow(std::max(0.0, dot(n, half)), o.shininess);
  }
  const auto level = (unsigned char)std::lround(255 * std::clamp(value, 0.0, 1.0));
  return {level, level, level};
}

}  // namespace

Image render_points(const CloudView& cloud, const Vec3ArrayView& reference_normals, const RenderOptions& options) {
  options.validate();
  if (options.mode == RenderMode::error && reference_normals.empty() && cloud.size() > 0) {
    throw Error(ErrorCode::invalid_argument,
                "error mode needs reference normals (the true normals, one per point) to compare with");
  }
  detail::check_cloud(cloud, detail::CloudRequirements::filter());
  if (options.mode == RenderMode::error) check_reference(cloud, reference_normals);

  const std::size_t n = cloud.size();
  const int width = options.width, height = options.height;
  const int drawing_width = options.mode == RenderMode::error ? width - options.colour_bar_width : width;
  const int threads = options.threads > 0 ? options.threads : omp_get_max_threads();

  // Surfel radii in model units.
  const BoundingBox cloud_box = bounding_box(cloud.positions);
  double base_radius = 0;
  if (!cloud.has_radii() && n > 0) {
    base_radius = estimate_mean_radius(cloud.positions);
    if (!(base_radius > 0)) {
      const Vec3 d = {cloud_box.max[0] - cloud_box.min[0], cloud_box.max[1] - cloud_box.min[1],
                      cloud_box.max[2] - cloud_box.min[2]};
      base_radius = kFallbackRadiusFraction * length(d);
    }
  }
  auto radius_of = [&](std::size_t i) {
    return options.radius_scale * (cloud.has_radii() ? cloud.radii.get(i) : base_radius);
  };

  BoundingBox box;
  if (options.frame) {
    box = *options.frame;
  } else {
    double largest = 0;
    for (std::size_t i = 0; i < n; ++i) largest = std::max(largest, radius_of(i));
    box = cloud_box;
    for (int k = 0; k < 3; ++k) {
      box.min[k] -= largest;
      box.max[k] += largest;
    }
  }
  const Camera cam = make_camera(box, options, drawing_width);
  const std::vector<double> normals = detail::unit_normals(cloud.normals);
  const Vec3 light = normalized(options.light);
  const Vec3 half = normalized({light[0], light[1], light[2] + 1});  // view direction (0, 0, 1)

  std::vector<Splat> splats(n);
  std::vector<render_detail::Rgb> colours(n);
  const std::int64_t count = std::int64_t(n);
#pragma omp parallel for schedule(static) num_threads(threads)
  for (std::int64_t i = 0; i < count; ++i) {
    const Vec3 p = cloud.positions.at(std::size_t(i));
    const Vec3 w = {normals[3 * i], normals[3 * i + 1], normals[3 * i + 2]};
    Splat& s = splats[i];
    s.x = cam.cx + (dot(p, cam.right) - cam.u_mid) * cam.scale;
    s.y = cam.cy - (dot(p, cam.up) - cam.v_mid) * cam.scale;
    s.depth = dot(p, cam.toward) * cam.scale;
    s.radius = std::max(radius_of(std::size_t(i)) * cam.scale, kMinPixelRadius);
    s.normal = {dot(w, cam.right), dot(w, cam.up), dot(w, cam.toward)};
    if (std::fabs(s.normal[2]) >= kEdgeOn && std::isfinite(s.x) && std::isfinite(s.y) && std::isfinite(s.depth)) {
      // The projected ellipse's half extents: R sqrt(1 - n_x^2) across, R sqrt(1 - n_y^2) down.
      const double ex = s.radius * std::sqrt(std::max(0.0, 1 - s.normal[0] * s.normal[0]));
      const double ey = s.radius * std::sqrt(std::max(0.0, 1 - s.normal[1] * s.normal[1]));
      // Pixel x covers [x, x + 1) and has its centre at x + 0.5.
      pixel_span(s.x - ex - 0.5, s.x + ex - 0.5, drawing_width, s.x0, s.x1);
      pixel_span(s.y - ey - 0.5, s.y + ey - 0.5, height, s.y0, s.y1);
    }
    switch (options.mode) {
      case RenderMode::shaded: colours[i] = shade(s.normal, light, half, options); break;
      case RenderMode::normals:
        for (int k = 0; k < 3; ++k) colours[i][k] = (unsigned char)std::lround(255 * (w[k] * 0.5 + 0.5));
        break;
      case RenderMode::error:
        colours[i] =
            render_detail::viridis(angle_degrees(w, reference_normals.at(std::size_t(i))) / options.error_max_degrees);
        break;
    }
  }

  // Surfels by band of rows, each band's list in index order (a counting sort, sequential so the
  // order is fixed).
  const int bands = (height + kBandRows - 1) / kBandRows;
  std::vector<std::size_t> band_start(std::size_t(bands) + 1, 0);
  for (const Splat& s : splats) {
    if (s.x0 > s.x1 || s.y0 > s.y1) continue;
    for (int b = s.y0 / kBandRows; b <= s.y1 / kBandRows; ++b) ++band_start[b + 1];
  }
  for (int b = 0; b < bands; ++b) band_start[b + 1] += band_start[b];
  std::vector<std::uint32_t> band_members(band_start[bands]);
  {
    std::vector<std::size_t> fill(band_start.begin(), band_start.end() - 1);
    for (std::size_t i = 0; i < n; ++i) {
      const Splat& s = splats[i];
      if (s.x0 > s.x1 || s.y0 > s.y1) continue;
      for (int b = s.y0 / kBandRows; b <= s.y1 / kBandRows; ++b) band_members[fill[b]++] = std::uint32_t(i);
    }
  }

  const std::size_t pixels = std::size_t(width) * std::size_t(height);
  std::vector<double> depth(pixels, -HUGE_VAL);
  std::vector<std::int64_t> owner(pixels, -1);
#pragma omp parallel for schedule(dynamic, 1) num_threads(threads)
  for (int b = 0; b < bands; ++b) {
    const int row_lo = b * kBandRows, row_hi = std::min(height - 1, row_lo + kBandRows - 1);
    for (std::size_t m = band_start[b]; m < band_start[b + 1]; ++m) {
      const std::uint32_t i = band_members[m];
      const Splat& s = splats[i];
      const double r2 = s.radius * s.radius;
      for (int y = std::max(s.y0, row_lo); y <= std::min(s.y1, row_hi); ++y) {
        const double dv = s.y - (y + 0.5);  // up is positive
        for (int x = s.x0; x <= s.x1; ++x) {
          const double du = (x + 0.5) - s.x;
          // Where the ray through the pixel centre meets the disk's plane, relative to its centre.
          const double dz = -(s.normal[0] * du + s.normal[1] * dv) / s.normal[2];
          if (du * du + dv * dv + dz * dz > r2) continue;
          const std::size_t at = std::size_t(y) * width + x;
          const double z = s.depth + dz;
          if (z > depth[at]) {
            depth[at] = z;
            owner[at] = i;
          }
        }
      }
    }
  }

  Image image;
  image.width = width;
  image.height = height;
  image.rgb.assign(3 * pixels, kBackground);
  for (std::size_t at = 0; at < pixels; ++at) {
    if (owner[at] < 0) continue;
    const render_detail::Rgb& c = colours[std::size_t(owner[at])];
    image.rgb[3 * at] = c[0];
    image.rgb[3 * at + 1] = c[1];
    image.rgb[3 * at + 2] = c[2];
  }
  if (options.mode == RenderMode::error)
    render_detail::draw_colour_bar(image, drawing_width, options.error_max_degrees);
  return image;
}

Image render_points(const CloudView& cloud, const RenderOptions& options) {
  return render_points(cloud, Vec3ArrayView{}, options);
}

}  // namespace pnf
