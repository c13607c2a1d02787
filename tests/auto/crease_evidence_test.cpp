// detail::crease_evidence (lib/src/auto/crease_evidence.hpp): the crease length that a count of
// edge fits implies, against answers worked by hand.
#include "auto/crease_evidence.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <vector>

namespace pnf::detail {
namespace {

// 10 of 100 fits at an edge, on 10000 points of spacing 0.01 (area 1) with fits of radius 0.05:
// the band is 0.1 wide, so 10% of the area is a crease 1 long; over sqrt(area) = 1 that is 1.
TEST(CreaseEvidence, LengthFromTheEdgeBand) {
  CreaseFits fits;
  for (int i = 0; i < 100; ++i) fits.residuals.push_back(i < 10 ? 0.3 : 0.01);
  fits.fit_radius = 0.05;
  const CreaseEvidence e = crease_evidence(fits, 0.1, 10000, 0.01);
  EXPECT_EQ(e.samples, 100u);
  EXPECT_EQ(e.edge_samples, 10u);
  EXPECT_DOUBLE_EQ(e.length_per_size, 1.0);
}

// The same surface 4 times denser: spacing halves, and so does the fit radius (a fixed number of
// neighbours), and the edge band's share of the samples halves with it; the length does not move.
TEST(CreaseEvidence, FourTimesDenserMeasuresTheSame) {
  CreaseFits sparse, dense;
  for (int i = 0; i < 1000; ++i) {
    sparse.residuals.push_back(i < 100 ? 1.0 : 0.0);
    dense.residuals.push_back(i < 50 ? 1.0 : 0.0);
  }
  sparse.fit_radius = 0.05;
  dense.fit_radius = 0.025;
  const double a = crease_evidence(sparse, 0.5, 10000, 0.01).length_per_size;
  const double b = crease_evidence(dense, 0.5, 40000, 0.005).length_per_size;
  EXPECT_DOUBLE_EQ(a, b);
  EXPECT_GT(a, 0);
}

// The sharpness: the median edge fit's residual, the noise taken out in quadrature, over the fit
// radius. Edge residuals 0.2, 0.3 (the median of three), 0.5 with noise 0.1 and radius 0.05:
// sqrt(0.09 - 0.01) / 0.05. Fits under the edge residual do not count.
TEST(CreaseEvidence, SharpnessIsTheMedianKinkOverTheFitRadius) {
  CreaseFits fits;
  fits.residuals = {0.01, 0.5, 0.2, 0.02, 0.3};
  fits.fit_radius = 0.05;
  fits.noise = 0.1;
  const CreaseEvidence e = crease_evidence(fits, 0.15, 10000, 0.01);
  EXPECT_EQ(e.edge_samples, 3u);
  EXPECT_NEAR(e.sharpness, std::sqrt(0.08) / 0.05, 1e-12);
  fits.residuals = {0.01, 0.02};
  EXPECT_EQ(crease_evidence(fits, 0.15, 10000, 0.01).sharpness, 0.0) << "no edge fits";
}

TEST(CreaseEvidence, NothingToJudgeIsNoCrease) {
  CreaseFits none;
  none.fit_radius = 0.05;
  EXPECT_EQ(crease_evidence(none, 0.1, 1000, 0.01).length_per_size, 0.0);
  CreaseFits flat;
  flat.residuals = {0.01, 0.02};
  flat.fit_radius = 0.05;
  EXPECT_EQ(crease_evidence(flat, 0.1, 1000, 0.01).length_per_size, 0.0);
  flat.fit_radius = 0;  // no radius: no band to convert
  flat.residuals = {1.0};
  EXPECT_EQ(crease_evidence(flat, 0.1, 1000, 0.01).length_per_size, 0.0);
}

}  // namespace
}  // namespace pnf::detail
