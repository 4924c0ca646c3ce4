// map_server's on-disk format: a YAML file (image, resolution, origin, negate, occupied_thresh,
// free_thresh, optional mode) next to an image, read with map_server's exact rules and written
// with map_saver's exact rules.
#pragma once

#include "mybot_common/image_header.h"

#include <stdexcept>
#include <string>

#include "mybot_nav_common/grid_map.h"

namespace mybot_navigation
{

struct MapIoError : std::runtime_error
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
  std::string image;  // resolved path (relative names are relative to the YAML's directory)
  double resolution = 0.0;
  Pose2D origin;
  bool negate = false;
  double occupied_thresh = 0.65;
  double free_thresh = 0.196;
  MapMode mode = MapMode::Trinary;
};

// Throws MapIoError naming the file and the field.
MapYaml readMapYaml(const std::string& yaml_path);
// Loads the image and converts pixels exactly as map_server's image_loader does.
// Images with more pixels on a side are refused (map_server's ~max_image_side): a header
// claiming 200000 x 200000 gets an error, not a 40 GB allocation.
GridMap loadMapImage(const MapYaml& meta, long max_side = mybot_common::kDefaultMaxImageSide);
GridMap loadMap(const std::string& yaml_path, long max_side = mybot_common::kDefaultMaxImageSide);

// map_saver's conversion: 0 <= v <= free -> 254, v >= occ -> 0, else 205; PGM (P5) rows from the top.
// Both files or neither (mybot_common::saveMapFiles): a failure throws MapIoError naming the file
// and leaves an existing pair as it was.
void saveMap(const GridMap& map, const std::string& basename, int occ = 65, int free = 25);

}  // namespace mybot_navigation
