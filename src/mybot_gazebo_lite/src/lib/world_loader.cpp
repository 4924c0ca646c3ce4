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

namespace mybot_gazebo_lite
{

namespace
{
// A map_server-style YAML's fields, checked (each error names the file and the key).
struct ImageWorld
{
  std::string image;  // absolute path
  double resolution = 0.0;
  double origin_x = 0.0, origin_y = 0.0, origin_yaw = 0.0;
  double occupied_thresh = 0.65;
  bool negate = false;
  double height = 1.0;  // m, of the extruded walls
};

ImageWorld readImageWorldYaml(const std::string& yaml_path)
{
  YAML::Node y;
  try
  {
    y = YAML::LoadFile(yaml_path);
  }
  catch (const std::exception& e)
  {
    throw LoadError(yaml_path + ": YAML: " + e.what());
  }
  auto fail = [&](const std::string& key, const std::string& msg) -> void
  { throw LoadError(yaml_path + ": '" + key + "': " + msg); };
  auto num = [&](const char* key, bool required, double def)
  {
    if (!y[key])
    {
      if (required)
        fail(key, "missing");
      return def;
    }
    double v = def;
    try
    {
      v = y[key].as<double>();
    }
    catch (const std::exception&)
    {
      fail(key, "not a number");
    }
    if (!std::isfinite(v))
      fail(key, "must be finite");
    return v;
  };
  if (!y.IsMap())
    throw LoadError(yaml_path + ": expected a map_server-style YAML mapping");
  if (!y["image"])
    fail("image", "missing");
  if (!y["image"].IsScalar())
    fail("image", "expected a file name");
  ImageWorld w;
  w.image = y["image"].as<std::string>();
  if (w.image.empty() || w.image[0] != '/')
    w.image = dirOf(yaml_path) + "/" + w.image;
  w.resolution = num("resolution", true, 0);
  if (!(w.resolution > 0))
    fail("resolution", "must be positive");
  if (!y["origin"] || !y["origin"].IsSequence() || y["origin"].size() != 3)
    fail("origin", "expected [x, y, yaw]");
  try
  {
    w.origin_x = y["origin"][0].as<double>();
    w.origin_y = y["origin"][1].as<double>();
    w.origin_yaw = y["origin"][2].as<double>();
  }
  catch (const std::exception&)
  {
    fail("origin", "expected [x, y, yaw] numbers");
  }
  if (!std::isfinite(w.origin_x) || !std::isfinite(w.origin_y) || !std::isfinite(w.origin_yaw))
    fail("origin", "must be finite");
  w.occupied_thresh = num("occupied_thresh", false, 0.65);
  if (!(w.occupied_thresh > 0 && w.occupied_thresh <= 1))
    fail("occupied_thresh", "must be in (0, 1]");
  w.negate = static_cast<int>(num("negate", false, 0)) != 0;
  w.height = num("height", false, 1.0);
  if (!(w.height > 0))
    fail("height", "must be positive");
  return w;
}

cv::Mat readImageWorldImage(const std::string& yaml_path, const ImageWorld& w, long max_image_side)
{
  auto fail = [&](const std::string& msg) { throw LoadError(yaml_path + ": 'image': " + msg); };
  // The header first: a file claiming 200000 x 200000 pixels is refused before decoding.
  std::string too_large = mybot_common::declaredImageSizeError(w.image, max_image_side, "~max_image_side");
  if (!too_large.empty())
    fail(too_large);
  cv::Mat img;
  try
  {
    img = cv::imread(w.image, cv::IMREAD_GRAYSCALE);
  }
  catch (const cv::Exception& e)
  {
    fail("cannot read image '" + w.image + "': " + e.what());
  }
  if (img.empty())
    fail("cannot read image '" + w.image + "'");
  too_large = mybot_common::imageSizeError(w.image, img.cols, img.rows, max_image_side, "~max_image_side");
  if (!too_large.empty())
    fail(too_large);

  return img;
}

// Occupied cells merged into boxes: row runs, extended downwards while identical.
std::vector<Shape> mergeOccupiedCellsIntoBoxes(const cv::Mat& img, const ImageWorld& w)
{
  std::vector<Shape> boxes;
  const int W = img.cols, H = img.rows;
  auto occupied = [&](int r, int col)
  {
    double v = img.at<uint8_t>(r, col) / 255.0;
    double p = w.negate ? v : 1.0 - v;
    return p > w.occupied_thresh;
  };
  struct Run
  {
    int x0, x1, r0;
  };
  std::vector<Run> open;
  auto emit = [&](const Run& run, int r_end)
  {
    // Image row 0 is the top (largest y).
    const double res = w.resolution;
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
  walls.pose = makeTransform(btVector3(w.origin_x, w.origin_y, 0), btVector3(0, 0, w.origin_yaw));
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
