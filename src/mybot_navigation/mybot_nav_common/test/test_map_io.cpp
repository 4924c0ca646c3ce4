#include <gtest/gtest.h>

#include <cstdio>
#include <fstream>
#include <string>

#include "mybot_common/temp_dir.h"
#include "mybot_nav_common/map_io.h"

using namespace mybot_navigation;

namespace
{
void writeFile(const std::string& path, const std::string& content)
{
  std::ofstream(path, std::ios::binary) << content;
}

// A 3 x 2 binary PGM, pixel rows top to bottom: {0, 254, 205}, {100, 150, 255}.
void writeFixtureImage(const std::string& path)
{
  std::string pgm = "P5\n3 2\n255\n";
  for (int v : {0, 254, 205, 100, 150, 255})
    pgm.push_back(static_cast<char>(v));
  writeFile(path, pgm);
}

std::string yaml(const std::string& image, const std::string& extra)
{
  return "image: " + image +
         "\nresolution: 0.1\norigin: [-1.0, 2.0, 0.0]\noccupied_thresh: 0.65\nfree_thresh: 0.196\n" + extra;
}

// Grid rows run bottom-up: grid row 0 is the image's last row.
std::vector<int> cells(const GridMap& m)
{
  return {m.at(0, 1), m.at(1, 1), m.at(2, 1), m.at(0, 0), m.at(1, 0), m.at(2, 0)};
}
}  // namespace

// Expected values worked out by hand from map_server's image_loader rules.
TEST(MapIo, TrinaryFixtureAsRosReadsIt)
{
  const mybot_common::TempDir dir("mybot_map_io");
  const std::string& d = dir.path();
  writeFixtureImage(d + "/m.pgm");
  writeFile(d + "/m.yaml", yaml("m.pgm", "negate: 0\n"));
  const GridMap m = loadMap(d + "/m.yaml");
  EXPECT_EQ(m.info.width, 3);
  EXPECT_EQ(m.info.height, 2);
  EXPECT_DOUBLE_EQ(m.info.resolution, 0.1);
  EXPECT_DOUBLE_EQ(m.info.origin.x, -1.0);
  EXPECT_DOUBLE_EQ(m.info.origin.y, 2.0);
  EXPECT_EQ(cells(m), (std::vector<int>{100, 0, -1, -1, -1, 0}));
}

TEST(MapIo, ScaleFixtureAsRosReadsIt)
{
  const mybot_common::TempDir dir("mybot_map_io");
  const std::string& d = dir.path();
  writeFixtureImage(d + "/m.pgm");
  writeFile(d + "/m.yaml", yaml("m.pgm", "negate: 0\nmode: scale\n"));
  EXPECT_EQ(cells(loadMap(d + "/m.yaml")), (std::vector<int>{100, 0, 1, 89, 47, 0}));
}

TEST(MapIo, NegateFixtureAsRosReadsIt)
{
  const mybot_common::TempDir dir("mybot_map_io");
  const std::string& d = dir.path();
  writeFixtureImage(d + "/m.pgm");
  writeFile(d + "/m.yaml", yaml("m.pgm", "negate: 1\n"));
  EXPECT_EQ(cells(loadMap(d + "/m.yaml")), (std::vector<int>{0, 100, 100, -1, -1, 100}));
}

TEST(MapIo, RawFixtureAsRosReadsIt)
{
  const mybot_common::TempDir dir("mybot_map_io");
  const std::string& d = dir.path();
  writeFixtureImage(d + "/m.pgm");
  writeFile(d + "/m.yaml", yaml("m.pgm", "negate: 0\nmode: raw\n"));
  // Raw copies the byte into the signed cell.
  EXPECT_EQ(cells(loadMap(d + "/m.yaml")), (std::vector<int>{0, -2, -51, 100, -106, -1}));
}

TEST(MapIo, SaveLoadRoundTripIsExact)
{
  const mybot_common::TempDir dir("mybot_map_io");
  const std::string& d = dir.path();
  MapInfo info;
  info.resolution = 0.05;
  info.width = 7;
  info.height = 5;
  info.origin = {-1.25, 3.5, 0.0};
  GridMap m(info, GridMap::kUnknown);
  for (int i = 0; i < 35; ++i)
    m.data[i] = (i % 3 == 0) ? 100 : (i % 3 == 1 ? 0 : -1);
  saveMap(m, d + "/round");
  const GridMap back = loadMap(d + "/round.yaml");
  EXPECT_EQ(back.info.width, 7);
  EXPECT_EQ(back.info.height, 5);
  EXPECT_DOUBLE_EQ(back.info.resolution, 0.05);
  EXPECT_DOUBLE_EQ(back.info.origin.x, -1.25);
  EXPECT_DOUBLE_EQ(back.info.origin.y, 3.5);
  EXPECT_EQ(back.data, m.data);
  // map_saver writes the image as a bare file name.
  std::ifstream y(d + "/round.yaml");
  std::string first;
  std::getline(y, first);
  EXPECT_EQ(first, "image: round.pgm");
}

TEST(MapIo, ErrorsNameTheFieldAndFile)
{
  const mybot_common::TempDir dir("mybot_map_io");
  const std::string& d = dir.path();
  writeFixtureImage(d + "/m.pgm");
  auto message = [&](const std::string& content)
  {
    writeFile(d + "/bad.yaml", content);
    try
    {
      loadMap(d + "/bad.yaml");
    }
    catch (const MapIoError& e)
    {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  const std::string no_res =
      message("image: m.pgm\norigin: [0,0,0]\nnegate: 0\noccupied_thresh: 0.65\nfree_thresh: 0.196\n");
  EXPECT_NE(no_res.find("resolution"), std::string::npos) << no_res;
  EXPECT_NE(no_res.find("bad.yaml"), std::string::npos) << no_res;
  const std::string bad_mode = message(yaml("m.pgm", "negate: 0\nmode: fancy\n"));
  EXPECT_NE(bad_mode.find("mode"), std::string::npos) << bad_mode;
  const std::string missing = message(yaml("nothere.pgm", "negate: 0\n"));
  EXPECT_NE(missing.find("nothere.pgm"), std::string::npos) << missing;
  const std::string bad_origin =
      message("image: m.pgm\nresolution: 0.1\norigin: [0, 0]\nnegate: 0\noccupied_thresh: 0.65\nfree_thresh: 0.196\n");
  EXPECT_NE(bad_origin.find("origin"), std::string::npos) << bad_origin;
  EXPECT_NE(message("{{{").find("bad.yaml"), std::string::npos);
  EXPECT_THROW(loadMap(d + "/does_not_exist.yaml"), MapIoError);
}

// Files are checked for meaning, not just type: each case is refused naming its field.
class MapIoMeaning : public ::testing::Test
{
protected:
  void SetUp() override { writeFixtureImage(d_ + "/m.pgm"); }
  std::string error(const std::string& content)
  {
    writeFile(d_ + "/bad.yaml", content);
    try
    {
      loadMap(d_ + "/bad.yaml");
    }
    catch (const MapIoError& e)
    {
      return e.what();
    }
    return "no error";
  }
  static std::string map(const std::string& origin, const std::string& res, const std::string& occ,
                         const std::string& free, const std::string& image = "m.pgm")
  {
    return "image: " + image + "\nresolution: " + res + "\norigin: " + origin + "\nnegate: 0\noccupied_thresh: " + occ +
           "\nfree_thresh: " + free + "\n";
  }
  const mybot_common::TempDir dir_{"mybot_map_io"};
  const std::string& d_ = dir_.path();
};

TEST_F(MapIoMeaning, NanOriginIsRefused)
{
  const std::string e = error(map("[.nan, 0, 0]", "0.1", "0.65", "0.196"));
  EXPECT_NE(e.find("bad.yaml: field 'origin' must be finite"), std::string::npos) << e;
}

TEST_F(MapIoMeaning, InfiniteResolutionIsRefused)
{
  const std::string e = error(map("[0, 0, 0]", ".inf", "0.65", "0.196"));
  EXPECT_NE(e.find("field 'resolution'"), std::string::npos) << e;
}

TEST_F(MapIoMeaning, FreeAboveOccupiedIsRefused)
{
  const std::string e = error(map("[0, 0, 0]", "0.1", "0.3", "0.6"));
  EXPECT_NE(e.find("'free_thresh' (0.600000) must be smaller than 'occupied_thresh' (0.300000)"), std::string::npos)
      << e;
}

TEST_F(MapIoMeaning, OccupiedThresholdOutsideZeroOneIsRefused)
{
  const std::string e = error(map("[0, 0, 0]", "0.1", "7", "0.196"));
  EXPECT_NE(e.find("field 'occupied_thresh' must be in [0, 1]"), std::string::npos) << e;
  const std::string f = error(map("[0, 0, 0]", "0.1", "0.65", "-0.1"));
  EXPECT_NE(f.find("field 'free_thresh' must be in [0, 1]"), std::string::npos) << f;
}

TEST_F(MapIoMeaning, ImageThatIsAListIsRefused)
{
  const std::string e = error(map("[0, 0, 0]", "0.1", "0.65", "0.196", "[a, b]"));
  EXPECT_NE(e.find("field 'image' must be a string"), std::string::npos) << e;
}

TEST_F(MapIoMeaning, ThresholdThatIsTextIsRefusedQuotingIt)
{
  const std::string e = error(map("[0, 0, 0]", "0.1", "high", "0.196"));
  EXPECT_NE(e.find("field 'occupied_thresh' must be a number, got \"high\""), std::string::npos) << e;
}

// A header claiming 200000 x 200000 (OpenCV threw an uncaught cv::Exception): a clean error
// naming the image and the limit's parameter, before any decoding.
TEST_F(MapIoMeaning, HugeImageHeaderIsRefusedBeforeDecoding)
{
  writeFile(d_ + "/huge.pgm", "P5\n200000 200000\n255\n");
  const std::string e = error(map("[0, 0, 0]", "0.1", "0.65", "0.196", "huge.pgm"));
  EXPECT_NE(e.find("huge.pgm declares 200000 x 200000 pixels, more than 20000 on a side (parameter ~max_image_side)"),
            std::string::npos)
      << e;
}

// The limit is the caller's (map_server's ~max_image_side): also checked on formats whose header
// we do not read, after decoding.
TEST_F(MapIoMeaning, ImageLargerThanTheGivenLimitIsRefused)
{
  writeFile(d_ + "/ok.yaml", map("[0, 0, 0]", "0.1", "0.65", "0.196"));
  EXPECT_NO_THROW(loadMap(d_ + "/ok.yaml", 3));
  EXPECT_THROW(loadMap(d_ + "/ok.yaml", 2), MapIoError);
}

TEST_F(MapIoMeaning, TruncatedImageIsAnErrorNotACrash)
{
  writeFile(d_ + "/cut.pgm", "P5\n300 300\n255\n\x01\x02");
  const std::string e = error(map("[0, 0, 0]", "0.1", "0.65", "0.196", "cut.pgm"));
  EXPECT_NE(e.find("cut.pgm"), std::string::npos) << e;
}
