#include "kernel_source.hpp"

#include <gtest/gtest.h>

#include "pnf/error.hpp"

namespace {

TEST(KernelSource, IncludesAreInlinedOnceWithLineMarkers) {
  std::string src = pnf::detail::kernel_source("filter.cl");
  EXPECT_EQ(src.find("#include \"pnf_"), std::string::npos) << "an include was left in";
  EXPECT_NE(src.find("#line 1 \"pnf_common.h\""), std::string::npos);
  EXPECT_NE(src.find("#line 1 \"pnf_filter.h\""), std::string::npos);
  EXPECT_NE(src.find("__kernel void pnf_filter_pass"), std::string::npos);
  // pnf_common.h is included by pnf_filter.h only; it must appear once.
  EXPECT_EQ(src.find("#line 1 \"pnf_common.h\""), src.rfind("#line 1 \"pnf_common.h\""));
}

TEST(KernelSource, UnknownFileIsAnError) { EXPECT_THROW(pnf::detail::kernel_source("nope.cl"), pnf::Error); }

}  // namespace
