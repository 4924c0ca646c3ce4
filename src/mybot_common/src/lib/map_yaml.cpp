#include "mybot_common/map_yaml.h"

#include <cmath>
#include <fstream>
#include <type_traits>

#include <yaml-cpp/yaml.h>

namespace mybot_common
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
    throw MapFileError(file + ": the map does not contain a '" + key + "' field");
  const char* expected = std::is_same_v<T, std::string> ? "a string"
                         : std::is_integral_v<T>        ? "an integer"
                                                        : "a number";
  if (!n.IsScalar())
    throw MapFileError(file + ": field '" + key + "' must be " + expected);
  try
  {
    const T v = n.as<T>();
    if constexpr (std::is_floating_point_v<T>)
      if (!std::isfinite(v))
        throw MapFileError(file + ": field '" + key + "' must be a finite number, got " + n.Scalar());
    return v;
  }
  catch (const YAML::Exception&)
  {
    throw MapFileError(file + ": field '" + key + "' must be " + expected + ", got \"" + n.Scalar() + "\"");
  }
}
}  // namespace

MapYaml readMapYaml(const std::string& yaml_path)
{
  std::ifstream in(yaml_path);
  if (!in)
    throw MapFileError(yaml_path + ": cannot open map YAML file");
  YAML::Node doc;
  try
  {
    doc = YAML::Load(in);
  }
  catch (const YAML::Exception& e)
  {
    throw MapFileError(yaml_path + ": not valid YAML: " + e.what());
  }
  if (!doc.IsMap())
    throw MapFileError(yaml_path + ": not a YAML mapping");
  MapYaml m;
  m.resolution = required<double>(doc, "resolution", yaml_path);
  if (!(m.resolution > 0.0))
    throw MapFileError(yaml_path + ": field 'resolution' must be a positive number");
  m.negate = required<int>(doc, "negate", yaml_path) != 0;
  m.occupied_thresh = required<double>(doc, "occupied_thresh", yaml_path);
  m.free_thresh = required<double>(doc, "free_thresh", yaml_path);
  // Probabilities, free below occupied; otherwise a wall can vanish from the map.
  if (m.occupied_thresh < 0.0 || m.occupied_thresh > 1.0)
    throw MapFileError(yaml_path + ": field 'occupied_thresh' must be in [0, 1], got " +
                       std::to_string(m.occupied_thresh));
  if (m.free_thresh < 0.0 || m.free_thresh > 1.0)
    throw MapFileError(yaml_path + ": field 'free_thresh' must be in [0, 1], got " + std::to_string(m.free_thresh));
  if (m.free_thresh >= m.occupied_thresh)
    throw MapFileError(yaml_path + ": field 'free_thresh' (" + std::to_string(m.free_thresh) +
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
      throw MapFileError(yaml_path + ": field 'mode' has invalid value \"" + mode + "\" (trinary, scale or raw)");
  }
  const YAML::Node origin = doc["origin"];
  if (!origin)
    throw MapFileError(yaml_path + ": the map does not contain a 'origin' field");
  if (!origin.IsSequence() || origin.size() != 3)
    throw MapFileError(yaml_path + ": field 'origin' must be [x, y, yaw]");
  try
  {
    m.origin_x = origin[0].as<double>();
    m.origin_y = origin[1].as<double>();
    m.origin_yaw = origin[2].as<double>();
  }
  catch (const YAML::Exception&)
  {
    throw MapFileError(yaml_path + ": field 'origin' must be [x, y, yaw] numbers");
  }
  if (!std::isfinite(m.origin_x) || !std::isfinite(m.origin_y) || !std::isfinite(m.origin_yaw))
    throw MapFileError(yaml_path + ": field 'origin' must be finite, got [" + origin[0].Scalar() + ", " +
                       origin[1].Scalar() + ", " + origin[2].Scalar() + "]");
  m.image = required<std::string>(doc, "image", yaml_path);
  if (m.image.empty())
    throw MapFileError(yaml_path + ": field 'image' cannot be an empty string");
  if (m.image[0] != '/')
    m.image = dirName(yaml_path) + "/" + m.image;
  return m;
}

std::int8_t mapCellValue(const MapYaml& meta, const std::uint8_t* pixel, int channels)
{
  const bool has_alpha = channels == 4 || channels == 2;
  // As image_loader: in trinary mode the alpha is averaged with the colours.
  const int avg_channels = (meta.mode == MapMode::Trinary || !has_alpha) ? channels : channels - 1;
  int sum = 0;
  for (int k = 0; k < avg_channels; ++k)
    sum += pixel[k];
  double color_avg = sum / static_cast<double>(avg_channels);
  const int alpha = channels == 1 ? 1 : pixel[channels - 1];
  if (meta.negate)
    color_avg = 255 - color_avg;
  if (meta.mode == MapMode::Raw)
    return static_cast<std::int8_t>(static_cast<unsigned char>(color_avg));
  const double occ = (255 - color_avg) / 255.0;
  if (occ > meta.occupied_thresh)
    return 100;
  if (occ < meta.free_thresh)
    return 0;
  if (meta.mode == MapMode::Trinary || alpha < 1.0)
    return -1;
  return static_cast<std::int8_t>(1 + 98 * (occ - meta.free_thresh) / (meta.occupied_thresh - meta.free_thresh));
}

}  // namespace mybot_common
