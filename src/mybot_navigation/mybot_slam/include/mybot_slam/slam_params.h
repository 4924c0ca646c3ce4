// The SLAM parameters by name (gmapping's where it has one: delta, linearUpdate, angularUpdate,
// temporalUpdate, occ_thresh, maxUrange, maxRange), with their checks: one table read by slam_node
// (ROS parameters) and slam_replay (a YAML file), so both run the same Slam the same way. No ROS.
#pragma once

#include <functional>
#include <string>
#include <vector>

#include "mybot_slam/slam.h"

namespace mybot_navigation
{

// What a run needs besides SlamParams: how scans are cut before matching.
struct SlamRunParams
{
  SlamParams slam;
  double max_urange = 80.0;  // m: longer readings are cut here (gmapping maxUrange)
  double max_range = 0.0;    // m: readings at or beyond are no returns; 0 = the scan's range_max
};

struct SlamParamSpec
{
  enum class Type
  {
    Number,
    Integer,
    Boolean
  };
  const char* name;
  Type type;
  std::function<double&(SlamRunParams&)> field_double;  // Number
  std::function<int&(SlamRunParams&)> field_int;        // Integer
  std::function<bool&(SlamRunParams&)> field_bool;      // Boolean
  std::function<bool(double)> ok;
  const char* requirement;  // "a positive cell size (m)"
};

const std::vector<SlamParamSpec>& slamParamSpecs();

// The rules across parameters; "" or a message naming them.
std::string checkSlamRunParams(const SlamRunParams& p);

}  // namespace mybot_navigation
