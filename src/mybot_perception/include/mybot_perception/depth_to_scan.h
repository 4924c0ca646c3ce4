// One band of a depth image turned into a planar laser scan, as depthimage_to_laserscan does:
// per image column, the nearest valid depth among the band's rows, converted to the range along
// the horizontal ray through that column (not the raw depth, which is the distance to the image
// plane), in a LaserScan's angular order. No ROS.
//
// Geometry. A pinhole camera (fx, cx from camera_info's K) sees column u along the ray
// (x, z) = ((u - cx) / fx, 1) in its optical frame (x right, z forward). A point at depth z
// in column u lies x = (u - cx) z / fx to the side, so its range in the scan plane is
// hypot(x, z), at the bearing -atan2(u - cx, fx): positive to the left, as a LaserScan counts
// counter-clockwise. Column width - 1 is therefore angle_min, column 0 angle_max; in between,
// each column goes to the beam nearest its bearing.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

namespace mybot_perception
{

struct PinholeColumns
{
  int width = 0, height = 0;
  double fx = 0.0, cx = 0.0;  // K[0], K[2] (pixels)
  double cy = 0.0;            // K[5]: the band is centred on the optical centre's row
};

// A centred pinhole camera of horizontal field of view hfov (rad), as Gazebo makes one.
PinholeColumns pinholeFromFov(int width, int height, double hfov);

struct DepthToScanParams
{
  int scan_height = 1;      // rows of the band, centred on cy
  double range_min = 0.45;  // m (depthimage_to_laserscan's defaults)
  double range_max = 10.0;  // m
};

struct PlanarScan
{
  double angle_min = 0.0, angle_max = 0.0, angle_increment = 0.0;
  // REP 117: a valid range, else +inf (no return: NaN or 0 depth, or only returns beyond
  // range_max), -inf (only returns nearer than range_min), NaN (no image column at this bearing).
  std::vector<float> ranges;
};

// "" if the camera and parameters make a scan, else a message naming the field or parameter.
std::string checkDepthToScan(const PinholeColumns& camera, const DepthToScanParams& params);

// The scan's angles for this camera (ranges sized, all NaN).
PlanarScan emptyScan(const PinholeColumns& camera);

// depth: the image's rows, `row_stride` elements apart; 16UC1 in millimetres or 32FC1 in metres.
// Call checkDepthToScan first.
PlanarScan depthToScan(const std::uint16_t* depth_mm, std::size_t row_stride, const PinholeColumns& camera,
                       const DepthToScanParams& params);
PlanarScan depthToScan(const float* depth_m, std::size_t row_stride, const PinholeColumns& camera,
                       const DepthToScanParams& params);

}  // namespace mybot_perception
