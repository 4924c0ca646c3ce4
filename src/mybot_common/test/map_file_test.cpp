#include "mybot_common/map_file.h"

#include <gtest/gtest.h>
#include <sys/stat.h>

#include <cmath>
#include <cstdlib>
#include <fstream>
#include <sstream>

#include "mybot_common/atomic_file.h"
#include "mybot_common/temp_dir.h"

using mybot_common::MapCells;

namespace
{
MapCells twoByTwo()
{
  MapCells m;
  m.width = 2;
  m.height = 2;
  m.resolution = 0.05;
  m.origin_x = -1.0;
  m.origin_y = 2.0;
  m.origin_yaw = 0.5;
  m.data = {0, 100, -1, 50};  // bottom row: free, occupied; top row: unknown, in between
  return m;
}

std::string read(const std::string& p)
{
  std::ifstream f(p, std::ios::binary);
  std::stringstream s;
  s << f.rdbuf();
  return s.str();
}

}  // namespace

// map_saver's bytes: header, then the top row first, free 254, occupied 0, the rest 205.
TEST(MapFile, PgmIsMapSaversFormatTopRowFirst)
{
  const std::string pgm = mybot_common::mapPgm(twoByTwo());
  const std::string header = "P5\n# CREATOR: map_saver.cpp 0.050 m/pix\n2 2\n255\n";
  ASSERT_EQ(pgm.substr(0, header.size()), header);
  const std::string pixels = pgm.substr(header.size());
  ASSERT_EQ(pixels.size(), 4u);
  EXPECT_EQ(static_cast<unsigned char>(pixels[0]), 205);  // unknown
  EXPECT_EQ(static_cast<unsigned char>(pixels[1]), 205);  // 50: neither free nor occupied
  EXPECT_EQ(static_cast<unsigned char>(pixels[2]), 254);  // free
  EXPECT_EQ(static_cast<unsigned char>(pixels[3]), 0);    // occupied
}

TEST(MapFile, YamlNamesTheImageAndOrigin)
{
  EXPECT_EQ(mybot_common::mapYaml("m.pgm", twoByTwo()),
            "image: m.pgm\nresolution: 0.050000\norigin: [-1.000000, 2.000000, 0.500000]\nnegate: 0\n"
            "occupied_thresh: 0.65\nfree_thresh: 0.196\n\n");
}

TEST(MapFile, MalformedGridIsRefusedBeforeAnyFileIsTouched)
{
  const mybot_common::TempDir dir("map_file_test");
  const std::string& d = dir.path();
  mybot_common::saveMapFiles(d + "/m", twoByTwo());
  const std::string old_pgm = read(d + "/m.pgm"), old_yaml = read(d + "/m.yaml");
  MapCells bad = twoByTwo();
  bad.data.pop_back();
  EXPECT_THROW(mybot_common::saveMapFiles(d + "/m", bad), std::invalid_argument);
  bad = twoByTwo();
  bad.resolution = std::nan("");
  EXPECT_THROW(mybot_common::saveMapFiles(d + "/m", bad), std::invalid_argument);
  bad = twoByTwo();
  bad.origin_x = INFINITY;
  EXPECT_THROW(mybot_common::saveMapFiles(d + "/m", bad), std::invalid_argument);
  EXPECT_EQ(read(d + "/m.pgm"), old_pgm);
  EXPECT_EQ(read(d + "/m.yaml"), old_yaml);
}

TEST(MapFile, UnwritableYamlLeavesTheOldPair)
{
  const mybot_common::TempDir dir("map_file_test");
  const std::string& d = dir.path();
  mybot_common::saveMapFiles(d + "/m", twoByTwo());
  const std::string old_pgm = read(d + "/m.pgm");
  // The YAML path becomes a folder: the new PGM must not land beside the old YAML's place.
  ASSERT_EQ(std::rename((d + "/m.yaml").c_str(), (d + "/m.yaml.bak").c_str()), 0);
  ASSERT_EQ(::mkdir((d + "/m.yaml").c_str(), 0755), 0);
  MapCells other = twoByTwo();
  other.data = {100, 100, 100, 100};
  EXPECT_THROW(mybot_common::saveMapFiles(d + "/m", other), mybot_common::AtomicFileError);
  EXPECT_EQ(read(d + "/m.pgm"), old_pgm);
}
