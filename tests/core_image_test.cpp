// Images: PNG and EXR written atomically and read back bit-exact; bad paths are named.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <filesystem>

#include "forest/core/error.hpp"
#include "forest/core/files.hpp"
#include "forest/core/image.hpp"
#include "test_paths.hpp"

namespace forest {
namespace {
namespace fs = std::filesystem;

fs::path freshFolder(const std::string& name) {
  const fs::path folder = fs::path(FOREST_TEST_OUTPUT) / name;
  fs::remove_all(folder);
  return folder;
}

TEST(Image, PngRoundTripsExactlyAndLeavesNoTemporaryFile) {
  const fs::path folder = freshFolder("image-png");
  Image8 image(7, 5, 4);
  for (size_t i = 0; i < image.pixels.size(); ++i) image.pixels[i] = static_cast<std::uint8_t>(i * 37 % 256);
  writeImage(folder / "a.png", image);
  const Image8 back = readImage8(folder / "a.png");
  EXPECT_EQ(back.width, 7);
  EXPECT_EQ(back.height, 5);
  EXPECT_EQ(back.channels, 4);
  EXPECT_EQ(back.pixels, image.pixels);
  EXPECT_EQ(std::distance(fs::directory_iterator(folder), fs::directory_iterator()), 1);
}

TEST(Image, ExrKeepsFloats) {
  const fs::path folder = freshFolder("image-exr");
  ImageF image(3, 2, 1);
  image.pixels = {0.0f, 1e-7f, 0.333333f, 12345.678f, -2.5f, 1.0f};
  writeImage(folder / "d.exr", image);
  EXPECT_EQ(readImageF(folder / "d.exr").pixels, image.pixels);
}

TEST(Image, FlipRowsReversesRowOrder) {
  Image8 image(2, 3, 1);
  image.pixels = {1, 2, 3, 4, 5, 6};
  flipRows(image);
  EXPECT_EQ(image.pixels, (std::vector<std::uint8_t>{5, 6, 3, 4, 1, 2}));
}

TEST(Image, UnknownExtensionIsAnErrorAndNothingIsLeftBehind) {
  const fs::path folder = freshFolder("image-bad");
  EXPECT_THROW(writeImage(folder / "a.notaformat", Image8(2, 2, 3)), Error);
  EXPECT_TRUE(!fs::exists(folder) || fs::is_empty(folder));
}

TEST(Image, MissingFileIsNamed) {
  EXPECT_THAT([] { readImage8("/nonexistent/x.png"); },
              ::testing::ThrowsMessage<InputError>(::testing::HasSubstr("/nonexistent/x.png: no such file")));
}

TEST(Files, AtomicWriteReplacesContents) {
  const fs::path folder = freshFolder("files");
  writeFileAtomic(folder / "r.json", "first");
  writeFileAtomic(folder / "r.json", "second");
  EXPECT_EQ(readTextFile(folder / "r.json"), "second");
  EXPECT_EQ(std::distance(fs::directory_iterator(folder), fs::directory_iterator()), 1);
}

}  // namespace
}  // namespace forest
