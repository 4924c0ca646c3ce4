// map_server's map YAML (the file beside the map image): read and checked with map_server's rules,
// and map_server's rule that turns an image pixel into a cell. The one reader of the format:
// mybot_map_server (through mybot_nav_common's loadMap) and the simulator's floor-plan worlds
// (mybot_gazebo_lite) both call it, so a file one of them takes the other takes too, with the same
// message when it does not. map_file.h writes the format. No ROS, no OpenCV.
#pragma once

#include <cstdint>
#include <stdexcept>
#include <string>

namespace mybot_common
{

// A map file pair that cannot be read or written; the message names the file and the field.
struct MapFileError : std::runtime_error
{
  using std::runtime_error::runtime_error;
};

enum class MapMode
{
  Trinary,
  Scale,
  Raw
};

struct MapYaml
{
  std::string image;        // resolved: a relative name is relative to the YAML's folder
  double resolution = 0.0;  // m per cell
  double origin_x = 0.0, origin_y = 0.0, origin_yaw = 0.0;  // the lower-left cell's corner
  bool negate = false;
  double occupied_thresh = 0.65;
  double free_thresh = 0.196;
  MapMode mode = MapMode::Trinary;
};

// map_server's fields: image, resolution, origin, negate, occupied_thresh and free_thresh are
// required, mode is optional (trinary). Checked for meaning as well as type: a resolution that is
// not positive, an origin that is not finite, thresholds outside [0, 1] or free not below occupied
// are refused. Keys it does not know are left to the caller. Throws MapFileError
// ("m.yaml: field 'origin' must be finite, got [nan, 0, 0]").
MapYaml readMapYaml(const std::string& yaml_path);

// The cell map_server's image_loader makes of one pixel of `channels` 8-bit channels (1 grey,
// 2 grey + alpha, 3 RGB, 4 RGBA): from the mean of the colour channels (alpha too in trinary
// mode), negated if asked; occupied (100) above occupied_thresh, free (0) below free_thresh,
// otherwise unknown (-1), or in scale mode 1..99 (unknown if transparent). Raw mode: the mean.
std::int8_t mapCellValue(const MapYaml& meta, const std::uint8_t* pixel, int channels);

}  // namespace mybot_common
