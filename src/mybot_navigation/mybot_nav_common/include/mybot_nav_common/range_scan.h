// A laser scan reduced to what mapping needs, in the robot (base) frame, plus the
// conversion from raw ranges that deals with NaN / inf / out-of-range readings.
#pragma once

#include <vector>

#include "mybot_nav_common/pose2d.h"

namespace mybot_navigation
{

struct RangeScan
{
  Point2D origin;               // sensor position in the base frame
  std::vector<Point2D> hits;    // beam end points that hit something (base frame)
  std::vector<Point2D> misses;  // end points of beams that only observed free space (base frame)
  // m from origin: no hit lies beyond it (the usable range it was converted with; 0 = unknown).
  // A map built from the scan cannot show a wall farther away, whatever is there.
  double usable_range = 0.0;
};

struct ScanConversionStats
{
  int hits = 0;
  int no_return = 0;  // +inf or >= range_max: free space up to the usable range
  int clipped = 0;    // valid but beyond max_usable_range: free space only
  int invalid = 0;    // NaN, -inf, below range_min
};

struct ScanGeometry
{
  Pose2D sensor_in_base;     // 2D pose of the sensor in the base frame
  bool upside_down = false;  // sensor z axis points down: beam angles are mirrored
};

// REP 117 semantics: NaN = invalid, +inf = no return, -inf = too close.
// A value >= range_max is treated as no return. Beams beyond max_usable_range are clipped to it
// and contribute free space only (gmapping's maxUrange).
RangeScan convertRanges(const std::vector<float>& ranges, double angle_min, double angle_increment, double range_min,
                        double range_max, double max_usable_range, const ScanGeometry& geometry,
                        ScanConversionStats* stats = nullptr);

}  // namespace mybot_navigation
