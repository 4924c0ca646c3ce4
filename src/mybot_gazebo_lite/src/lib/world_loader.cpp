// World files: a floor plan made from an occupancy image with a map_server-style YAML, and
// loadWorldFile, which takes either that or an SDF world (sdf_loader.cpp).
#include "mybot_gazebo_lite/parsing.h"

#include <opencv2/imgcodecs.hpp>
#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <sstream>

#include "mybot_common/map_yaml.h"

namespace mybot_gazebo_lite
{

namespace
{
// A floor plan: map_server's YAML (mybot_common::readMapYaml, the one reader of the format, so a
// file map_server serves the simulator loads, with the same messages when it does not) plus our
// one key, the walls' height.
struct ImageWorld
{
  mybot_common::MapYaml map;
  double height = 1.0;  // m, of the extruded walls
};

ImageWorld readImageWorldYaml(const std::string& yaml_path)
{
  ImageWorld w;
  try
  {
    w.map = mybot_common::readMapYaml(yaml_path);
  }
  catch (const mybot_common::MapFileError& e)
  {
    throw LoadError(e.what());
  }
  // The file parsed above: only `height` is left to read, and to check.
  const YAML::Node height = YAML::LoadFile(yaml_path)["height"];
  if (height)
  {
    try
    {
      w.height = height.as<double>();
    }
    catch (const YAML::Exception&)
    {
      throw LoadError(yaml_path + ": field 'height' must be a number, got \"" + height.Scalar() + "\"");
    }
    if (!(w.height > 0) || !std::isfinite(w.height))
      throw LoadError(yaml_path + ": field 'height' must be a positive number of metres, got " + height.Scalar());
  }
  return w;
}

cv::Mat readImageWorldImage(const std::string& yaml_path, const ImageWorld& w, long max_image_side)
{
  auto fail = [&](const std::string& msg) { throw LoadError(yaml_path + ": field 'image': " + msg); };
  // The header first: a file claiming 200000 x 200000 pixels is refused before decoding.
  std::string too_large = mybot_common::declaredImageSizeError(w.map.image, max_image_side, "~max_image_side");
  if (!too_large.empty())
    fail(too_large);
  cv::Mat img;
  try
  {
    img = cv::imread(w.map.image, cv::IMREAD_UNCHANGED);  // as map_server: every channel counts
  }
  catch (const cv::Exception& e)
  {
    fail("cannot read image '" + w.map.image + "': " + e.what());
  }
  if (img.empty())
    fail("cannot read image '" + w.map.image + "'");
  too_large = mybot_common::imageSizeError(w.map.image, img.cols, img.rows, max_image_side, "~max_image_side");
  if (!too_large.empty())
    fail(too_large);
  if (img.depth() != CV_8U)
    fail("image '" + w.map.image + "' is not 8 bits per channel");
  return img;
}

// Occupied cells merged into boxes: row runs, extended downwards while identical.
std::vector<Shape> mergeOccupiedCellsIntoBoxes(const cv::Mat& img, const ImageWorld& w)
{
  std::vector<Shape> boxes;
  const int W = img.cols, H = img.rows;
  const int channels = img.channels();
  // A wall where map_server serves an occupied cell (in raw mode: a pixel mean of 100).
  auto occupied = [&](int r, int col)
  { return mybot_common::mapCellValue(w.map, img.ptr<uint8_t>(r) + col * channels, channels) == 100; };
  struct Run
  {
    int x0, x1, r0;
  };
  std::vector<Run> open;
  auto emit = [&](const Run& run, int r_end)
  {
    // Image row 0 is the top (largest y).
    const double res = w.map.resolution;
    double x0 = run.x0 * res, x1 = (run.x1 + 1) * res;
    double ytop = (H - run.r0) * res, ybot = (H - r_end) * res;
    Shape s;
    s.type = Shape::BOX;
    s.size = btVector3(x1 - x0, ytop - ybot, w.height);
    s.pose.setIdentity();
    s.pose.setOrigin(btVector3((x0 + x1) / 2, (ytop + ybot) / 2, w.height / 2));
    boxes.push_back(s);
  };
  for (int r = 0; r <= H; ++r)
  {
    std::vector<Run> runs;
    if (r < H)
    {
      for (int col = 0; col < W;)
      {
        if (!occupied(r, col))
        {
          ++col;
          continue;
        }
        int s = col;
        while (col < W && occupied(r, col))
          ++col;
        runs.push_back({s, col - 1, r});
      }
    }
    std::vector<Run> next;
    for (auto& o : open)
    {
      bool cont = false;
      for (auto& n : runs)
        if (n.x0 == o.x0 && n.x1 == o.x1 && n.r0 == r)
        {
          n.r0 = o.r0;
          cont = true;
        }
      if (!cont)
        emit(o, r);
    }
    open = runs;
  }
  return boxes;
}
}  // namespace

WorldSpec loadImageWorld(const std::string& yaml_path, long max_image_side)
{
  const ImageWorld w = readImageWorldYaml(yaml_path);
  const cv::Mat img = readImageWorldImage(yaml_path, w, max_image_side);
  WorldSpec world;
  world.source = yaml_path;
  world.name = "floor_plan";
  world.ground_plane = true;
  WorldModel walls;
  walls.name = "floor_plan_walls";
  walls.is_static = true;
  walls.pose = makeTransform(btVector3(w.map.origin_x, w.map.origin_y, 0), btVector3(0, 0, w.map.origin_yaw));
  WorldLink link;
  link.name = "walls";
  link.shapes = mergeOccupiedCellsIntoBoxes(img, w);
  if (!link.shapes.empty())
    walls.links.push_back(std::move(link));
  world.models.push_back(std::move(walls));
  return world;
}

WorldSpec loadWorldFile(const std::string& path, const UriResolver& resolver, long max_image_side)
{
  auto ends = [&](const std::string& s)
  { return path.size() >= s.size() && path.compare(path.size() - s.size(), s.size(), s) == 0; };
  if (ends(".yaml") || ends(".yml"))
    return loadImageWorld(path, max_image_side);
  std::string xml = readFile(path, "world");
  return parseSdfWorld(xml, path, dirOf(path), resolver);
}

}  // namespace mybot_gazebo_lite
