// pnf::independent_normal_errors (pnf/auto_params.hpp): the gate on the estimate alone that makes
// improve_normals_auto judge the rule's independent-errors setting beside the rule's own.
#include <gtest/gtest.h>

#include "pnf/auto_params.hpp"

namespace pnf::test {
namespace {

// On clean positions, where the coupling has nothing to follow, errors somewhat alike between
// neighbours are PCA's (the clean tori with PCA-32 and PCA-64 normals read correlations 0.18 and
// 0.34, couplings 0.19 and 0.07) and keep the rule's line alone; the same correlations on noisy
// positions, or a near-zero one on clean positions, count as independent errors.
TEST(IndependentErrors, CorrelatedNormalsOnCleanPositionsKeepTheRule) {
  DataEstimate e;
  e.points = 20000;
  e.samples = 4000;
  e.mean_radius = 1;
  e.area_spacing = 1;
  e.normal_noise_deg = 1.0;
  e.normal_position_coupling = 0.07;
  e.curved_share = 1;
  const auto independent = [&](double noise_spacings, double correlation) {
    e.position_noise = noise_spacings * e.area_spacing;
    e.normal_error_correlation = correlation;
    return independent_normal_errors(choose_filter_params(e));
  };
  EXPECT_FALSE(independent(0.0, 0.34));
  EXPECT_FALSE(independent(0.0, 0.18));
  EXPECT_FALSE(independent(0.04, 0.1));
  EXPECT_TRUE(independent(0.0, 0.03));
  EXPECT_TRUE(independent(0.05, 0.34));
  EXPECT_FALSE(independent(0.25, 0.35)) << "correlated as PCA over many neighbours";
}

// Too few points say too little about how the errors relate.
TEST(IndependentErrors, NeedTwoThousandPoints) {
  DataEstimate e;
  e.points = 1999;
  e.samples = 400;
  e.mean_radius = 1;
  e.area_spacing = 1;
  e.normal_noise_deg = 1.0;
  e.normal_position_coupling = 0.07;
  e.normal_error_correlation = 0.03;
  e.curved_share = 1;
  EXPECT_FALSE(independent_normal_errors(choose_filter_params(e)));
  e.points = 2000;
  EXPECT_TRUE(independent_normal_errors(choose_filter_params(e)));
}

}  // namespace
}  // namespace pnf::test
