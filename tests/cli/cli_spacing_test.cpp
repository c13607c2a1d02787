// One spacing: `pnf info` and `pnf filter --auto` report the same mean surfel radius for one file,
// the estimate without a radius property and the property's mean with one (issue 12: before it,
// --auto used its own cylinder spacing, 20% above info's on random samples, and ignored the
// property).
#include <gtest/gtest.h>

#include <random>
#include <regex>
#include <string>

#include "cli_test_support.hpp"
#include "pnf/point_cloud.hpp"
#include "test_clouds.hpp"

namespace pnf::test {
namespace {

// Uniform random samples of a creased plane (a 150 degree ridge along x = 0), lightly noisy
// normals: what scanners give, and where the two old spacings differed most.
PointCloud creased_plane(int points, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(-1, 1);
  constexpr double kSlope = 0.27;  // tan 15 degrees on each side
  PointCloud c;
  for (int i = 0; i < points; ++i) {
    const double x = u(rng), y = u(rng);
    c.positions.push_back({x, y, -kSlope * std::abs(x)});
    c.normals.push_back(jitter_normal(normalized({x < 0 ? -kSlope : kSlope, 0, 1}), 3, rng));
  }
  return c;
}

// The number after `label` (spaces after it skipped) in `text`; fails the test when absent.
std::string number_after(const std::string& text, const std::string& label) {
  std::smatch m;
  if (!std::regex_search(text, m, std::regex(label + " +([-+0-9.eE]+)"))) {
    ADD_FAILURE() << "no '" << label << " <number>' in\n" << text;
    return "?";
  }
  return m[1];
}

void expect_one_spacing(const CliRun& info, const CliRun& filter, const std::string& want) {
  ASSERT_EQ(info.exit_code, 0) << info.describe();
  ASSERT_EQ(filter.exit_code, 0) << filter.describe();
  const std::string from_info = number_after(info.out, "mean radius");
  if (!want.empty()) EXPECT_EQ(from_info, want) << info.out;
  // --auto's own report, then the filter's summary of the run it made.
  std::smatch m;
  ASSERT_TRUE(std::regex_search(filter.err, m, std::regex("--auto:[\\s\\S]*?mean radius +([-+0-9.eE]+)")))
      << filter.err;
  EXPECT_EQ(m[1], from_info) << "--auto's mean radius is not info's\n" << info.out << filter.err;
  const std::string summary = filter.err.substr(filter.err.find("pnf filter:"));
  EXPECT_EQ(number_after(summary, "mean radius"), from_info) << "the run's radius is not info's\n" << filter.err;
  // Nobody gave it: the summary says where it came from (issue 32), as --auto's report does.
  EXPECT_EQ(summary.find("(given)"), std::string::npos) << filter.err;
}

TEST_F(CliTest, InfoAndAutoReportOneSpacing) {
  const std::string in = write_cloud("ridge.ply", creased_plane(6000, 5));
  expect_one_spacing(run({"info", in}), run({"filter", in, path("out.ply"), "--auto", "--backend", "reference"}), "");
}

TEST_F(CliTest, InfoAndAutoBothHonourTheRadiusProperty) {
  PointCloud cloud = creased_plane(6000, 6);
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> radius(0.02, 0.03);
  double sum = 0;
  for (std::size_t i = 0; i < cloud.size(); ++i) {
    cloud.radii.push_back(radius(rng));
    sum += cloud.radii.back();
  }
  char mean[32];
  std::snprintf(mean, sizeof mean, "%.6g", sum / double(cloud.size()));
  const std::string in = write_cloud("ridge_radius.ply", cloud);
  const CliRun filter = run({"filter", in, path("out.ply"), "--auto", "--backend", "reference"});
  expect_one_spacing(run({"info", in}), filter, mean);
  EXPECT_TRUE(contains(filter.err, "radius property")) << filter.err;
}

}  // namespace
}  // namespace pnf::test
