#include "mybot_slam/ros/bag_replay.h"

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <map>
#include <memory>
#include <new>
#include <stdexcept>

#include <nav_msgs/Odometry.h>
#include <rosbag/bag.h>
#include <rosbag/view.h>
#include <sensor_msgs/LaserScan.h>
#include <tf2/buffer_core.h>
#include <tf2/exceptions.h>
#include <tf2_msgs/TFMessage.h>
#include <yaml-cpp/yaml.h>

#include "mybot_common/checks.h"
#include "mybot_nav_common/range_scan.h"
#include "mybot_nav_common/ros/conversions.h"

namespace mybot_navigation
{

namespace
{
struct ScanRecord
{
  double stamp;
  Pose2D odom;
  int keyframe;                 // the keyframe current after this scan (-1 before the first)
  Pose2D in_keyframe;           // the scan's pose relative to that keyframe
  std::vector<Point2D> points;  // match points of a scan the Slam tracked (for Slam::placeScans)
};

Pose2D interpolate(const std::vector<std::pair<double, Pose2D>>& odom, double t)
{
  auto it = std::lower_bound(odom.begin(), odom.end(), t,
                             [](const std::pair<double, Pose2D>& a, double v) { return a.first < v; });
  if (it == odom.begin())
    return it->second;
  if (it == odom.end())
    return odom.back().second;
  const auto& [t1, b] = *it;
  const auto& [t0, a] = *(it - 1);
  const double f = t1 > t0 ? (t - t0) / (t1 - t0) : 0.0;
  const Pose2D d = between(a, b);
  return compose(a, {d.x * f, d.y * f, d.theta * f});
}
}  // namespace

// slam_node's parameters from a YAML file (the same names as its ROS parameters, e.g.
// config/slam.yaml); node-only settings (frames, rates) are skipped, anything else is an error.
SlamRunParams loadSlamParams(const std::string& path)
{
  SlamRunParams run;
  if (path.empty())
    return run;
  YAML::Node doc;
  try
  {
    doc = YAML::LoadFile(path);
  }
  catch (const YAML::Exception& e)
  {
    throw std::runtime_error(path + ": " + e.what());
  }
  if (!doc.IsMap())
    throw std::runtime_error(path + ": expected a mapping of slam_node parameters");
  std::map<std::string, const SlamParamSpec*> by_name;
  for (const SlamParamSpec& s : slamParamSpecs())
    by_name[s.name] = &s;
  static const char* node_only[] = {
      "base_frame", "odom_frame", "map_frame", "map_update_interval", "transform_publish_period", "throttle_scans"};
  for (const auto& kv : doc)
  {
    const std::string name = kv.first.as<std::string>();
    auto it = by_name.find(name);
    if (it == by_name.end())
    {
      if (std::find(std::begin(node_only), std::end(node_only), name) != std::end(node_only))
        continue;
      throw std::runtime_error(path + ": unknown parameter '" + name + "'");
    }
    const SlamParamSpec& s = *it->second;
    try
    {
      if (s.type == SlamParamSpec::Type::Boolean)
        s.field_bool(run) = kv.second.as<bool>();
      else
      {
        const double v = kv.second.as<double>();
        if (!s.ok(v) || (s.type == SlamParamSpec::Type::Integer && v != std::floor(v)))
          throw std::runtime_error("");
        if (s.type == SlamParamSpec::Type::Integer)
          s.field_int(run) = static_cast<int>(v);
        else
          s.field_double(run) = v;
      }
    }
    catch (const std::exception&)
    {
      throw std::runtime_error(path + ": parameter '" + name + "' must be " + s.requirement);
    }
  }
  const std::string inconsistent = checkSlamRunParams(run);
  if (!inconsistent.empty())
    throw std::runtime_error(path + ": " + inconsistent);
  return run;
}

double carmenFlaserStep(double angle_min, double angle_increment, std::size_t n)
{
  // 181 or 361 readings at 180/(n-1) deg are a SICK's own, -90 to +90 deg: those stay.
  if (n < 2 || n % 180 != 0 || std::abs(angle_min + M_PI / 2) > 1e-6 ||
      std::abs(angle_increment - M_PI / static_cast<double>(n - 1)) > 1e-6)
    return 0.0;
  return M_PI / static_cast<double>(n);
}

namespace
{
BagReplayResult replayOpenBag(rosbag::Bag& bag, const BagReplayOptions& opt, Slam& slam, const SlamRunParams& run,
                              const std::function<void(std::size_t, std::size_t)>& progress)
{
  // The laser's mounting, and (for "interpolate") every odometry pose by stamp.
  std::map<std::string, Pose2D> mount;  // child frame -> pose in its parent (the base)
  std::vector<std::pair<double, Pose2D>> odom_by_stamp;
  // For "last": every odometry message by the time it was recorded. rosbag's C++ View merges
  // topics by record time alone, so a scan and an odometry message recorded at the same instant
  // come out in either order; the logs write the odometry first (the hospital's every scan, 53 of
  // ACES's), and a scan takes the last odometry recorded at or before it.
  std::vector<std::pair<ros::Time, Pose2D>> odom_by_record_time;
  for (const rosbag::MessageInstance& m : rosbag::View(bag, rosbag::TopicQuery({"/tf_static", opt.odom_topic})))
  {
    if (auto tf = m.instantiate<tf2_msgs::TFMessage>())
      for (const auto& t : tf->transforms)
        mount[t.child_frame_id] = toPose2D(t.transform);
    else if (auto o = m.instantiate<nav_msgs::Odometry>())
    {
      odom_by_stamp.push_back({o->header.stamp.toSec(), toPose2D(o->pose.pose)});
      odom_by_record_time.push_back({m.getTime(), odom_by_stamp.back().second});
    }
  }
  std::stable_sort(odom_by_stamp.begin(), odom_by_stamp.end(),
                   [](const auto& a, const auto& b) { return a.first < b.first; });
  // With odom_frame, the whole bag's tf in one buffer that keeps all of it (the log's span).
  const bool from_tf = !opt.odom_frame.empty();
  std::unique_ptr<tf2::BufferCore> tf;
  std::map<std::string, Pose2D> tf_mount;  // laser frame -> its pose in base_frame, looked up once
  if (from_tf)
  {
    rosbag::View all(bag);
    tf = std::make_unique<tf2::BufferCore>(all.getEndTime() - all.getBeginTime() + ros::Duration(3600.0));
    for (const rosbag::MessageInstance& m :
         rosbag::View(bag, rosbag::TopicQuery(std::vector<std::string>{"/tf", "/tf_static"})))
      if (auto msg = m.instantiate<tf2_msgs::TFMessage>())
        for (const auto& t : msg->transforms)
          tf->setTransform(t, "bag", m.getTopic() == "/tf_static");
  }

  rosbag::View view(bag, rosbag::TopicQuery(std::vector<std::string>{opt.scan_topic}));
  const std::size_t total = view.size();
  std::vector<ScanRecord> scans;
  BagReplayResult result;
  bool started = false;
  std::size_t next_odom = 0;  // odom_by_record_time[next_odom] is the first recorded after the scan
  std::size_t done = 0;
  for (const rosbag::MessageInstance& m : view)
  {
    if (progress)
      progress(++done, total);
    while (next_odom < odom_by_record_time.size() && odom_by_record_time[next_odom].first <= m.getTime())
      ++next_odom;
    auto scan = m.instantiate<sensor_msgs::LaserScan>();
    if (!scan || scan->ranges.empty() || (!from_tf && next_odom == 0))
      continue;
    // As slam_node drops them (scanGeometryOk): a scan whose ranges contradict its angles, or whose
    // range limits are no range, would put walls at wrong bearings or at NaN.
    const std::string refusal = mybot_common::scanError(scan->angle_min, scan->angle_max, scan->angle_increment,
                                                        scan->ranges.size(), scan->range_min, scan->range_max);
    if (!refusal.empty())
    {
      if (result.scans_refused++ == 0)
        result.first_refusal = "the scan at " + std::to_string(scan->header.stamp.toSec()) + " " + refusal;
      continue;
    }
    const double stamp = scan->header.stamp.toSec();
    Pose2D odom;
    ScanGeometry g;
    if (from_tf)
    {
      try
      {
        odom = toPose2D(tf->lookupTransform(opt.odom_frame, opt.base_frame, scan->header.stamp).transform);
        // The mounting once per laser frame, as slam_node caches it.
        auto mt = tf_mount.find(scan->header.frame_id);
        if (mt == tf_mount.end() && !opt.override_mount)
          mt =
              tf_mount
                  .emplace(scan->header.frame_id,
                           toPose2D(tf->lookupTransform(opt.base_frame, scan->header.frame_id, ros::Time(0)).transform))
                  .first;
        if (mt != tf_mount.end())
          g.sensor_in_base = mt->second;
      }
      catch (const tf2::TransformException&)
      {
        ++result.scans_without_odometry;
        continue;
      }
    }
    else
    {
      odom = opt.odom == "last" ? odom_by_record_time[next_odom - 1].second : interpolate(odom_by_stamp, stamp);
      auto mt = mount.find(scan->header.frame_id);
      if (mt != mount.end())
        g.sensor_in_base = mt->second;
    }
    if (opt.override_mount)
      g.sensor_in_base = opt.mount;
    if (!started)
    {
      result.first_stamp = result.last_stamp = stamp;
      started = true;
    }
    if (opt.max_log_seconds > 0.0 && stamp - result.first_stamp > opt.max_log_seconds)
      break;
    double angle_increment = scan->angle_increment;
    if (!opt.carmen_angles && carmenFlaserStep(scan->angle_min, scan->angle_increment, scan->ranges.size()) > 0.0)
      ++result.scans_converter_angles;
    if (opt.carmen_angles)
    {
      const double step = carmenFlaserStep(scan->angle_min, scan->angle_increment, scan->ranges.size());
      if (step > 0.0)
      {
        angle_increment = step;
        ++result.scans_reangled;
      }
      else if (result.scans_reangled == 0)
        throw std::runtime_error(opt.bag + ": --carmen-angles: the first scan on " + opt.scan_topic + " (" +
                                 std::to_string(scan->ranges.size()) + " beams, angle_min " +
                                 std::to_string(scan->angle_min) + " rad, angle_increment " +
                                 std::to_string(scan->angle_increment) +
                                 " rad) does not have the angles a CARMEN FLASER converter derives (-pi/2, "
                                 "pi/(n-1)): nothing to correct");
    }
    result.first_stamp = std::min(result.first_stamp, stamp);
    result.last_stamp = std::max(result.last_stamp, stamp);
    // The scan's place relative to its keyframe: as the Slam tracked it, else by odometry.
    bool tracked = false;
    std::vector<Point2D> points;
    if (slam.wantsScan(stamp, odom))
    {
      const double range_max = run.max_range > 0.0 ? std::min<double>(run.max_range, scan->range_max) : scan->range_max;
      RangeScan converted =
          convertRanges(scan->ranges, scan->angle_min, angle_increment, scan->range_min, range_max, run.max_urange, g);
      points = adaptiveVoxelFilter(converted.hits, run.slam.match_point_spacing,
                                   static_cast<size_t>(run.slam.match_min_points));
      const SlamStats before = slam.stats();
      const ScanOutcome outcome = slam.addScan(stamp, odom, converted);
      tracked = outcome != ScanOutcome::OutOfOrder && outcome != ScanOutcome::BeyondMap;
      for (const LoopClosureRecord& c : loopClosureEvents(before, slam.stats()))
        result.closures.push_back(c);
    }
    else
    {
      slam.updateOdometry(odom);
    }
    const int keyframe = static_cast<int>(slam.keyframes().size()) - 1;
    Pose2D in_keyframe;
    if (tracked && keyframe >= 0)
      in_keyframe = slam.lastScanInKeyframe();
    else if (keyframe >= 0)
      in_keyframe = between(slam.keyframes().back().odom, odom);
    scans.push_back({stamp, odom, keyframe, in_keyframe, tracked ? std::move(points) : std::vector<Point2D>{}});
  }
  bag.close();
  result.scans = scans.size();
  if (opt.final_optimization)
    slam.runFinalOptimization();
  // Every scan's pose after the last optimisation: its keyframe's, moved as tracked, or (after
  // the final optimisation) matched against the keyframes around it (Slam::placeScans).
  std::vector<ScanToPlace> to_place;
  for (ScanRecord& s : scans)
  {
    result.odometry.push_back({s.stamp, s.odom});
    if (s.keyframe >= 0)
      to_place.push_back(
          {s.keyframe, s.in_keyframe, opt.final_optimization ? std::move(s.points) : std::vector<Point2D>{}});
  }
  const std::vector<Pose2D> placed = slam.placeScans(to_place);
  size_t next = 0;
  for (const ScanRecord& s : scans)
    if (s.keyframe >= 0)
      result.trajectory.push_back({s.stamp, placed[next++]});
  return result;
}

}  // namespace

BagReplayResult replayBag(const BagReplayOptions& opt, Slam& slam, const SlamRunParams& run,
                          const std::function<void(std::size_t, std::size_t)>& progress)
{
  // rosbag's messages say what failed but not in which file, nor what to do about it.
  if (std::filesystem::is_directory(opt.bag))
    throw std::runtime_error(opt.bag + ": a folder, not a bag");
  std::ifstream file(opt.bag, std::ios::binary);
  if (!file)
    throw std::runtime_error(opt.bag + ": cannot open the file (" + std::strerror(errno) + ")");
  std::string magic(9, '\0');
  if (!file.read(&magic[0], static_cast<std::streamsize>(magic.size())) || magic != "#ROSBAG V")
    throw std::runtime_error(opt.bag + ": not a ROS 1 bag (it does not start with \"#ROSBAG V\")");
  file.close();
  rosbag::Bag bag;
  try
  {
    bag.open(opt.bag, rosbag::bagmode::Read);
  }
  catch (const rosbag::BagException& e)
  {
    // The index sits at the end of the file, so a recording that was cut short has none.
    throw std::runtime_error(opt.bag + ": " + e.what() +
                             " (no readable index: if its recording was cut short, `rosbag reindex` rebuilds it)");
  }
  try
  {
    return replayOpenBag(bag, opt, slam, run, progress);
  }
  catch (const ros::Exception& e)  // rosbag::BagException, or a message that does not deserialize
  {
    throw std::runtime_error(opt.bag + ": damaged (" + e.what() + ")");
  }
  catch (const std::bad_alloc&)  // an uncompressed message whose array length was overwritten
  {
    throw std::runtime_error(opt.bag + ": damaged (a message declares more data than memory holds)");
  }
}

}  // namespace mybot_navigation
