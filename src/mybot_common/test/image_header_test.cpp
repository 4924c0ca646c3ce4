#include "mybot_common/image_header.h"
#include "mybot_common/temp_dir.h"

#include <gtest/gtest.h>

#include <cstdio>
#include <fstream>

using mybot_common::declaredImageSizeError;
using mybot_common::peekImageSize;

namespace
{
// The test's files, in one directory removed when the test binary exits.
const mybot_common::TempDir& dir()
{
  static const mybot_common::TempDir d("image_header_test");
  return d;
}

std::string file(const std::string& name, const std::string& bytes)
{
  const std::string p = dir().file(name);
  std::ofstream(p, std::ios::binary) << bytes;
  return p;
}
}  // namespace

TEST(ImageHeader, PgmWithComments)
{
  long w = 0, h = 0;
  ASSERT_TRUE(peekImageSize(file("a.pgm", "P5\n# CREATOR: map_saver.cpp 0.050 m/pix\n448 414\n255\n\x01\x02"), w, h));
  EXPECT_EQ(w, 448);
  EXPECT_EQ(h, 414);
}

TEST(ImageHeader, Png)
{
  const std::string png("\x89PNG\r\n\x1a\n\0\0\0\x0dIHDR\0\x03\x0d\x40\0\0\0\x07", 24);  // 200000 x 7
  long w = 0, h = 0;
  ASSERT_TRUE(peekImageSize(file("a.png", png), w, h));
  EXPECT_EQ(w, 200000);
  EXPECT_EQ(h, 7);
}

TEST(ImageHeader, HugeHeaderIsNamedWithTheLimitsParameter)
{
  const std::string p = file("huge.pgm", "P5\n200000 200000\n255\n");
  EXPECT_EQ(declaredImageSizeError(p, 20000, "~max_image_side"),
            "image " + p + " declares 200000 x 200000 pixels, more than 20000 on a side (parameter ~max_image_side)");
  EXPECT_EQ(declaredImageSizeError(file("ok.pgm", "P5 20000 3 255\n"), 20000, "x"), "");
}

TEST(ImageHeader, OtherFormatsAndGarbageAreNotGuessed)
{
  long w = 0, h = 0;
  EXPECT_FALSE(peekImageSize(file("a.bmp", "BM\x36\0\0\0"), w, h));
  EXPECT_FALSE(peekImageSize(file("b.pgm", "P5\nabc def\n"), w, h));
  EXPECT_FALSE(peekImageSize(file("c.pgm", "P5\n99999999999999 1\n"), w, h));
  EXPECT_FALSE(peekImageSize(dir().file("does_not_exist"), w, h));
}
