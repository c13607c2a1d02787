// pnf::render_points — draws a point cloud as shaded surfels into an RGB image, to see what a
// normal field looks like (and how much filtering changed it).
//
// Each point is an oriented disk (surfel) centred on the point, perpendicular to its normal,
// drawn with a depth buffer (the nearest disk wins each pixel) and one flat colour per disk. The
// camera is orthographic: the picture does not depend on a camera distance, the framing is exact,
// and two renders of clouds with the same frame line up pixel for pixel.
//
// Thread safety: render_points may be called concurrently; it uses up to `threads` OpenMP
// threads and gives the same image, byte for byte, for any thread count.
#pragma once

#include <optional>
#include <vector>

#include "pnf/bounding_box.hpp"
#include "pnf/cloud_view.hpp"
#include "pnf/point_cloud.hpp"

namespace pnf {

// What colour a surfel gets.
enum class RenderMode {
  shaded,   // grey, Blinn-Phong lit from its normal (two-sided: a disk seen from behind is lit
            // with its normal flipped)
  normals,  // its unit world-space normal n as the colour n * 0.5 + 0.5 (x red, y green, z blue)
  error,    // the angle between its normal and the reference normal of the same index, on a
            // viridis scale from 0 to error_max_degrees, with a colour bar at the right
};

// An 8-bit RGB image, rows from top to bottom, each row left to right: pixel (x, y) is at
// rgb[3 * (y * width + x)] (red, then green, blue). No gamma: values are the shading result
// times 255, rounded.
struct Image {
  int width = 0;
  int height = 0;
  std::vector<unsigned char> rgb;  // 3 * width * height
};

struct RenderOptions {
  // Image size in pixels, each 1 to 16384. Default 640 x 480. In error mode the colour bar takes
  // the rightmost colour_bar_width pixels and the points are drawn in the rest.
  int width = 640;
  int height = 480;

  // View direction, in degrees. The model's +y axis is up. Azimuth turns the camera about +y
  // (0: looking from +z toward -z, 90: from +x toward -x); elevation raises it toward +y (90:
  // looking straight down). Azimuth any finite value; elevation -90 to 90. Default 0, 0.
  double azimuth_degrees = 0;
  double elevation_degrees = 0;

  // Direction toward the light in camera coordinates (x right, y up, z toward the viewer), so the
  // light moves with the camera. Finite, non-zero; need not be unit length. Default up, left and
  // in front: the usual studio key light that shows relief without hiding the left side.
  Vec3 light{-0.5, 0.6, 1.0};

  RenderMode mode = RenderMode::shaded;

  // Surfel radius = radius_scale * (the point's `radius` property when the cloud has radii, else
  // estimate_mean_radius(positions), the spacing h the filter also uses), never less than 0.75
  // pixel so that a dense cloud drawn small keeps no holes (a pixel's centre is within sqrt(2)/2
  // pixel of any point in it). > 0, at most 100. Default 1.2: disks of radius sqrt(2)/2 h just
  // close a square grid of spacing h, 1 closes grids jittered by up to 0.3 h, and 1.2 closes
  // those jittered by up to half a spacing (a uniform but irregular sampling) from any view, and
  // leaves at most isolated pixels open where normals noisy by 15 degrees tilt the disks away
  // from the surface. Larger disks would hide more of each other, and with them detail.
  double radius_scale = 1.2;

  // Shading of RenderMode::shaded, each >= 0 and finite: a surfel with unit normal n (camera
  // coordinates, flipped toward the viewer), unit light l and half vector h = (l + v)/|l + v|,
  // v = (0, 0, 1), gets grey level
  //   255 * clamp(ambient + diffuse * max(0, n.l) + specular * max(0, n.h)^shininess, 0, 1),
  // the specular term only where n.l > 0. Defaults 0.1, 0.7, 0.15, 40 (shininess > 0): they sum
  // to 0.95, so that the brightest highlight (242) stays apart from the white background.
  double ambient = 0.1;
  double diffuse = 0.7;
  double specular = 0.15;
  double shininess = 40;

  // Error mode: angles at or above this many degrees get the top colour. In (0, 180]. Default 30,
  // wide enough for raw PCA normals of a scan, fine enough to show a few degrees.
  double error_max_degrees = 30;
  // Error mode: pixels on the right taken by the colour bar and its labels (in degrees). Must
  // leave at least 16 pixels for the points. Default 80.
  int colour_bar_width = 80;

  // The box the camera frames: its projection, centred, fills the drawing area up to a margin of
  // 5% of the area's size on each side. Empty (default): the cloud's bounding box grown by the
  // largest surfel radius, so that nothing is clipped. Give the same box to several renders (e.g.
  // the union of two clouds' boxes) to draw them from the same camera.
  std::optional<BoundingBox> frame;

  // OpenMP threads; 0 (default) means all cores. >= 0. The image does not depend on it.
  int threads = 0;

  // Throws pnf::Error(invalid_argument) naming the first bad field and its value.
  void validate() const;
};

// Renders `cloud` (N positions and N normals, optional N radii, read in place: a PointCloud
// converts to the view; normals need not be unit length)
// as options.mode says; for RenderMode::error, `reference_normals` (N vectors, non-zero) are the
// normals each point's is compared with, otherwise they are ignored and may be empty. Returns an
// options.width x options.height image on a white background. An empty cloud gives the
// background (and, in error mode, the colour bar).
//
// Throws pnf::Error: invalid_argument for bad options, or error mode without reference normals;
// invalid_input for a cloud without normals, mismatched sizes (naming both), a non-finite
// coordinate or radius, a negative radius, or a zero or non-finite normal (naming the first bad
// index).
Image render_points(const CloudView& cloud, const Vec3ArrayView& reference_normals, const RenderOptions& options);

// The same without reference normals, for the shaded and normals modes.
Image render_points(const CloudView& cloud, const RenderOptions& options = {});

}  // namespace pnf
