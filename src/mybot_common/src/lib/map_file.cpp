#include "mybot_common/map_file.h"

#include <cmath>
#include <cstdio>
#include <stdexcept>

#include "mybot_common/atomic_file.h"

namespace mybot_common
{

namespace
{
void checkGrid(const MapCells& map)
{
  if (map.width < 0 || map.height < 0)
    throw std::invalid_argument("map size " + std::to_string(map.width) + " x " + std::to_string(map.height) +
                                " is negative");
  if (map.data.size() != static_cast<std::size_t>(map.width) * static_cast<std::size_t>(map.height))
    throw std::invalid_argument("map data has " + std::to_string(map.data.size()) + " cells, expected width*height = " +
                                std::to_string(static_cast<std::size_t>(map.width) * map.height));
  if (!std::isfinite(map.resolution) || map.resolution <= 0.0)
    throw std::invalid_argument("map resolution must be a positive number, got " + std::to_string(map.resolution));
  if (!std::isfinite(map.origin_x) || !std::isfinite(map.origin_y) || !std::isfinite(map.origin_yaw))
    throw std::invalid_argument("map origin must be finite");
}
}  // namespace

std::string mapPgm(const MapCells& map, int occ, int free, const std::string& creator)
{
  checkGrid(map);
  char resolution[64];
  std::snprintf(resolution, sizeof resolution, "%.3f", map.resolution);
  std::string comment = creator;  // one comment line, whatever the creator's name holds
  for (char& c : comment)
    if (c == '\n' || c == '\r')
      c = ' ';
  std::string out = "P5\n# CREATOR: " + comment + " " + resolution + " m/pix\n" + std::to_string(map.width) + " " +
                    std::to_string(map.height) + "\n255\n";
  out.reserve(out.size() + map.data.size());
  for (int y = map.height - 1; y >= 0; --y)  // the image's first row is the grid's top
    for (int x = 0; x < map.width; ++x)
    {
      const int v = map.data[static_cast<std::size_t>(y) * map.width + x];
      out.push_back(static_cast<char>(v >= 0 && v <= free ? 254 : (v >= occ ? 0 : 205)));
    }
  return out;
}

std::string mapYaml(const std::string& image_name, const MapCells& map)
{
  char text[512];
  std::snprintf(text, sizeof text,
                "image: %s\nresolution: %f\norigin: [%f, %f, %f]\nnegate: 0\noccupied_thresh: 0.65\n"
                "free_thresh: 0.196\n\n",
                image_name.c_str(), map.resolution, map.origin_x, map.origin_y, map.origin_yaw);
  return text;
}

void saveMapFiles(const std::string& basename, const MapCells& map, int occ, int free, const std::string& creator)
{
  const std::string pgm = basename + ".pgm";
  const auto slash = pgm.find_last_of('/');
  const std::string image_name = slash == std::string::npos ? pgm : pgm.substr(slash + 1);
  // Both contents first: a malformed grid throws before any file is touched.
  std::string image = mapPgm(map, occ, free, creator);
  std::string yaml = mapYaml(image_name, map);
  writeFilesAtomically({{pgm, std::move(image)}, {basename + ".yaml", std::move(yaml)}});
}

}  // namespace mybot_common
