// pnf::detail::independent_normal_errors (lib/src/auto/judged_passes.hpp): the gate on the
// estimate alone that makes improve_normals_auto judge the rule's independent-errors setting beside the rule's own.
#include <gtest/gtest.h>

#include <cstddef>

#include "auto/judged_passes.hpp"
#include "pnf/choose_filter_params.hpp"

namespace pnf::test {
namespace {

// An estimate of curved, clean-ish data with 1-degree normal errors barely coupled to the
// positions; noise in area spacings, the neighbours' error correlation and the points vary.
bool independent(double noise_spacings, double correlation, std::size_t points = 20000) {
  DataEstimate e;
  e.points = points;
  e.samples = points / 5;
  e.mean_radius = 1;
  e.area_spacing = 1;
  e.normal_noise_deg = 1.0;
  e.normal_position_coupling = 0.07;
  e.curved_share = 1;
  e.position_noise = noise_spacings * e.area_spacing;
  e.normal_error_correlation = correlation;
  return detail::independent_normal_errors(choose_filter_params(e));
}

// On clean positions, where the coupling has nothing to follow, errors somewhat alike between
// neighbours are PCA's (the clean tori with PCA-32 and PCA-64 normals read correlations 0.18 and
// 0.34, couplings 0.19 and 0.07) and keep the rule's line alone; the same correlations on noisy
// positions, or a near-zero one on clean positions, count as independent errors.
TEST(IndependentErrors, CorrelatedNormalsOnCleanPositionsKeepTheRule) {
  EXPECT_FALSE(independent(0.0, 0.34));
  EXPECT_FALSE(independent(0.0, 0.18));
  EXPECT_FALSE(independent(0.04, 0.1));
  EXPECT_TRUE(independent(0.0, 0.03));
  EXPECT_TRUE(independent(0.05, 0.34));
  EXPECT_FALSE(independent(0.25, 0.35)) << "correlated as PCA over many neighbours";
}

// Too few points say too little about how the errors relate.
TEST(IndependentErrors, NeedTwoThousandPoints) {
  EXPECT_FALSE(independent(0.0, 0.03, 1999));
  EXPECT_TRUE(independent(0.0, 0.03, 2000));
}

}  // namespace
}  // namespace pnf::test
