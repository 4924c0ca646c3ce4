// slam_node: thin ROS wrapper around mybot_navigation::Slam with gmapping's interface
// (scan + tf odom->base in; map, map_metadata, tf map->odom, dynamic_map out).
#include <cmath>
#include <cstdio>
#include <map>
#include <memory>
#include <mutex>
#include <string>

#include <nav_msgs/GetMap.h>
#include <nav_msgs/OccupancyGrid.h>
#include <nav_msgs/Path.h>
#include <ros/ros.h>
#include <sensor_msgs/LaserScan.h>
#include <std_srvs/Trigger.h>
#include <tf2_ros/buffer.h>
#include <tf2_ros/transform_broadcaster.h>

#include "mybot_common/ros/node_main.h"
#include "mybot_lockstep/ros/participant.h"
#include "mybot_lockstep/ros/transform_listener.h"
#include "mybot_nav_common/ros/tf_gate.h"
#include "mybot_nav_common/ros/node_params.h"
#include "mybot_nav_common/ros/conversions.h"
#include "mybot_slam/slam.h"
#include "mybot_slam/slam_params.h"

using namespace mybot_navigation;

namespace
{
const auto positive = [](double v) { return std::isfinite(v) && v > 0.0; };
const auto non_negative = [](double v) { return std::isfinite(v) && v >= 0.0; };
const auto any_number = [](double v) { return std::isfinite(v); };
const auto probability = [](double v) { return v > 0.0 && v < 1.0; };
const auto non_empty = [](const std::string& s) { return !s.empty(); };
}  // namespace

class SlamNode
{
public:
  SlamNode() : pnh_("~"), listener_(tf_buffer_, [this] { releaseScans(); })
  {
    // Strict: a value of the wrong type or out of range throws ParamError naming it, and
    // runNode stops the node with that one line.
    const mybot_common::ParamReader params(pnh_);
    base_frame_ = params.checked<std::string>("base_frame", "base_link", non_empty, "a frame name");
    odom_frame_ = params.checked<std::string>("odom_frame", "odom", non_empty, "a frame name");
    map_frame_ = params.checked<std::string>("map_frame", "map", non_empty, "a frame name");
    map_update_interval_ = params.checked("map_update_interval", 5.0, non_negative, "a number >= 0 (s)");
    transform_publish_period_ = params.checked("transform_publish_period", 0.05, non_negative, "a number >= 0 (s)");
    throttle_scans_ = params.checked(
        "throttle_scans", 1, [](int v) { return v >= 1; }, "an integer >= 1");

    // The Slam's own parameters: one table, shared with slam_replay.
    SlamRunParams run;
    for (const SlamParamSpec& spec : slamParamSpecs())
    {
      switch (spec.type)
      {
        case SlamParamSpec::Type::Number:
          spec.field_double(run) = params.checked(spec.name, spec.field_double(run), spec.ok, spec.requirement);
          break;
        case SlamParamSpec::Type::Integer:
          spec.field_int(run) = params.checked(
              spec.name, spec.field_int(run), [&spec](int v) { return spec.ok(v); }, spec.requirement);
          break;
        case SlamParamSpec::Type::Boolean:
          spec.field_bool(run) = params.checked(
              spec.name, spec.field_bool(run), [](bool) { return true; }, "a bool");
          break;
      }
    }
    const std::string inconsistent = checkSlamRunParams(run);
    if (!inconsistent.empty())
      throw mybot_common::ParamError("parameters " + inconsistent);
    max_urange_ = run.max_urange;
    max_range_ = run.max_range;
    SlamParams p = run.slam;
    if (p.grid.resolution > 1.0)
      ROS_WARN("slam: ~delta = %.2f m is a very coarse map", p.grid.resolution);
    params_ = p;
    slam_ = std::make_unique<Slam>(p);

    map_pub_ = nh_.advertise<nav_msgs::OccupancyGrid>("map", 1, true);
    meta_pub_ = nh_.advertise<nav_msgs::MapMetaData>("map_metadata", 1, true);
    map_srv_ = nh_.advertiseService("dynamic_map", &SlamNode::mapService, this);
    finish_srv_ = nh_.advertiseService("finish_trajectory", &SlamNode::finishTrajectory, this);
    // The keyframe poses as the pose graph now has them (after every loop closure): what the map
    // was rendered from, for scoring a run against ground truth and for rviz.
    path_pub_ = pnh_.advertise<nav_msgs::Path>("trajectory", 1, true);

    // In lockstep when the simulator runs it (mybot_lockstep): scans and tf are handled period
    // by period, so the map does not depend on how busy the machine is. A scan waits until
    // odom -> base is known at its stamp; 100 of them (2.5 s of a 40 Hz laser) absorb the bursts
    // of a bag played live, where a queue of 5 dropped scans.
    auto& ls = mybot_lockstep::Participant::instance();
    scan_sub_ = ls.subscribe<sensor_msgs::LaserScan>(nh_, "scan", 100,
                                                     [this](const sensor_msgs::LaserScan::ConstPtr& m)
                                                     {
                                                       scans_.add(m);
                                                       releaseScans();
                                                     });
    if (transform_publish_period_ > 0.0)
      tf_timer_ =
          ls.createTimer(nh_, transform_publish_period_, [this](const ros::TimerEvent& e) { publishTransform(e); });
    ROS_INFO("slam: delta %.3f m, linearUpdate %.2f m, angularUpdate %.2f rad, frames %s -> %s -> %s, loop closure %s",
             p.grid.resolution, p.linear_update, p.angular_update, map_frame_.c_str(), odom_frame_.c_str(),
             base_frame_.c_str(), p.loop_closure ? "on" : "off");
  }

private:
  void releaseScans()
  {
    scans_.release(
        ros::Time::now(),
        [this](const sensor_msgs::LaserScan& scan)
        {
          if (scan.header.frame_id.empty())
          {
            ROS_WARN_THROTTLE(5.0, "slam: dropping a scan at %.3f: empty frame_id", scan.header.stamp.toSec());
            return true;  // handed on to be dropped, not kept forever
          }
          return tf_buffer_.canTransform(odom_frame_, scan.header.frame_id, scan.header.stamp);
        },
        [this](const sensor_msgs::LaserScan::ConstPtr& scan)
        {
          if (!scan->header.frame_id.empty())
            scanCallback(scan);
        });
  }

  struct BeamTable
  {
    double angle_min, angle_increment;
    size_t count;
  };

  bool laserGeometry(const sensor_msgs::LaserScan& scan, ScanGeometry& g)
  {
    auto it = geometry_.find(scan.header.frame_id);
    if (it != geometry_.end())
    {
      g = it->second;
      return true;
    }
    geometry_msgs::TransformStamped t;
    try
    {
      t = tf_buffer_.lookupTransform(base_frame_, scan.header.frame_id, ros::Time(0));
    }
    catch (const tf2::TransformException& e)
    {
      ROS_WARN_THROTTLE(5.0, "slam: no transform %s -> %s yet: %s", scan.header.frame_id.c_str(), base_frame_.c_str(),
                        e.what());
      return false;
    }
    const auto& q = t.transform.rotation;
    // Laser z axis expressed in the base frame: pointing down means a mounted-upside-down laser.
    const double z_z = 1.0 - 2.0 * (q.x * q.x + q.y * q.y);
    // Laser x axis in the base frame gives the yaw of beam 0 direction reference.
    const double x_x = 1.0 - 2.0 * (q.y * q.y + q.z * q.z), x_y = 2.0 * (q.x * q.y + q.w * q.z);
    g.sensor_in_base = {t.transform.translation.x, t.transform.translation.y, std::atan2(x_y, x_x)};
    g.upside_down = z_z < 0.0;
    if (std::abs(z_z) < 0.99)
      ROS_WARN("slam: laser frame %s is tilted with respect to %s; treating it as horizontal",
               scan.header.frame_id.c_str(), base_frame_.c_str());
    geometry_[scan.header.frame_id] = g;
    return true;
  }

  static void logClosure(const LoopClosureRecord& c)
  {
    ROS_INFO(
        "slam: loop closure keyframe %d -> %d %s (score %.2f, %.2f at the estimate, constraint ratio %.2f, "
        "correction %.3f m %.3f m %.3f rad)",
        c.to, c.from, c.reason, c.score, c.score_at_estimate, c.ratio, c.correction.x, c.correction.y,
        c.correction.theta);
  }

  void scanCallback(const sensor_msgs::LaserScan::ConstPtr& scan)
  {
    if (++scan_counter_ % throttle_scans_ != 0)
      return;
    const double stamp = scan->header.stamp.toSec();
    if (scan->ranges.empty())
    {
      ROS_WARN_THROTTLE(5.0, "slam: empty scan at %.3f ignored", stamp);
      return;
    }
    if (!mybot_navigation::scanGeometryOk("slam", scans_.topic(), *scan))
      return;
    geometry_msgs::TransformStamped odom_tf;
    try
    {
      odom_tf = tf_buffer_.lookupTransform(odom_frame_, base_frame_, scan->header.stamp);
    }
    catch (const tf2::TransformException& e)
    {
      ROS_WARN_THROTTLE(5.0, "slam: no odometry (%s -> %s) at scan time %.3f: %s", odom_frame_.c_str(),
                        base_frame_.c_str(), stamp, e.what());
      return;
    }
    const Pose2D odom = toPose2D(odom_tf.transform);
    std::lock_guard<std::mutex> lock(mutex_);
    startOverIfTimeWentBack();
    if (finished_)
      return;  // the map is final; map -> odom stays where the final optimisation left it
    if (!slam_->wantsScan(stamp, odom))
    {
      if (stamp <= last_stamp_)
        ROS_WARN_THROTTLE(5.0, "slam: scan at %.3f is not newer than the last one (%.3f): dropped", stamp, last_stamp_);
      else
        slam_->updateOdometry(odom);
      return;
    }
    ScanGeometry g;
    if (!laserGeometry(*scan, g))
      return;
    const double range_max = max_range_ > 0.0 ? std::min<double>(max_range_, scan->range_max) : scan->range_max;
    ScanConversionStats stats;
    const RangeScan rs = convertRanges(scan->ranges, scan->angle_min, scan->angle_increment, scan->range_min, range_max,
                                       max_urange_, g, &stats);
    // Throttled hard: some lasers mark every dropout NaN (REP 117), and the scan is still used.
    if (stats.invalid > 0)
      ROS_WARN_THROTTLE(30.0, "slam: scan at %.3f has %d invalid readings (NaN/-inf/below range_min): ignored", stamp,
                        stats.invalid);
    const SlamStats before = slam_->stats();
    const ScanOutcome outcome = slam_->addScan(stamp, odom, rs);
    const SlamStats& after = slam_->stats();
    for (const LoopClosureRecord& c : loopClosureEvents(before, after))
      logClosure(c);
    last_stamp_ = std::max(last_stamp_, stamp);
    // A base driver that stopped sending new poses, or a robot turned by hand (track_stall_search).
    if (after.stall_matches > before.stall_matches)
      ROS_WARN_THROTTLE(10.0,
                        "slam: the odometry (%s -> %s) reported no motion since the last scan, but the scan at %.3f "
                        "fits elsewhere: placed by a search in every heading (score %.2f)",
                        odom_frame_.c_str(), base_frame_.c_str(), stamp, after.last_match_score);
    // Odometry late against the scans in a turn (track_retry_window_angular).
    if (after.retry_matches > before.retry_matches)
      ROS_WARN_THROTTLE(10.0,
                        "slam: the scan at %.3f fits beyond the matcher's window around the odometry's (%s -> %s) "
                        "heading: placed by a search in a wider one (score %.2f); is the odometry stamped late?",
                        stamp, odom_frame_.c_str(), base_frame_.c_str(), after.last_match_score);
    switch (outcome)
    {
      case ScanOutcome::NoValidPoints:
        ROS_WARN_THROTTLE(5.0, "slam: scan at %.3f has no valid returns (%d invalid, %d out of range): not used", stamp,
                          stats.invalid, stats.no_return + stats.clipped);
        return;
      case ScanOutcome::OutOfOrder:
        ROS_WARN_THROTTLE(5.0, "slam: scan at %.3f is out of order: dropped", stamp);
        return;
      case ScanOutcome::BeyondMap:
        ROS_WARN_THROTTLE(5.0,
                          "slam: scan at %.3f refused: the odometry (%s -> %s: x %g, y %g) puts it beyond the map's "
                          "limits (%g m from the odometry's origin, %d cells a side); is the odometry broken?",
                          stamp, odom_frame_.c_str(), base_frame_.c_str(), odom.x, odom.y, kMaxCoordinate, kMaxMapSide);
        return;
      case ScanOutcome::Skipped:
        return;
      case ScanOutcome::Processed:
        break;
    }
    // Counted, not judged by the score: a weak match close to the prediction is still used
    // (weak_match_min_score).
    if (after.weak_matches > before.weak_matches)
      ROS_WARN_THROTTLE(10.0, "slam: weak scan match (score %.2f): using odometry for this step",
                        after.last_match_score);
    if (!published_ || stamp - last_map_publish_ >= map_update_interval_)
      publishMap(scan->header.stamp);
  }

  void publishMap(const ros::Time& stamp)
  {
    if (slam_->mapVersion() == published_version_ && published_)
      return;
    nav_msgs::OccupancyGrid msg;
    toOccupancyGrid(slam_->map(), msg);
    msg.header.frame_id = map_frame_;
    msg.header.stamp = stamp;
    msg.info.map_load_time = stamp;
    map_pub_.publish(msg);
    meta_pub_.publish(msg.info);
    publishTrajectory(stamp);
    published_ = true;
    published_version_ = slam_->mapVersion();
    last_map_publish_ = stamp.toSec();
    ROS_DEBUG("slam: published %dx%d map (%d keyframes, %d loop closures)", msg.info.width, msg.info.height,
              slam_->stats().keyframes, slam_->stats().loop_closures);
  }

  void publishTrajectory(const ros::Time& stamp)
  {
    nav_msgs::Path path;
    path.header.frame_id = map_frame_;
    path.header.stamp = stamp;
    path.poses.reserve(slam_->keyframes().size());
    for (const Keyframe& k : slam_->keyframes())
    {
      geometry_msgs::PoseStamped p;
      p.header.frame_id = map_frame_;
      p.header.stamp.fromSec(k.stamp);
      p.pose = toPoseMsg(k.pose);
      path.poses.push_back(p);
    }
    path_pub_.publish(path);
  }

  // Cartographer's finish_trajectory: the final optimisation of slam_replay (every keyframe tied
  // to every earlier pass through its place, the whole graph optimised once more), then the map
  // and trajectory are published and no longer change; map -> odom keeps its last value. Online
  // loop closure ties a revisit to one candidate every few keyframes, only where the drift it
  // removes is worth it; call this when mapping is over, before saving the map.
  bool finishTrajectory(std_srvs::Trigger::Request&, std_srvs::Trigger::Response& res)
  {
    std::lock_guard<std::mutex> lock(mutex_);
    if (finished_)
    {
      res.message = "the trajectory is already finished";
      return true;
    }
    if (slam_->keyframes().empty())
    {
      res.message = "no map yet: no scan has been processed";
      return true;
    }
    slam_->runFinalOptimization();
    finished_ = true;
    const SlamStats& st = slam_->stats();
    res.success = true;
    char message[160];
    std::snprintf(message, sizeof(message),
                  "%zu keyframes, %d revisit edges in the final optimisation (%d dropped); map consistency %.3f -> "
                  "%.3f",
                  slam_->keyframes().size(), st.final_edges, st.final_edges_dropped, st.final_consistency_before,
                  st.final_consistency_after);
    res.message = message;
    ROS_INFO("slam: trajectory finished: %s; the map no longer changes", res.message.c_str());
    publishMap(ros::Time::now());
    return true;
  }

  bool mapService(nav_msgs::GetMap::Request&, nav_msgs::GetMap::Response& res)
  {
    std::lock_guard<std::mutex> lock(mutex_);
    if (slam_->keyframes().empty())
      return false;  // gmapping also fails the call until a map exists
    toOccupancyGrid(slam_->map(), res.map);
    res.map.header.frame_id = map_frame_;
    res.map.header.stamp = ros::Time::now();
    return true;
  }

  // Time went backwards (a simulation reset sends the robot back to its spawn pose and the
  // odometry to zero; a bag played again, to its start): the map and trajectory belong to a past
  // that did not happen. Start a new map, as at launch, and go on. Call with mutex_ held.
  void startOverIfTimeWentBack()
  {
    const ros::Time now = ros::Time::now();
    const bool back = now < last_now_;
    last_now_ = now;
    if (!back)
      return;
    ROS_WARN("slam: time went backwards (to %.3f s); starting a new map", now.toSec());
    slam_ = std::make_unique<Slam>(params_);
    finished_ = false;
    last_stamp_ = -1e300;
    published_ = false;
    published_version_ = 0;
    last_map_publish_ = 0.0;
    last_tf_stamp_ = ros::Time();
  }

  void publishTransform(const ros::TimerEvent&)
  {
    Pose2D m2o;
    {
      std::lock_guard<std::mutex> lock(mutex_);
      startOverIfTimeWentBack();
      m2o = slam_->mapToOdom();
    }
    geometry_msgs::TransformStamped t;
    // Future-dated like gmapping so consumers can interpolate up to the next publication.
    t.header.stamp = ros::Time::now() + ros::Duration(transform_publish_period_);
    if (t.header.stamp <= last_tf_stamp_)
      return;  // the sim clock has not advanced since the last publication (tf2 rejects repeats)
    last_tf_stamp_ = t.header.stamp;
    t.header.frame_id = map_frame_;
    t.child_frame_id = odom_frame_;
    t.transform = toTransform(m2o);
    broadcaster_.sendTransform(t);
  }

  ros::NodeHandle nh_, pnh_;
  tf2_ros::Buffer tf_buffer_;
  mybot_lockstep::TransformListener listener_;
  tf2_ros::TransformBroadcaster broadcaster_;
  ros::Subscriber scan_sub_;
  TfGate<sensor_msgs::LaserScan> scans_{"slam", ros::NodeHandle().resolveName("scan"), 100};
  ros::Publisher map_pub_, meta_pub_, path_pub_;
  ros::ServiceServer map_srv_, finish_srv_;
  mybot_lockstep::Timer tf_timer_;
  std::string base_frame_, odom_frame_, map_frame_;
  double map_update_interval_, transform_publish_period_, max_urange_, max_range_;
  int throttle_scans_;
  long scan_counter_ = 0;
  std::unique_ptr<Slam> slam_;
  std::map<std::string, ScanGeometry> geometry_;
  std::mutex mutex_;
  double last_stamp_ = -1e300;
  bool published_ = false;
  bool finished_ = false;  // finish_trajectory was called: scans are no longer used
  uint64_t published_version_ = 0;
  double last_map_publish_ = 0.0;
  ros::Time last_tf_stamp_, last_now_;
  SlamParams params_;
};

int main(int argc, char** argv)
{
  return mybot_common::runNode(argc, argv, "slam",
                               []
                               {
                                 SlamNode node;
                                 ros::spin();
                               });
}
