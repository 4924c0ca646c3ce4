#include "mybot_nav_common/map_io.h"

#include <cmath>
#include <cstdio>
#include <fstream>
#include <type_traits>

#include <opencv2/imgcodecs.hpp>
#include <yaml-cpp/yaml.h>

#include "mybot_common/image_header.h"
#include "mybot_common/map_file.h"

namespace mybot_navigation
{
namespace
{
std::string dirName(const std::string& path)
{
  const auto slash = path.find_last_of('/');
  return slash == std::string::npos ? std::string(".") : path.substr(0, slash == 0 ? 1 : slash);
}

template <typename T>
T required(const YAML::Node& doc, const std::string& key, const std::string& file)
{
  const YAML::Node n = doc[key];
  if (!n)
    throw MapIoError(file + ": the map does not contain a '" + key + "' field");
  const char* expected = std::is_same_v<T, std::string> ? "a string"
                         : std::is_integral_v<T>        ? "an integer"
                                                        : "a number";
  if (!n.IsScalar())
    throw MapIoError(file + ": field '" + key + "' must be " + expected);
  try
  {
    const T v = n.as<T>();
    if constexpr (std::is_floating_point_v<T>)
      if (!std::isfinite(v))
        throw MapIoError(file + ": field '" + key + "' must be a finite number, got " + n.Scalar());
    return v;
  }
  catch (const YAML::Exception&)
  {
    throw MapIoError(file + ": field '" + key + "' must be " + expected + ", got \"" + n.Scalar() + "\"");
  }
}
}  // namespace

MapYaml readMapYaml(const std::string& yaml_path)
{
  std::ifstream in(yaml_path);
  if (!in)
    throw MapIoError(yaml_path + ": cannot open map YAML file");
  YAML::Node doc;
  try
  {
    doc = YAML::Load(in);
  }
  catch (const YAML::Exception& e)
  {
    throw MapIoError(yaml_path + ": not valid YAML: " + e.what());
  }
  if (!doc.IsMap())
    throw MapIoError(yaml_path + ": not a YAML mapping");
  MapYaml m;
  m.resolution = required<double>(doc, "resolution", yaml_path);
  if (!(m.resolution > 0.0) || !std::isfinite(m.resolution))
    throw MapIoError(yaml_path + ": field 'resolution' must be a positive number");
  m.negate = required<int>(doc, "negate", yaml_path) != 0;
  m.occupied_thresh = required<double>(doc, "occupied_thresh", yaml_path);
  m.free_thresh = required<double>(doc, "free_thresh", yaml_path);
  // Probabilities, free below occupied; otherwise a wall can vanish from the served map.
  if (m.occupied_thresh < 0.0 || m.occupied_thresh > 1.0)
    throw MapIoError(yaml_path + ": field 'occupied_thresh' must be in [0, 1], got " +
                     std::to_string(m.occupied_thresh));
  if (m.free_thresh < 0.0 || m.free_thresh > 1.0)
    throw MapIoError(yaml_path + ": field 'free_thresh' must be in [0, 1], got " + std::to_string(m.free_thresh));
  if (m.free_thresh >= m.occupied_thresh)
    throw MapIoError(yaml_path + ": field 'free_thresh' (" + std::to_string(m.free_thresh) +
                     ") must be smaller than 'occupied_thresh' (" + std::to_string(m.occupied_thresh) + ")");
  if (doc["mode"])
  {
    const std::string mode = required<std::string>(doc, "mode", yaml_path);
    if (mode == "trinary")
      m.mode = MapMode::Trinary;
    else if (mode == "scale")
      m.mode = MapMode::Scale;
    else if (mode == "raw")
      m.mode = MapMode::Raw;
    else
      throw MapIoError(yaml_path + ": field 'mode' has invalid value \"" + mode + "\" (trinary, scale or raw)");
  }
  const YAML::Node origin = doc["origin"];
  if (!origin)
    throw MapIoError(yaml_path + ": the map does not contain a 'origin' field");
  if (!origin.IsSequence() || origin.size() != 3)
    throw MapIoError(yaml_path + ": field 'origin' must be [x, y, yaw]");
  try
  {
    m.origin = {origin[0].as<double>(), origin[1].as<double>(), origin[2].as<double>()};
  }
  catch (const YAML::Exception&)
  {
    throw MapIoError(yaml_path + ": field 'origin' must be [x, y, yaw] numbers");
  }
  if (!std::isfinite(m.origin.x) || !std::isfinite(m.origin.y) || !std::isfinite(m.origin.theta))
    throw MapIoError(yaml_path + ": field 'origin' must be finite, got [" + origin[0].Scalar() + ", " +
                     origin[1].Scalar() + ", " + origin[2].Scalar() + "]");
  m.image = required<std::string>(doc, "image", yaml_path);
  if (m.image.empty())
    throw MapIoError(yaml_path + ": field 'image' cannot be an empty string");
  if (m.image[0] != '/')
    m.image = dirName(yaml_path) + "/" + m.image;
  return m;
}

GridMap loadMapImage(const MapYaml& meta, long max_side)
{
  // The header first: a file claiming 200000 x 200000 pixels is refused before decoding.
  std::string too_large = mybot_common::declaredImageSizeError(meta.image, max_side, "~max_image_side");
  if (!too_large.empty())
    throw MapIoError(too_large);
  cv::Mat img;
  try
  {
    img = cv::imread(meta.image, cv::IMREAD_UNCHANGED);
  }
  catch (const cv::Exception& e)
  {
    throw MapIoError("failed to read image file \"" + meta.image + "\" (field 'image'): " + e.what());
  }
  if (img.empty())
    throw MapIoError("failed to open image file \"" + meta.image + "\" (field 'image')");
  too_large = mybot_common::imageSizeError(meta.image, img.cols, img.rows, max_side, "~max_image_side");
  if (!too_large.empty())
    throw MapIoError(too_large);
  if (img.depth() != CV_8U)
    throw MapIoError("image file \"" + meta.image + "\" is not 8 bits per channel");
  MapInfo info;
  info.resolution = meta.resolution;
  info.width = img.cols;
  info.height = img.rows;
  info.origin = meta.origin;
  GridMap map(info, GridMap::kUnknown);
  const int channels = img.channels();
  const bool has_alpha = channels == 4 || channels == 2;
  // Like map_server: in trinary mode alpha is averaged with the colours.
  const int avg_channels = (meta.mode == MapMode::Trinary || !has_alpha) ? channels : channels - 1;
  for (int j = 0; j < img.rows; ++j)
  {
    const uint8_t* row = img.ptr<uint8_t>(j);
    for (int i = 0; i < img.cols; ++i)
    {
      const uint8_t* p = row + i * channels;
      int sum = 0;
      for (int k = 0; k < avg_channels; ++k)
        sum += p[k];
      double color_avg = sum / static_cast<double>(avg_channels);
      const int alpha = channels == 1 ? 1 : p[channels - 1];
      if (meta.negate)
        color_avg = 255 - color_avg;
      unsigned char value;
      if (meta.mode == MapMode::Raw)
      {
        value = static_cast<unsigned char>(color_avg);
      }
      else
      {
        const double occ = (255 - color_avg) / 255.0;
        if (occ > meta.occupied_thresh)
          value = 100;
        else if (occ < meta.free_thresh)
          value = 0;
        else if (meta.mode == MapMode::Trinary || alpha < 1.0)
          value = static_cast<unsigned char>(-1);
        else
          value =
              static_cast<unsigned char>(1 + 98 * (occ - meta.free_thresh) / (meta.occupied_thresh - meta.free_thresh));
      }
      // Image rows run top-down, the grid bottom-up.
      map.at(i, img.rows - j - 1) = static_cast<int8_t>(value);
    }
  }
  return map;
}

GridMap loadMap(const std::string& yaml_path, long max_side)
{
  return loadMapImage(readMapYaml(yaml_path), max_side);
}

void saveMap(const GridMap& map, const std::string& basename, int occ, int free)
{
  mybot_common::MapCells cells;
  cells.width = map.info.width;
  cells.height = map.info.height;
  cells.resolution = map.info.resolution;
  cells.origin_x = map.info.origin.x;
  cells.origin_y = map.info.origin.y;
  cells.origin_yaw = map.info.origin.theta;
  cells.data = map.data;
  try
  {
    mybot_common::saveMapFiles(basename, cells, occ, free);
  }
  catch (const std::exception& e)
  {
    throw MapIoError(e.what());
  }
}

}  // namespace mybot_navigation
