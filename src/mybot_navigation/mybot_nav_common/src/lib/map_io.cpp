#include "mybot_nav_common/map_io.h"

#include <cstdio>

#include <opencv2/imgcodecs.hpp>

#include "mybot_common/image_header.h"
#include "mybot_common/map_file.h"

namespace mybot_navigation
{
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
  info.origin = {meta.origin_x, meta.origin_y, meta.origin_yaw};
  GridMap map(info, GridMap::kUnknown);
  const int channels = img.channels();
  for (int j = 0; j < img.rows; ++j)
  {
    const uint8_t* row = img.ptr<uint8_t>(j);
    // Image rows run top-down, the grid bottom-up.
    for (int i = 0; i < img.cols; ++i)
      map.at(i, img.rows - j - 1) = mybot_common::mapCellValue(meta, row + i * channels, channels);
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
