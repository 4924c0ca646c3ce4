#include "mybot_perception/depth_to_scan.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace mybot_perception
{

namespace
{
constexpr float kNaN = std::numeric_limits<float>::quiet_NaN();
constexpr float kInf = std::numeric_limits<float>::infinity();

// REP 117's preference for one beam: any valid range over +inf (no return: nothing within
// range_max) and -inf (something nearer than range_min), over NaN (no column at this bearing);
// the nearest valid wins.
float better(float old_value, float candidate)
{
  if (std::isfinite(candidate))
    return std::isfinite(old_value) ? std::min(old_value, candidate) : candidate;
  if (std::isfinite(old_value) || std::isnan(candidate))
    return old_value;
  if (std::isnan(old_value))
    return candidate;
  return std::max(old_value, candidate);  // +inf (far) over -inf (near): the beam is open
}

float classify(double r, const DepthToScanParams& p)
{
  if (r < p.range_min)
    return -kInf;
  if (r > p.range_max)
    return kInf;
  return static_cast<float>(r);
}

// The band's rows: scan_height rows centred on the optical centre's row, clipped to the image.
void bandRows(const PinholeColumns& c, const DepthToScanParams& p, int& first, int& last)
{
  first = static_cast<int>(std::lround(c.cy)) - p.scan_height / 2;
  last = first + p.scan_height - 1;
  first = std::max(first, 0);
  last = std::min(last, c.height - 1);
}

template <typename T, typename ToMetres>
PlanarScan convert(const T* depth, std::size_t stride, const PinholeColumns& c, const DepthToScanParams& p,
                   ToMetres to_metres)
{
  PlanarScan scan = emptyScan(c);
  int first = 0, last = 0;
  bandRows(c, p, first, last);
  // Per column: the range per metre of depth, hypot(u - cx, fx) / fx, and the beam whose angle
  // is nearest the column's bearing. Bearings are not evenly spaced (atan of even pixel
  // offsets): near the centre two columns may share a beam, near the edges a beam may get none
  // and stay NaN, as with depthimage_to_laserscan.
  std::vector<double> stretch(static_cast<std::size_t>(c.width));
  std::vector<std::size_t> beam_of(static_cast<std::size_t>(c.width));
  const std::size_t n = scan.ranges.size();
  for (int u = 0; u < c.width; ++u)
  {
    stretch[static_cast<std::size_t>(u)] = std::hypot(u - c.cx, c.fx) / c.fx;
    const double bearing = -std::atan2(u - c.cx, c.fx);
    const long i = std::lround((bearing - scan.angle_min) / scan.angle_increment);
    beam_of[static_cast<std::size_t>(u)] = static_cast<std::size_t>(std::clamp<long>(i, 0, static_cast<long>(n) - 1));
  }
  for (int v = first; v <= last; ++v)
  {
    const T* row = depth + static_cast<std::size_t>(v) * stride;
    for (int u = 0; u < c.width; ++u)
    {
      // No depth (NaN, 0, +inf: nothing within the camera's reach) is no return, +inf.
      const double z = to_metres(row[u]);
      const float r = std::isfinite(z) && z > 0.0 ? classify(z * stretch[static_cast<std::size_t>(u)], p) : kInf;
      float& beam = scan.ranges[beam_of[static_cast<std::size_t>(u)]];
      beam = better(beam, r);
    }
  }
  return scan;
}
}  // namespace

PinholeColumns pinholeFromFov(int width, int height, double hfov)
{
  PinholeColumns c;
  c.width = width;
  c.height = height;
  c.fx = (width / 2.0) / std::tan(hfov / 2.0);
  c.cx = (width - 1) / 2.0;
  c.cy = (height - 1) / 2.0;
  return c;
}

std::string checkDepthToScan(const PinholeColumns& c, const DepthToScanParams& p)
{
  if (c.width < 2 || c.height < 1)
    return "image of " + std::to_string(c.width) + " x " + std::to_string(c.height) + " pixels: need 2 columns or more";
  if (!(std::isfinite(c.fx) && c.fx > 0.0) || !std::isfinite(c.cx) || !std::isfinite(c.cy))
    return "camera_info K has no usable focal length or centre (fx " + std::to_string(c.fx) + ")";
  if (p.scan_height < 1 || p.scan_height > c.height)
    return "parameter scan_height (" + std::to_string(p.scan_height) + ") must be between 1 and the image height (" +
           std::to_string(c.height) + ")";
  if (!(p.range_min >= 0.0 && p.range_max > p.range_min && std::isfinite(p.range_max)))
    return "parameters range_min (" + std::to_string(p.range_min) + ") and range_max (" + std::to_string(p.range_max) +
           ") must satisfy 0 <= range_min < range_max";
  return "";
}

PlanarScan emptyScan(const PinholeColumns& c)
{
  PlanarScan s;
  // The rays through the first and last columns, as depthimage_to_laserscan measures them.
  s.angle_max = std::atan2(c.cx, c.fx);                   // column 0, to the left
  s.angle_min = -std::atan2((c.width - 1) - c.cx, c.fx);  // column width - 1, to the right
  s.angle_increment = (s.angle_max - s.angle_min) / (c.width - 1);
  s.ranges.assign(static_cast<std::size_t>(c.width), kNaN);
  return s;
}

PlanarScan depthToScan(const std::uint16_t* depth_mm, std::size_t stride, const PinholeColumns& c,
                       const DepthToScanParams& p)
{
  return convert(depth_mm, stride, c, p,
                 [](std::uint16_t d) { return d == 0 ? std::numeric_limits<double>::quiet_NaN() : d * 0.001; });
}

PlanarScan depthToScan(const float* depth_m, std::size_t stride, const PinholeColumns& c, const DepthToScanParams& p)
{
  return convert(depth_m, stride, c, p, [](float d) { return static_cast<double>(d); });
}

}  // namespace mybot_perception
