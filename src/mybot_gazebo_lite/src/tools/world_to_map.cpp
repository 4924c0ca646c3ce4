// world_to_map: renders a world's static geometry into a ground-truth
// occupancy grid (PGM + YAML in map_server's format).
#include "mybot_gazebo_lite/parsing.h"
#include "mybot_gazebo_lite/raycast2d.h"
#include "mybot_common/map_file.h"

#include <cmath>
#include <cstdio>
#include <iostream>
#include <limits>
#include <string>

using namespace mybot_gazebo_lite;

namespace
{
const char* const kUsage =
    "usage: world_to_map <world file (.world/.sdf/.yaml)> <out_name> [--resolution 0.05]\n"
    "                    [--height H | --z-min 0.05 --z-max 2.0] [--margin 1.0]\n"
    "writes <out_name>.pgm and <out_name>.yaml (map_server format).\n"
    "--height slices at one height (e.g. the laser's); otherwise any static\n"
    "geometry between z-min and z-max is occupied.\n";

int usage()
{
  std::cerr << kUsage;
  return 2;
}
}  // namespace

int main(int argc, char** argv)
{
  for (int i = 1; i < argc; ++i)
    if (std::string(argv[i]) == "--help" || std::string(argv[i]) == "-h")
    {
      std::cout << kUsage;
      return 0;
    }
  if (argc < 3)
    return usage();
  std::string world_file = argv[1], out = argv[2];
  double res = 0.05, zmin = 0.05, zmax = 2.0, margin = 1.0;
  for (int i = 3; i < argc; ++i)
  {
    std::string a = argv[i];
    if (i + 1 >= argc)
      return usage();
    char* end = nullptr;
    double v = std::strtod(argv[i + 1], &end);
    if (*end != '\0' || !std::isfinite(v))
    {
      std::cerr << "world_to_map: " << a << ": not a number: " << argv[i + 1] << "\n";
      return 2;
    }
    if (a == "--resolution")
      res = v;
    else if (a == "--height")
      zmin = zmax = v;
    else if (a == "--z-min")
      zmin = v;
    else if (a == "--z-max")
      zmax = v;
    else if (a == "--margin")
      margin = v;
    else
    {
      std::cerr << "world_to_map: unknown argument " << a << "\n";
      return usage();
    }
    ++i;
  }
  // One message naming the option and its value, as for a value that is not a number.
  const char* bad = !(res > 0)    ? "--resolution must be > 0"
                    : zmax < zmin ? "--z-max must be >= --z-min"
                    : margin < 0  ? "--margin must be >= 0"
                                  : nullptr;
  if (bad)
  {
    std::cerr << "world_to_map: " << bad << " (resolution " << res << ", z-min " << zmin << ", z-max " << zmax
              << ", margin " << margin << ")\n";
    return 2;
  }
  WorldSpec world;
  try
  {
    world = loadWorldFile(world_file);
  }
  catch (const std::exception& e)
  {
    std::cerr << "world_to_map: " << e.what() << "\n";
    return 1;
  }
  Slice2D all;
  for (double z = zmin;; z += 0.05)
  {
    z = std::min(z, zmax);
    Slice2D s = sliceWorld(world, z);
    all.polygons.insert(all.polygons.end(), s.polygons.begin(), s.polygons.end());
    all.circles.insert(all.circles.end(), s.circles.begin(), s.circles.end());
    all.segments.insert(all.segments.end(), s.segments.begin(), s.segments.end());
    if (z >= zmax)
      break;
  }
  if (all.empty())
  {
    std::cerr << "world_to_map: " << world_file << ": no static geometry between z=" << zmin << " and " << zmax << "\n";
    return 1;
  }
  double x0 = std::numeric_limits<double>::infinity(), y0 = x0, x1 = -x0, y1 = -x0;
  for (const auto& s : all.allSegments())
  {
    x0 = std::min({x0, s.x0, s.x1});
    x1 = std::max({x1, s.x0, s.x1});
    y0 = std::min({y0, s.y0, s.y1});
    y1 = std::max({y1, s.y0, s.y1});
  }
  for (const auto& c : all.circles)
  {
    x0 = std::min(x0, c.cx - c.r);
    x1 = std::max(x1, c.cx + c.r);
    y0 = std::min(y0, c.cy - c.r);
    y1 = std::max(y1, c.cy + c.r);
  }
  // Align the origin to the resolution so maps of one world line up.
  x0 = std::floor((x0 - margin) / res) * res;
  y0 = std::floor((y0 - margin) / res) * res;
  int w = static_cast<int>(std::ceil((x1 + margin - x0) / res));
  int h = static_cast<int>(std::ceil((y1 + margin - y0) / res));
  std::vector<uint8_t> grid;
  rasterizeSlice(all, x0, y0, res, w, h, grid);

  mybot_common::MapCells map;
  map.width = w;
  map.height = h;
  map.resolution = res;
  map.origin_x = x0;
  map.origin_y = y0;
  map.data.resize(grid.size());
  for (size_t i = 0; i < grid.size(); ++i)
    map.data[i] = grid[i] ? 100 : 0;
  // Both files or neither: a failed save leaves an existing pair as it was.
  try
  {
    mybot_common::saveMapFiles(out, map, 65, 25, "world_to_map from " + world_file);
  }
  catch (const std::exception& e)
  {
    std::cerr << "world_to_map: " << e.what() << "\n";
    return 1;
  }
  const std::string pgm = out + ".pgm", yaml = out + ".yaml";
  std::cout << "wrote " << pgm << " (" << w << "x" << h << " @ " << res << " m) and " << yaml << "\n";
  return 0;
}
