#include "mybot_common/map_yaml.h"

#include <gtest/gtest.h>

#include <fstream>

#include "mybot_common/map_file.h"
#include "mybot_common/temp_dir.h"

using mybot_common::MapFileError;
using mybot_common::MapMode;
using mybot_common::MapYaml;
using mybot_common::readMapYaml;

namespace
{
class MapYamlFile : public ::testing::Test
{
protected:
  std::string write(const std::string& content)
  {
    std::ofstream(path_) << content;
    return path_;
  }
  // readMapYaml's message, or "no error".
  std::string error(const std::string& content)
  {
    try
    {
      readMapYaml(write(content));
    }
    catch (const MapFileError& e)
    {
      return e.what();
    }
    return "no error";
  }
  static std::string fields(const std::string& extra = "")
  {
    return "image: m.pgm\nresolution: 0.05\norigin: [-1.5, 2, 0.25]\nnegate: 0\noccupied_thresh: 0.65\n"
           "free_thresh: 0.196\n" +
           extra;
  }
  const mybot_common::TempDir dir_{"map_yaml"};
  const std::string path_ = dir_.path() + "/m.yaml";
};
}  // namespace

TEST_F(MapYamlFile, ReadsMapServersFieldsAndResolvesTheImageBesideTheFile)
{
  const MapYaml m = readMapYaml(write(fields("mode: scale\n")));
  EXPECT_EQ(m.image, dir_.path() + "/m.pgm");
  EXPECT_DOUBLE_EQ(m.resolution, 0.05);
  EXPECT_DOUBLE_EQ(m.origin_x, -1.5);
  EXPECT_DOUBLE_EQ(m.origin_y, 2.0);
  EXPECT_DOUBLE_EQ(m.origin_yaw, 0.25);
  EXPECT_FALSE(m.negate);
  EXPECT_DOUBLE_EQ(m.occupied_thresh, 0.65);
  EXPECT_DOUBLE_EQ(m.free_thresh, 0.196);
  EXPECT_EQ(m.mode, MapMode::Scale);
  EXPECT_EQ(readMapYaml(write("image: /abs/m.pgm\n" + fields().substr(13))).image, "/abs/m.pgm");
}

// What map_saver writes, read back unchanged.
TEST_F(MapYamlFile, ReadsWhatMapFileWrites)
{
  mybot_common::MapCells cells;
  cells.width = 1, cells.height = 1, cells.resolution = 0.1, cells.origin_x = 3, cells.origin_yaw = 0;
  const MapYaml m = readMapYaml(write(mybot_common::mapYaml("saved.pgm", cells)));
  EXPECT_EQ(m.image, dir_.path() + "/saved.pgm");
  EXPECT_DOUBLE_EQ(m.resolution, 0.1);
  EXPECT_DOUBLE_EQ(m.origin_x, 3.0);
  EXPECT_EQ(m.mode, MapMode::Trinary);
}

// map_server requires every field but mode; each refusal names the file and the field.
TEST_F(MapYamlFile, EachMissingFieldIsNamed)
{
  for (const char* key : {"image", "resolution", "origin", "negate", "occupied_thresh", "free_thresh"})
  {
    std::string text = fields();
    const auto at = text.find(std::string(key) + ":");
    text.erase(at, text.find('\n', at) + 1 - at);
    EXPECT_EQ(error(text), path_ + ": the map does not contain a '" + key + "' field");
  }
}

TEST_F(MapYamlFile, FieldsAreCheckedForMeaning)
{
  EXPECT_EQ(error(fields()), "no error");
  EXPECT_EQ(error("image: m.pgm\nresolution: -1\n"), path_ + ": field 'resolution' must be a positive number");
  EXPECT_EQ(error("image: m.pgm\nresolution: .inf\n"),
            path_ + ": field 'resolution' must be a finite number, got .inf");
  EXPECT_EQ(error("resolution: 0.1\nnegate: 0\noccupied_thresh: high\n"),
            path_ + ": field 'occupied_thresh' must be a number, got \"high\"");
  EXPECT_EQ(error("resolution: 0.1\nnegate: 0\noccupied_thresh: 0.3\nfree_thresh: 0.6\n"),
            path_ + ": field 'free_thresh' (0.600000) must be smaller than 'occupied_thresh' (0.300000)");
  EXPECT_EQ(error(fields("mode: fancy\n")),
            path_ + ": field 'mode' has invalid value \"fancy\" (trinary, scale or raw)");
  const std::string nan_origin = fields().replace(fields().find("[-1.5, 2, 0.25]"), 15, "[.nan, 0, 0]");
  EXPECT_EQ(error(nan_origin), path_ + ": field 'origin' must be finite, got [.nan, 0, 0]");
  const std::string list_image = fields().replace(0, 12, "image: [a, b]");
  EXPECT_EQ(error(list_image), path_ + ": field 'image' must be a string");
  EXPECT_EQ(error("{{{").rfind(path_ + ": not valid YAML", 0), 0u);
  EXPECT_EQ(error("- a\n- b\n"), path_ + ": not a YAML mapping");
  EXPECT_EQ(error(""), path_ + ": not a YAML mapping");
}

TEST(MapCellValue, FollowsMapServersImageLoader)
{
  MapYaml m;  // trinary, 0.65 / 0.196
  const std::uint8_t black = 0, white = 255, grey = 205, mid = 128;
  EXPECT_EQ(mybot_common::mapCellValue(m, &black, 1), 100);
  EXPECT_EQ(mybot_common::mapCellValue(m, &white, 1), 0);
  EXPECT_EQ(mybot_common::mapCellValue(m, &grey, 1), -1);
  m.negate = true;
  EXPECT_EQ(mybot_common::mapCellValue(m, &white, 1), 100);
  m.negate = false;
  m.mode = MapMode::Scale;  // (255 - 128) / 255 = 0.498, between the thresholds: 1 + 98 * 0.665
  EXPECT_EQ(mybot_common::mapCellValue(m, &mid, 1), 66);
  const std::uint8_t transparent_grey[2] = {128, 0};
  EXPECT_EQ(mybot_common::mapCellValue(m, transparent_grey, 2), -1);
  m.mode = MapMode::Raw;
  EXPECT_EQ(mybot_common::mapCellValue(m, &mid, 1), static_cast<std::int8_t>(128));
  // Colour: the mean of the channels, not a luminance.
  m.mode = MapMode::Trinary;
  const std::uint8_t red[3] = {255, 0, 0};  // mean 85: occupancy 0.667
  EXPECT_EQ(mybot_common::mapCellValue(m, red, 3), 100);
}
