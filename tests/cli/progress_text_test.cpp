// The pnf command's progress display (tools/pnf/progress_text.hpp): the bar's labels and shares,
// and the lines it writes where stderr is not a terminal (a log; rank 0 under mpirun).
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>
#include <string>

#include "progress_text.hpp"

namespace pnf::test {
namespace {

std::string written(std::FILE* f) {
  std::rewind(f);
  std::string text;
  for (int c = std::fgetc(f); c != EOF; c = std::fgetc(f)) text += char(c);
  return text;
}

TEST(ProgressText, PassesCountWithinAPassAndOtherStagesTheirOwnShare) {
  const cli::ProgressText within = cli::progress_text({2, 8, 1.0, ProgressStage::filtering, 0.5});
  EXPECT_DOUBLE_EQ(within.done, 2.5 / 8);
  EXPECT_EQ(within.label, "pass 3/8");
  const cli::ProgressText ended = cli::progress_text({3, 8, 1.0, ProgressStage::pass, 1.0});
  EXPECT_DOUBLE_EQ(ended.done, 3.0 / 8);
  EXPECT_EQ(ended.label, "pass 3/8");
  const cli::ProgressText lists = cli::progress_text({0, 8, 1.0, ProgressStage::lists, 0.45});
  EXPECT_DOUBLE_EQ(lists.done, 0.45);
  EXPECT_EQ(lists.label, "lists  45%");
  EXPECT_DOUBLE_EQ(cli::progress_text({0, 0, 1.0, ProgressStage::estimate, 1.7}).done, 1.0);
}

TEST(ProgressLines, WriteALinePerIntervalWithTheStageAndShare) {
  std::FILE* f = std::tmpfile();
  ASSERT_NE(f, nullptr);
  cli::ProgressLines every(f, 0.0);
  every({0, 4, 0.5, ProgressStage::lists, 0.25});
  every({1, 4, 0.5, ProgressStage::filtering, 0.5});
  every({2, 4, 0.5, ProgressStage::pass, 1.0});
  const std::string text = written(f);
  std::fclose(f);
  EXPECT_NE(text.find("pnf: lists  25% ("), std::string::npos) << text;
  EXPECT_NE(text.find("pnf: pass 2/4, 38% of the passes ("), std::string::npos) << text;
  EXPECT_NE(text.find("pnf: pass 2/4, 50% of the passes ("), std::string::npos) << text;
  EXPECT_EQ(std::count(text.begin(), text.end(), '\n'), 3) << text;
}

TEST(ProgressLines, AShortRunWritesNone) {
  std::FILE* f = std::tmpfile();
  ASSERT_NE(f, nullptr);
  cli::ProgressLines rarely(f, 3600.0);
  for (int pass = 1; pass <= 4; ++pass) rarely({pass, 4, 0.1, ProgressStage::pass, 1.0});
  EXPECT_EQ(written(f), "");
  std::fclose(f);
}

}  // namespace
}  // namespace pnf::test
