#include "pnf/filter_params.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "pnf/error.hpp"

namespace {

std::string validation_error(const pnf::FilterParams& p) {
  try {
    p.validate();
  } catch (const pnf::Error& e) {
    EXPECT_EQ(e.code(), pnf::ErrorCode::invalid_argument);
    return e.what();
  }
  return "";
}

TEST(FilterParams, DefaultsAreSpecs) {
  pnf::FilterParams p;
  EXPECT_EQ(p.sigma_f, 4.0);
  EXPECT_EQ(p.sigma_g, 0.5);
  EXPECT_EQ(p.iterations, 4);
  EXPECT_EQ(p.units, pnf::Units::radius);
  EXPECT_EQ(validation_error(p), "");
}

TEST(FilterParams, BadValuesNameTheFieldAndValue) {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const double inf = std::numeric_limits<double>::infinity();
  struct Case {
    pnf::FilterParams params;
    const char* expected;
  };
  auto with = [](auto set) {
    pnf::FilterParams p;
    set(p);
    return p;
  };
  const Case cases[] = {
      {with([](auto& p) { p.sigma_f = 0; }), "sigma_f = 0"},
      {with([](auto& p) { p.sigma_f = -1; }), "sigma_f = -1"},
      {with([&](auto& p) { p.sigma_f = nan; }), "sigma_f = nan"},
      {with([&](auto& p) { p.sigma_g = inf; }), "sigma_g = inf"},
      {with([](auto& p) { p.sigma_g = -0.5; }), "sigma_g = -0.5"},
      {with([](auto& p) { p.iterations = -1; }), "iterations = -1"},
      {with([](auto& p) { p.mean_radius = -2; }), "mean_radius = -2"},
  };
  for (const Case& c : cases) {
    std::string msg = validation_error(c.params);
    EXPECT_NE(msg.find(c.expected), std::string::npos) << "expected '" << c.expected << "' in '" << msg << "'";
  }
}

}  // namespace
