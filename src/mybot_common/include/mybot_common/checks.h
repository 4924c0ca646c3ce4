// Checks of numbers that come from outside (service requests, topics, files) before they enter
// running state: one NaN in a pose spreads to every transform computed from it. No ROS.
#pragma once

#include <cstddef>
#include <initializer_list>
#include <limits>
#include <string>

namespace mybot_common
{

struct NamedValue
{
  const char* name;  // as the user knows it: "initial_pose.position.x"
  double value;
};

// The first value that is not finite or whose magnitude exceeds `limit`, described for a
// message ("initial_pose.position.x is nan", "pose.position.y is 1e+30, beyond +-1e+06"), or ""
// when every value is fine.
std::string firstInvalid(std::initializer_list<NamedValue> values,
                         double limit = std::numeric_limits<double>::infinity());

// A number as a message shows it (printf's %g): "0.003", "4", "1e+30".
std::string formatNumber(double v);

// A LaserScan's own geometry (REP 117 / sensor_msgs): finite angles, a non-zero increment with
// the sign of angle_max - angle_min, and round((angle_max - angle_min) / angle_increment) + 1
// ranges, or one fewer: an angle_max at the end of the sweep, one increment past the last beam,
// as 5169 of the 6917 scans of the Freiburg hospital log have it (beam i is still at angle_min +
// i angle_increment, as every consumer draws it). "" if it holds, else a message with both numbers
// ("has 100 ranges where its angles (angle_min -1.5708, angle_max 1.5708, angle_increment 0.00873)
// make 361"): a scan that contradicts itself would be drawn into maps and costmaps at the wrong
// bearings.
std::string scanGeometryError(double angle_min, double angle_max, double angle_increment, std::size_t ranges);

// A LaserScan's range limits: range_min finite and >= 0, range_max above it (+inf: no limit). "" if
// they hold, else a message naming the field ("has range_max nan ..."). A NaN range_max put every
// no-return reading's free space at NaN metres, into the map and the costmap; a negative range_min
// let a negative range through as a wall behind the laser.
std::string scanRangeError(double range_min, double range_max);

// Both: what makes a scan usable, for every node and tool that takes scans ("" if it is).
std::string scanError(double angle_min, double angle_max, double angle_increment, std::size_t ranges, double range_min,
                      double range_max);

}  // namespace mybot_common
