// map_server's file pair (NAME.pgm + NAME.yaml) as ROS navigation's map_saver writes it, byte for
// byte, saved atomically: a failed or killed save leaves the old pair as it was. The C++ home of
// this format; Python's is mybot_map_server.map_saver. No ROS.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

namespace mybot_common
{

// An occupancy grid as nav_msgs/OccupancyGrid holds it: row-major, row 0 at the bottom (lowest
// y), -1 unknown, 0..100 occupancy; origin = the pose of cell (0, 0)'s corner.
struct MapCells
{
  int width = 0, height = 0;
  double resolution = 0.0;
  double origin_x = 0.0, origin_y = 0.0, origin_yaw = 0.0;
  std::vector<std::int8_t> data;
};

// The P5 image, top row first: 0 <= v <= free -> 254, v >= occ -> 0, anything else 205.
// Throws std::invalid_argument if data does not hold width * height cells or a size is negative.
std::string mapPgm(const MapCells& map, int occ = 65, int free = 25, const std::string& creator = "map_saver.cpp");

// The YAML that goes with it (map_saver's thresholds 0.65 / 0.196, trinary).
std::string mapYaml(const std::string& image_name, const MapCells& map);

// Writes basename.pgm and basename.yaml, both or neither (AtomicFileError naming the file; the
// grid is checked before anything is written). Throws std::invalid_argument for a malformed grid:
// a wrong cell count, or a resolution or origin that is not finite.
void saveMapFiles(const std::string& basename, const MapCells& map, int occ = 65, int free = 25,
                  const std::string& creator = "map_saver.cpp");

}  // namespace mybot_common
