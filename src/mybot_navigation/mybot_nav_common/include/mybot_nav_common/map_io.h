// map_server's on-disk format: a YAML file (image, resolution, origin, negate, occupied_thresh,
// free_thresh, optional mode) next to an image, read with map_server's exact rules and written
// with map_saver's exact rules.
#pragma once

#include "mybot_common/image_header.h"
#include "mybot_common/map_yaml.h"

#include <string>

#include "mybot_nav_common/grid_map.h"

namespace mybot_navigation
{

// readMapYaml, MapYaml and MapMode are mybot_common's (map_yaml.h): the one reader of the
// format, which the simulator's floor-plan worlds use too.
using MapIoError = mybot_common::MapFileError;
using mybot_common::MapMode;
using mybot_common::MapYaml;
using mybot_common::readMapYaml;

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
