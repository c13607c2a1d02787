// The view entry points: the caller's float or double arrays, at any stride, give the normals of
// the PointCloud call to the last bit, and the output goes where the caller says.
#include <gtest/gtest.h>

#include <cstring>
#include <random>

#include "pnf/cloud_view.hpp"
#include "pnf/error.hpp"
#include "pnf/improve_normals.hpp"
#include "pnf/normal_filter.hpp"
#include "test_backends.hpp"
#include "test_clouds.hpp"

namespace {

using namespace pnf;
using namespace pnf::test;

// A sphere whose coordinates and normals are exactly representable in float, so that float
// views hold the same values as the PointCloud.
PointCloud float_exact_sphere() {
  PointCloud ball = jittered_sphere(3000, 5.0, 31, 15);
  for (std::vector<Vec3>* values : {&ball.positions, &ball.normals}) {
    for (Vec3& v : *values) {
      for (double& c : v) c = double(float(c));
    }
  }
  return ball;
}

class FilterViewsTest : public ::testing::TestWithParam<Backend> {};

TEST_P(FilterViewsTest, FloatAndStridedViewsGiveThePointCloudNormalsBitForBit) {
  NormalFilter* filter = PNF_FILTER_OR_SKIP(GetParam());
  PNF_SKIP_IF_NULL(filter);
  const PointCloud ball = float_exact_sphere();
  const std::size_t n = ball.size();
  const std::vector<Vec3> expected = filter->run(ball).normals;

  // float32, packed.
  std::vector<float> xyz(3 * n), nxyz(3 * n);
  for (std::size_t i = 0; i < n; ++i) {
    for (int c = 0; c < 3; ++c) {
      xyz[3 * i + c] = float(ball.positions[i][c]);
      nxyz[3 * i + c] = float(ball.normals[i][c]);
    }
  }
  std::vector<Vec3> from_float(n);
  filter->run(CloudView(Vec3ArrayView(xyz.data(), n), Vec3ArrayView(nxyz.data(), n)), from_float);
  // float64 inside rows of 7 values (x y z nx ny nz pad), like an interleaved vertex buffer.
  std::vector<double> rows(7 * n, -99.0);
  for (std::size_t i = 0; i < n; ++i) {
    for (int c = 0; c < 3; ++c) {
      rows[7 * i + c] = ball.positions[i][c];
      rows[7 * i + 3 + c] = ball.normals[i][c];
    }
  }
  const std::ptrdiff_t row_bytes = 7 * sizeof(double);
  CloudView interleaved(Vec3ArrayView(rows.data(), n, ScalarType::float64, row_bytes),
                        Vec3ArrayView(rows.data() + 3, n, ScalarType::float64, row_bytes));
  std::vector<Vec3> from_strided(n);
  filter->run(interleaved, from_strided);
  // Column-major (x of every point, then y, then z): a component stride, as a transposed numpy array.
  std::vector<double> columns(3 * n), normal_columns(3 * n);
  for (std::size_t i = 0; i < n; ++i) {
    for (int c = 0; c < 3; ++c) {
      columns[c * n + i] = ball.positions[i][c];
      normal_columns[c * n + i] = ball.normals[i][c];
    }
  }
  const std::ptrdiff_t component_bytes = std::ptrdiff_t(n * sizeof(double));
  std::vector<Vec3> from_columns(n);
  filter->run(CloudView(Vec3ArrayView(columns.data(), n, ScalarType::float64, sizeof(double), component_bytes),
                        Vec3ArrayView(normal_columns.data(), n, ScalarType::float64, sizeof(double), component_bytes)),
              from_columns);
  for (std::size_t i = 0; i < n; ++i) {
    ASSERT_EQ(from_float[i], expected[i]) << "float view, point " << i;
    ASSERT_EQ(from_strided[i], expected[i]) << "strided view, point " << i;
    ASSERT_EQ(from_columns[i], expected[i]) << "column-major view, point " << i;
  }
}

TEST_P(FilterViewsTest, WritesIntoTheCallersStridedBufferAndInPlace) {
  NormalFilter* filter = PNF_FILTER_OR_SKIP(GetParam());
  PNF_SKIP_IF_NULL(filter);
  const PointCloud ball = float_exact_sphere();
  const std::size_t n = ball.size();
  const std::vector<Vec3> expected = filter->run(ball).normals;

  // Into the normal columns of an interleaved double buffer; the other columns untouched.
  std::vector<double> rows(7 * n, -99.0);
  for (std::size_t i = 0; i < n; ++i) {
    for (int c = 0; c < 3; ++c) {
      rows[7 * i + c] = ball.positions[i][c];
      rows[7 * i + 3 + c] = ball.normals[i][c];
    }
  }
  const std::ptrdiff_t row_bytes = 7 * sizeof(double);
  const Vec3ArrayView positions(rows.data(), n, ScalarType::float64, row_bytes);
  const Vec3ArrayView normals(rows.data() + 3, n, ScalarType::float64, row_bytes);
  filter->run(CloudView(positions, normals), MutableVec3ArrayView(rows.data() + 3, n, ScalarType::float64, row_bytes));
  for (std::size_t i = 0; i < n; ++i) {
    for (int c = 0; c < 3; ++c) {
      ASSERT_EQ(rows[7 * i + c], ball.positions[i][c]) << i;
      ASSERT_EQ(rows[7 * i + 3 + c], expected[i][c]) << i;
    }
    ASSERT_EQ(rows[7 * i + 6], -99.0) << "padding written at " << i;
  }

  // Into float: each value rounded once from the double result.
  std::vector<float> out(3 * n);
  filter->run(ball, MutableVec3ArrayView(out.data(), n));
  for (std::size_t i = 0; i < n; ++i) {
    for (int c = 0; c < 3; ++c) ASSERT_EQ(out[3 * i + c], float(expected[i][c])) << i;
  }
}

TEST_P(FilterViewsTest, AnOutputOfTheWrongSizeIsRefusedAndNothingWritten) {
  NormalFilter* filter = PNF_FILTER_OR_SKIP(GetParam());
  PNF_SKIP_IF_NULL(filter);
  const PointCloud ball = float_exact_sphere();
  std::vector<Vec3> out(ball.size() - 1, Vec3{7, 7, 7});
  try {
    filter->run(ball, out);
    FAIL() << "no error";
  } catch (const Error& e) {
    EXPECT_EQ(e.code(), ErrorCode::invalid_argument);
    EXPECT_NE(std::string(e.what()).find("output normals hold 2999 rows for 3000 points"), std::string::npos)
        << e.what();
  }
  for (const Vec3& v : out) ASSERT_EQ(v, (Vec3{7, 7, 7}));
}

INSTANTIATE_TEST_SUITE_P(Backends, FilterViewsTest, ::testing::Values(Backend::reference, Backend::opencl),
                         [](const auto& info) { return std::string(pnf::to_string(info.param)); });

TEST(FilterViews, ANanInAStridedFloatViewNamesTheVertex) {
  std::vector<float> xyz(30, 0.0f), nxyz(30, 1.0f);
  xyz[3 * 7 + 1] = std::numeric_limits<float>::quiet_NaN();
  std::vector<Vec3> out(10);
  try {
    improve_normals(CloudView(Vec3ArrayView(xyz.data(), 10), Vec3ArrayView(nxyz.data(), 10)), out, {},
                    FilterOptions{Device::reference()});
    FAIL() << "no error";
  } catch (const Error& e) {
    EXPECT_EQ(e.code(), ErrorCode::invalid_input);
    EXPECT_NE(std::string(e.what()).find("vertex 7 has a NaN"), std::string::npos) << e.what();
  }
}

}  // namespace
