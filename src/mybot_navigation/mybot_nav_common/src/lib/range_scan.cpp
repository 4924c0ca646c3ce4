#include "mybot_nav_common/range_scan.h"

#include <cmath>

namespace mybot_navigation
{

RangeScan convertRanges(const std::vector<float>& ranges, double angle_min, double angle_increment, double range_min,
                        double range_max, double max_usable_range, const ScanGeometry& geometry,
                        ScanConversionStats* stats)
{
  ScanConversionStats local;
  ScanConversionStats& st = stats ? *stats : local;
  st = ScanConversionStats{};
  RangeScan scan;
  scan.origin = {geometry.sensor_in_base.x, geometry.sensor_in_base.y};
  scan.hits.reserve(ranges.size());
  const double usable = std::min(range_max, max_usable_range);
  scan.usable_range = usable;
  const double dir = geometry.upside_down ? -1.0 : 1.0;
  for (size_t i = 0; i < ranges.size(); ++i)
  {
    const double r = ranges[i];
    const double a = geometry.sensor_in_base.theta + dir * (angle_min + angle_increment * static_cast<double>(i));
    const double c = std::cos(a), s = std::sin(a);
    if (std::isnan(r) || r < range_min || (std::isinf(r) && r < 0))
    {
      ++st.invalid;
      continue;
    }
    if (std::isinf(r) || r >= range_max)
    {
      ++st.no_return;
      scan.misses.push_back({scan.origin.x + c * usable, scan.origin.y + s * usable});
      continue;
    }
    if (r > max_usable_range)
    {
      ++st.clipped;
      scan.misses.push_back({scan.origin.x + c * usable, scan.origin.y + s * usable});
      continue;
    }
    ++st.hits;
    scan.hits.push_back({scan.origin.x + c * r, scan.origin.y + s * r});
  }
  return scan;
}

}  // namespace mybot_navigation
