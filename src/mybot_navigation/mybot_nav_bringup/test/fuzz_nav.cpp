// Mutation fuzzing of what the navigation nodes do with a LaserScan and the odometry around it
// (scripts/fuzz --only scan runs it; built with AddressSanitizer and UBSan, the libraries of
// mybot_nav_common, mybot_amcl, mybot_move_base and mybot_slam compiled again with it; not a gate
// test: what it finds depends on its seed and its time, and what it found becomes a gtest).
//
//   fuzz_nav scan SECONDS SEED OUT_DIR INPUT...     (SECONDS 0: each input once, the replay)
//
// An input is a scan as text (test/fuzz_seeds/*.scan: real scans of the Freiburg logs): the
// LaserScan's fields, `pose`, where the robot stands in factory_truth's map, `goal`, where
// move_base is sent (optional), and `step`, its odometry between scans. Each round mutates one input
// (mybot_common/fuzz.h) and, unless the nodes' check drops it (mybot_common::scanError, as slam_node, amcl and
// move_base do), gives it three times, the robot moving by `step` each time, to what each node does with it:
//  - amcl: amcl_node's conversion (laserScanData) and the filter's update, from an initial pose;
//  - move_base: scanEndPoints into a global costmap on the map and a rolling local one, and the
//    navigator's step towards the goal (planner, controller, recoveries);
//  - slam_node: convertRanges and Slam::addScan.
// What it checks: no crash, no sanitizer report, no hang (20 s a round: current.scan stays for
// scripts/fuzz to keep), and that the estimates and the velocity command stay finite (else
// OUT_DIR/nonfinite-N.scan).

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <random>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#include "mybot_amcl/amcl.h"
#include "mybot_common/checks.h"
#include "mybot_common/fuzz.h"
#include "mybot_move_base/costmap.h"
#include "mybot_move_base/navigator.h"
#include "mybot_nav_common/map_io.h"
#include "mybot_nav_common/range_scan.h"
#include "mybot_nav_common/ros/node_params.h"
#include "mybot_slam/slam.h"

using namespace mybot_navigation;

namespace
{
struct ScanInput
{
  sensor_msgs::LaserScan scan;
  Pose2D pose, step;
  Pose2D goal{6.0, 3.0, 0.0};
};

// strtod's numbers, so that nan, inf and 1e400 (inf) read as a message's float would hold them.
std::vector<double> numbers(const std::string& text, const std::string& key)
{
  std::vector<double> out;
  std::string s = text;
  for (char& c : s)
    if (c == '[' || c == ']' || c == ',')
      c = ' ';
  std::istringstream in(s);
  for (std::string word; in >> word;)
  {
    char* end = nullptr;
    out.push_back(std::strtod(word.c_str(), &end));
    if (end != word.c_str() + word.size())
      throw std::invalid_argument("'" + key + "': not a number: " + word);
  }
  return out;
}

ScanInput parse(const std::string& text)
{
  ScanInput in;
  int fields = 0;
  std::istringstream lines(text);
  for (std::string line; std::getline(lines, line);)
  {
    if (line.empty() || line[0] == '#')
      continue;
    const auto colon = line.find(':');
    if (colon == std::string::npos)
      throw std::invalid_argument("no 'key: value' line: " + line.substr(0, 40));
    const std::string key = line.substr(0, colon);
    const std::vector<double> v = numbers(line.substr(colon + 1), key);
    auto one = [&]() -> float
    {
      if (v.size() != 1)
        throw std::invalid_argument("'" + key + "': one number expected");
      return static_cast<float>(v[0]);
    };
    auto pose = [&]() -> Pose2D
    {
      if (v.size() != 3)
        throw std::invalid_argument("'" + key + "': [x, y, theta] expected");
      return {v[0], v[1], v[2]};
    };
    if (key == "angle_min")
      in.scan.angle_min = one();
    else if (key == "angle_max")
      in.scan.angle_max = one();
    else if (key == "angle_increment")
      in.scan.angle_increment = one();
    else if (key == "range_min")
      in.scan.range_min = one();
    else if (key == "range_max")
      in.scan.range_max = one();
    else if (key == "ranges")
      in.scan.ranges.assign(v.begin(), v.end());
    else if (key == "pose")
      in.pose = pose();
    else if (key == "step")
      in.step = pose();
    else if (key == "goal")
    {
      in.goal = pose();
      --fields;  // optional
    }
    else
      throw std::invalid_argument("unknown key '" + key + "'");
    ++fields;
  }
  if (fields < 8)
    throw std::invalid_argument("a field is missing");
  // What tf2 would refuse to carry (a NaN transform) never reaches the nodes.
  for (double x : {in.pose.x, in.pose.y, in.pose.theta, in.step.x, in.step.y, in.step.theta})
    if (!std::isfinite(x))
      throw std::invalid_argument("a pose tf2 would refuse");
  return in;
}

bool finite(const Pose2D& p)
{
  return std::isfinite(p.x) && std::isfinite(p.y) && std::isfinite(p.theta);
}

class Nodes
{
public:
  explicit Nodes(const GridMap& map) : map_(map)
  {
    amcl_params_.filter.min_particles = 100;  // the default 500 / 5000 cost the fuzzer rounds, not paths
    amcl_params_.filter.max_particles = 500;
    local_params_.rolling_window = true;
    local_params_.use_static_map = false;
    slam_params_.linear_update = slam_params_.angular_update = 0.25;  // config/slam.yaml's: each step a keyframe
  }

  // Whether every estimate stayed finite; a refusal goes to `refusal`.
  bool run(const ScanInput& in, std::string* refusal)
  {
    const sensor_msgs::LaserScan& scan = in.scan;
    const std::string error = mybot_common::scanError(scan.angle_min, scan.angle_max, scan.angle_increment,
                                                      scan.ranges.size(), scan.range_min, scan.range_max);
    if (!error.empty() || scan.ranges.empty())
    {
      if (refusal)
        *refusal = "dropped by the nodes: " + (error.empty() ? std::string("no ranges") : error);
      return true;
    }
    Amcl amcl(amcl_params_);
    amcl.setMap(map_);
    amcl.setInitialPose(in.pose, 0.25, 0.25, 0.07);
    Costmap global(global_params_), local(local_params_);
    global.setStaticMap(map_);
    GlobalPlanner planner;
    LocalPlanner controller;
    Navigator navigator(NavigatorParams{}, global, local, planner, controller);
    navigator.setGoal(in.goal, 100.0, in.pose);
    Slam slam(slam_params_);
    const Pose2D odom0{1.0, -2.0, 0.5};  // the odometry frame is not the map's
    Pose2D pose = in.pose, odom = odom0;
    bool ok = true;
    for (int k = 0; k < 3; ++k)
    {
      amcl.processScan(odom, laserScanData(scan.ranges, scan.angle_min, scan.angle_increment, scan.range_min,
                                           scan.range_max, -1.0, -1.0, {}, false));
      for (Costmap* cm : {&global, &local})
      {
        std::vector<Point2D> hits, ends;
        scanEndPoints(scan, pose, false, cm->params().raytrace_range, hits, ends, true);
        if (cm == &local)
          cm->updateOrigin(pose.x, pose.y);
        cm->updateWithScan({pose.x, pose.y}, hits, ends);
        cm->updateCosts();
      }
      const Velocity2D cmd = navigator.step(100.0 + 0.5 * k, pose, {}).cmd;
      const double stamp = 100.0 + 0.5 * k;
      if (slam.wantsScan(stamp, odom))
        slam.addScan(stamp, odom,
                     convertRanges(scan.ranges, scan.angle_min, scan.angle_increment, scan.range_min, scan.range_max,
                                   30.0, ScanGeometry{}));
      else
        slam.updateOdometry(odom);
      ok = ok && std::isfinite(cmd.vx) && std::isfinite(cmd.vy) && std::isfinite(cmd.wz) &&
           finite(slam.currentPose()) && finite(slam.mapToOdom()) &&
           (!amcl.hasEstimate() || (finite(amcl.estimate().mean) && finite(amcl.mapToOdom())));
      pose = compose(pose, in.step);
      odom = compose(odom, in.step);
    }
    summary_ = "amcl " + std::to_string(amcl.updates()) + " updates, slam " + std::to_string(slam.keyframes().size()) +
               " keyframes, move_base " + toString(navigator.state()) +
               (navigator.abortReason().empty() ? "" : " (" + navigator.abortReason() + ")");
    if (!ok)
      std::fprintf(stderr, "  an estimate or the command is not finite: slam (%g, %g, %g), amcl (%g, %g, %g)\n",
                   slam.currentPose().x, slam.currentPose().y, slam.currentPose().theta, amcl.estimate().mean.x,
                   amcl.estimate().mean.y, amcl.estimate().mean.theta);
    return ok;
  }

  // What the last run did, for the replay's log.
  const std::string& summary() const { return summary_; }

private:
  const GridMap& map_;
  std::string summary_;
  AmclParams amcl_params_;
  CostmapParams global_params_, local_params_;
  SlamParams slam_params_;
};
}  // namespace

int main(int argc, char** argv)
{
  if (argc < 6 || std::string(argv[1]) != "scan")
  {
    std::fprintf(stderr, "usage: fuzz_nav scan SECONDS SEED OUT_DIR INPUT...\n");
    return 2;
  }
  const GridMap map = loadMap(FACTORY_MAP);
  Nodes nodes(map);
  return mybot_common::fuzz::drive("scan", std::atof(argv[2]), static_cast<unsigned>(std::atol(argv[3])), argv[4],
                                   mybot_common::fuzz::readInputs(argc, argv, 5),
                                   [&](const std::string& text, const std::string&)
                                   {
                                     mybot_common::fuzz::Outcome o;
                                     try
                                     {
                                       o.finite = nodes.run(parse(text), &o.what);
                                     }
                                     catch (const std::invalid_argument& e)  // not a scan a node could receive
                                     {
                                       o.what = std::string("not a scan: ") + e.what();
                                     }
                                     o.taken = o.what.empty();
                                     if (o.taken)
                                       o.what = "taken: " + nodes.summary();
                                     return o;
                                   });
}
