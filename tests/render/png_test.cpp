// Tests of pnf/png.hpp: the file is a PNG of the right size and format (grey when it can be), the same image gives
// the same bytes, and a failed write leaves nothing behind.
#include "pnf/png.hpp"

#include <gtest/gtest.h>
#include <stdlib.h>

#include <filesystem>
#include <fstream>
#include <set>
#include <string>

#include "pnf/error.hpp"
#include "png_header.hpp"

namespace pnf {
namespace {

namespace fs = std::filesystem;
using render_test::read_bytes;
using render_test::read_png_header;

class PngTest : public ::testing::Test {
 protected:
  void SetUp() override {
    std::string pattern = (fs::temp_directory_path() / "pnf_png_test_XXXXXX").string();
    ASSERT_NE(::mkdtemp(pattern.data()), nullptr);
    folder_ = pattern;
  }
  void TearDown() override {
    std::error_code ignored;
    fs::remove_all(folder_, ignored);
  }
  std::set<std::string> entries() const {
    std::set<std::string> names;
    for (const auto& e : fs::directory_iterator(folder_)) names.insert(e.path().filename().string());
    return names;
  }
  fs::path folder_;
};

Image gradient(int width, int height) {
  Image image{width, height, std::vector<unsigned char>(3 * std::size_t(width) * height)};
  for (std::size_t i = 0; i < image.rgb.size(); ++i) image.rgb[i] = (unsigned char)(i * 7);
  return image;
}

TEST_F(PngTest, WritesAnRgbPngOfTheImageSize) {
  const std::string path = (folder_ / "a.png").string();
  write_png(path, gradient(37, 11));
  const render_test::PngHeader header = read_png_header(path);
  ASSERT_TRUE(header.valid);
  EXPECT_EQ(header.width, 37u);
  EXPECT_EQ(header.height, 11u);
  EXPECT_EQ(header.bit_depth, 8);
  EXPECT_EQ(header.colour_type, 2);  // RGB
  EXPECT_EQ(entries(), std::set<std::string>{"a.png"});
}

TEST_F(PngTest, AllGreyImagesAreStoredAsGrey) {
  const std::string path = (folder_ / "grey.png").string();
  Image image = gradient(16, 9);
  for (std::size_t i = 0; i < image.rgb.size(); i += 3) image.rgb[i + 1] = image.rgb[i + 2] = image.rgb[i];
  write_png(path, image);
  render_test::PngHeader header = read_png_header(path);
  ASSERT_TRUE(header.valid);
  EXPECT_EQ(header.colour_type, 0);  // grey
  EXPECT_EQ(header.width, 16u);
  image.rgb.back() ^= 1;  // one pixel with colour: RGB again
  write_png(path, image);
  EXPECT_EQ(read_png_header(path).colour_type, 2);
}

TEST_F(PngTest, SameImageSameBytesAndReplacesTheOldFile) {
  const std::string a = (folder_ / "a.png").string(), b = (folder_ / "b.png").string();
  std::ofstream(b) << "old contents";
  write_png(a, gradient(20, 30));
  write_png(b, gradient(20, 30));
  EXPECT_EQ(read_bytes(a), read_bytes(b));
  EXPECT_EQ(entries(), (std::set<std::string>{"a.png", "b.png"}));
}

TEST_F(PngTest, BadImagesAreInvalidArgumentsAndWriteNothing) {
  const std::string path = (folder_ / "a.png").string();
  Image wrong_size = gradient(4, 4);
  wrong_size.rgb.pop_back();
  for (const Image& image : {Image{}, Image{0, 5, {}}, wrong_size}) {
    try {
      write_png(path, image);
      FAIL() << "no error for a " << image.width << " x " << image.height << " image of " << image.rgb.size()
             << " bytes";
    } catch (const Error& e) {
      EXPECT_EQ(e.code(), ErrorCode::invalid_argument) << e.what();
      EXPECT_NE(std::string(e.what()).find("a.png"), std::string::npos) << e.what();
    }
  }
  EXPECT_TRUE(entries().empty());
}

TEST_F(PngTest, UnwritablePlacesAreIoErrorsAndLeaveNothing) {
  // A folder that does not exist, and a target that is a folder (the rename fails after the
  // temporary file was written: it must be removed).
  fs::create_directory(folder_ / "taken.png");
  for (const fs::path& path : {folder_ / "missing" / "a.png", folder_ / "taken.png"}) {
    try {
      write_png(path.string(), gradient(8, 8));
      FAIL() << "no error writing " << path;
    } catch (const Error& e) {
      EXPECT_EQ(e.code(), ErrorCode::io) << e.what();
      EXPECT_NE(std::string(e.what()).find(path.string()), std::string::npos) << e.what();
    }
  }
  EXPECT_EQ(entries(), std::set<std::string>{"taken.png"});
  EXPECT_TRUE(fs::is_empty(folder_ / "taken.png"));
}

}  // namespace
}  // namespace pnf
