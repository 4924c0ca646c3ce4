// move_base: thin ROS wrapper around mybot_navigation::Navigator with move_base's interface:
// the move_base action (move_base_msgs/MoveBaseAction), move_base_simple/goal, make_plan and
// clear_costmaps services, cmd_vel out; global and local costmaps, global and local plans
// published for rviz. Parameter names follow move_base, costmap_2d, global_planner and
// dwa_local_planner (namespaces ~global_costmap, ~local_costmap, ~GlobalPlanner, ~DWAPlannerROS).
#include <list>
#include <memory>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include <geometry_msgs/PoseStamped.h>
#include <geometry_msgs/Twist.h>
#include <move_base_msgs/MoveBaseAction.h>
#include <nav_msgs/GetMap.h>
#include <nav_msgs/GetPlan.h>
#include <nav_msgs/OccupancyGrid.h>
#include <nav_msgs/Odometry.h>
#include <nav_msgs/Path.h>
#include <ros/ros.h>
#include <sensor_msgs/LaserScan.h>
#include <std_srvs/Empty.h>
#include <tf2_geometry_msgs/tf2_geometry_msgs.h>
#include <tf2_ros/buffer.h>

#include "mybot_common/ros/node_main.h"
#include "mybot_lockstep/ros/participant.h"
#include "mybot_lockstep/ros/transform_listener.h"
#include "mybot_move_base/navigator.h"
#include "mybot_nav_common/ros/node_params.h"
#include "mybot_nav_common/ros/conversions.h"
#include "mybot_nav_common/ros/tf_gate.h"
#include "goal_server.h"

using namespace mybot_navigation;

namespace
{
const char* kNode = "move_base";

struct CostmapConfig
{
  CostmapParams params;
  std::string global_frame, robot_base_frame;
  double update_frequency = 5.0, publish_frequency = 0.0, transform_tolerance = 0.2;
  std::string map_topic = "map";
  struct Source
  {
    std::string name, topic;
    bool marking = true, clearing = true, inf_is_valid = true;
  };
  std::vector<Source> sources;
};

// costmap_2d's parameters, flat (pre-layer) style as in the navigation tutorials, with the
// layer namespaces (obstacle_layer/, inflation_layer/) accepted as overrides.
CostmapConfig readCostmap(const ros::NodeHandle& nh, bool rolling_default)
{
  CostmapConfig c;
  CostmapParams& p = c.params;
  auto d = [&](const std::string& n, double def) { return readParam<double>(kNode, nh, n, def); };
  c.global_frame = readParam<std::string>(kNode, nh, "global_frame", "map");
  c.robot_base_frame = readParam<std::string>(kNode, nh, "robot_base_frame", "base_link");
  c.update_frequency = d("update_frequency", 5.0);
  c.publish_frequency = d("publish_frequency", 0.0);
  c.transform_tolerance = d("transform_tolerance", 0.2);
  c.map_topic = readParam<std::string>(kNode, nh, "map_topic", "map");
  p.rolling_window = readParam<bool>(kNode, nh, "rolling_window", rolling_default);
  p.width = d("width", 10.0);
  p.height = d("height", 10.0);
  p.resolution = d("resolution", 0.05);
  p.use_static_map = readParam<bool>(kNode, nh, "static_map", true);
  p.track_unknown_space = readParam<bool>(kNode, nh, "track_unknown_space", false);
  p.lethal_cost_threshold = readParam<int>(kNode, nh, "lethal_cost_threshold", 100);
  p.robot_radius = d("robot_radius", 0.46);
  p.footprint_padding = d("footprint_padding", 0.01);
  if (nh.hasParam("footprint"))
  {
    XmlRpc::XmlRpcValue v;
    nh.getParam("footprint", v);
    std::string error;
    if (!parseFootprint(v, p.footprint, error))
      fatalParam(kNode, nh, "footprint", error);
  }
  p.obstacle_range = d("obstacle_range", p.obstacle_range);
  p.raytrace_range = d("raytrace_range", p.raytrace_range);
  p.obstacle_range = d("obstacle_layer/obstacle_range", p.obstacle_range);
  p.raytrace_range = d("obstacle_layer/raytrace_range", p.raytrace_range);
  p.inflation_radius = d("inflation_radius", p.inflation_radius);
  p.cost_scaling_factor = d("cost_scaling_factor", p.cost_scaling_factor);
  p.inflation_radius = d("inflation_layer/inflation_radius", p.inflation_radius);
  p.cost_scaling_factor = d("inflation_layer/cost_scaling_factor", p.cost_scaling_factor);
  const std::string sources = readParam<std::string>(kNode, nh, "observation_sources", "");
  std::istringstream names(sources);
  for (std::string name; names >> name;)
  {
    CostmapConfig::Source s;
    s.name = name;
    ros::NodeHandle snh(nh, name);
    s.topic = readParam<std::string>(kNode, snh, "topic", name);
    const std::string type = readParam<std::string>(kNode, snh, "data_type", "LaserScan");
    if (type != "LaserScan")
      fatalParam(kNode, snh, "data_type", "only LaserScan observation sources are supported (got " + type + ")");
    s.marking = readParam<bool>(kNode, snh, "marking", true);
    s.clearing = readParam<bool>(kNode, snh, "clearing", true);
    s.inf_is_valid = readParam<bool>(kNode, snh, "inf_is_valid", true);
    c.sources.push_back(s);
  }
  p.use_obstacles = !c.sources.empty();
  p.footprint_clearing_enabled = readParam<bool>(kNode, nh, "footprint_clearing_enabled", p.footprint_clearing_enabled);
  p.footprint_clearing_enabled =
      readParam<bool>(kNode, nh, "obstacle_layer/footprint_clearing_enabled", p.footprint_clearing_enabled);
  const std::string error = validate(p);
  if (!error.empty())
    fatalParam(kNode, nh, "", error);
  if (!(c.update_frequency > 0.0))
    fatalParam(kNode, nh, "update_frequency", "must be > 0");
  return c;
}

LocalPlannerParams readLocalPlanner(const ros::NodeHandle& nh, double controller_frequency)
{
  LocalPlannerParams p;
  auto d = [&](const std::string& n, double& v) { v = readParam<double>(kNode, nh, n, v); };
  auto i = [&](const std::string& n, int& v) { v = readParam<int>(kNode, nh, n, v); };
  d("max_vel_x", p.max_vel_x);
  d("min_vel_x", p.min_vel_x);
  d("max_vel_y", p.max_vel_y);
  d("min_vel_y", p.min_vel_y);
  // dwa_local_planner renamed max/min_trans_vel and max/min_rot_vel in Noetic: accept both.
  d("max_trans_vel", p.max_vel_trans);
  d("min_trans_vel", p.min_vel_trans);
  d("max_vel_trans", p.max_vel_trans);
  d("min_vel_trans", p.min_vel_trans);
  d("max_rot_vel", p.max_vel_theta);
  d("min_rot_vel", p.min_vel_theta);
  d("max_vel_theta", p.max_vel_theta);
  d("min_vel_theta", p.min_vel_theta);
  d("acc_lim_x", p.acc_lim_x);
  d("acc_lim_y", p.acc_lim_y);
  d("acc_lim_theta", p.acc_lim_theta);
  p.holonomic_robot = readParam<bool>(kNode, nh, "holonomic_robot", false);
  d("sim_time", p.sim_time);
  d("sim_granularity", p.sim_granularity);
  d("angular_sim_granularity", p.angular_sim_granularity);
  i("vx_samples", p.vx_samples);
  i("vy_samples", p.vy_samples);
  i("vth_samples", p.vth_samples);
  d("path_distance_bias", p.path_distance_bias);
  d("goal_distance_bias", p.goal_distance_bias);
  d("occdist_scale", p.occdist_scale);
  d("forward_point_distance", p.forward_point_distance);
  d("holonomic_align_scale", p.holonomic_align_scale);
  d("oscillation_reset_dist", p.oscillation_reset_dist);
  d("oscillation_reset_angle", p.oscillation_reset_angle);
  d("xy_goal_tolerance", p.xy_goal_tolerance);
  d("yaw_goal_tolerance", p.yaw_goal_tolerance);
  p.latch_xy_goal_tolerance = readParam<bool>(kNode, nh, "latch_xy_goal_tolerance", false);
  d("trans_stopped_vel", p.trans_stopped_vel);
  d("rot_stopped_vel", p.rot_stopped_vel);
  d("rotate_to_path_angle", p.rotate_to_path_angle);
  p.controller_frequency = controller_frequency;
  const std::string error = validate(p);
  if (!error.empty())
    fatalParam(kNode, nh, "", error);
  return p;
}

PlannerParams readPlanner(const ros::NodeHandle& nh)
{
  PlannerParams p;
  p.use_dijkstra = readParam<bool>(kNode, nh, "use_dijkstra", p.use_dijkstra);
  p.allow_unknown = readParam<bool>(kNode, nh, "allow_unknown", p.allow_unknown);
  p.default_tolerance = readParam<double>(kNode, nh, "default_tolerance", p.default_tolerance);
  p.neutral_cost = readParam<double>(kNode, nh, "neutral_cost", p.neutral_cost);
  p.cost_factor = readParam<double>(kNode, nh, "cost_factor", p.cost_factor);
  p.lethal_cost = readParam<int>(kNode, nh, "lethal_cost", p.lethal_cost);
  p.smooth_path = readParam<bool>(kNode, nh, "smooth_path", p.smooth_path);
  const std::string error = validate(p);
  if (!error.empty())
    fatalParam(kNode, nh, "", error);
  return p;
}

nav_msgs::Path toPath(const std::vector<Pose2D>& poses, const std::string& frame, const ros::Time& stamp)
{
  nav_msgs::Path path;
  path.header.frame_id = frame;
  path.header.stamp = stamp;
  for (const Pose2D& p : poses)
  {
    geometry_msgs::PoseStamped ps;
    ps.header = path.header;
    ps.pose = toPoseMsg(p);
    path.poses.push_back(ps);
  }
  return path;
}
}  // namespace

class MoveBaseNode
{
  using Server = mybot_move_base::GoalServer<move_base_msgs::MoveBaseAction>;

public:
  MoveBaseNode()
      : pnh_("~"),
        listener_(tf_buffer_, [this] { releaseScans(); }),
        global_cfg_(readCostmap(ros::NodeHandle(pnh_, "global_costmap"), false)),
        local_cfg_(readCostmap(ros::NodeHandle(pnh_, "local_costmap"), true)),
        global_(global_cfg_.params),
        local_(local_cfg_.params)
  {
    NavigatorParams np;
    auto d = [&](const std::string& n, double& v) { v = readParam<double>(kNode, pnh_, n, v); };
    controller_frequency_ = readParam<double>(kNode, pnh_, "controller_frequency", 20.0);
    if (!(controller_frequency_ > 0.0))
      fatalParam(kNode, pnh_, "controller_frequency", "must be > 0");
    d("planner_frequency", np.planner_frequency);
    d("planner_patience", np.planner_patience);
    d("controller_patience", np.controller_patience);
    d("oscillation_timeout", np.oscillation_timeout);
    d("oscillation_distance", np.oscillation_distance);
    np.max_planning_retries = readParam<int>(kNode, pnh_, "max_planning_retries", np.max_planning_retries);
    np.recovery_behavior_enabled = readParam<bool>(kNode, pnh_, "recovery_behavior_enabled", true);
    np.clearing_rotation_allowed = readParam<bool>(kNode, pnh_, "clearing_rotation_allowed", true);
    d("conservative_reset_dist", np.conservative_reset_dist);
    d("backup_distance", np.backup_distance);
    d("backup_speed", np.backup_speed);
    const std::string nav_error = validate(np);
    if (!nav_error.empty())
      fatalParam(kNode, pnh_, "", nav_error);
    const std::string global_planner =
        readParam<std::string>(kNode, pnh_, "base_global_planner", "global_planner/GlobalPlanner");
    const std::string local_planner =
        readParam<std::string>(kNode, pnh_, "base_local_planner", "dwa_local_planner/DWAPlannerROS");
    if (global_planner != "global_planner/GlobalPlanner" && global_planner != "navfn/NavfnROS")
      ROS_WARN("move_base: base_global_planner \"%s\" is not available; using global_planner/GlobalPlanner",
               global_planner.c_str());
    if (local_planner != "dwa_local_planner/DWAPlannerROS" &&
        local_planner != "base_local_planner/TrajectoryPlannerROS")
      ROS_WARN("move_base: base_local_planner \"%s\" is not available; using dwa_local_planner/DWAPlannerROS",
               local_planner.c_str());
    // navfn and TrajectoryPlannerROS configs use their own namespaces; read whichever is named.
    const std::string gp_ns = global_planner == "navfn/NavfnROS" ? "NavfnROS" : "GlobalPlanner";
    const std::string lp_ns =
        local_planner == "base_local_planner/TrajectoryPlannerROS" ? "TrajectoryPlannerROS" : "DWAPlannerROS";
    planner_ = std::make_unique<GlobalPlanner>(readPlanner(ros::NodeHandle(pnh_, gp_ns)));
    controller_ = std::make_unique<LocalPlanner>(readLocalPlanner(ros::NodeHandle(pnh_, lp_ns), controller_frequency_));
    navigator_ = std::make_unique<Navigator>(np, global_, local_, *planner_, *controller_);
    if (global_cfg_.global_frame != local_cfg_.global_frame)
      fatalParam(kNode, pnh_, "local_costmap/global_frame",
                 "must equal global_costmap/global_frame (\"" + global_cfg_.global_frame +
                     "\"): this controller follows the plan in the global frame");
    global_frame_ = global_cfg_.global_frame;
    base_frame_ = global_cfg_.robot_base_frame;

    cmd_pub_ = nh_.advertise<geometry_msgs::Twist>("cmd_vel", 1);
    plan_pub_ = pnh_.advertise<nav_msgs::Path>(gp_ns + "/plan", 1, true);
    local_plan_pub_ = pnh_.advertise<nav_msgs::Path>(lp_ns + "/local_plan", 1);
    dwa_global_plan_pub_ = pnh_.advertise<nav_msgs::Path>(lp_ns + "/global_plan", 1);
    goal_pub_ = pnh_.advertise<geometry_msgs::PoseStamped>("current_goal", 1, true);
    global_costmap_pub_ = pnh_.advertise<nav_msgs::OccupancyGrid>("global_costmap/costmap", 1, true);
    local_costmap_pub_ = pnh_.advertise<nav_msgs::OccupancyGrid>("local_costmap/costmap", 1, true);
    // In lockstep when the simulator runs it (mybot_lockstep): odometry, scans, tf, the map and
    // the timers are handled period by period, and so are the action's goals and cancels
    // (GoalServer).
    auto& ls = mybot_lockstep::Participant::instance();
    simple_goal_sub_ = ls.subscribe<geometry_msgs::PoseStamped>(
        nh_, "move_base_simple/goal", 1, [this](const geometry_msgs::PoseStamped::ConstPtr& m) { simpleGoal(m); });
    action_goal_pub_ = nh_.advertise<move_base_msgs::MoveBaseActionGoal>("move_base/goal", 1);
    // Only the newest odometry is used, but under lockstep every message of a period must be
    // received (a queue of 1 drops the rest, and the period waits for them): room for a period.
    odom_sub_ = ls.subscribe<nav_msgs::Odometry>(nh_, "odom", 20,
                                                 [this](const nav_msgs::Odometry::ConstPtr& m) { odomReceived(m); });
    make_plan_srv_ = pnh_.advertiseService("make_plan", &MoveBaseNode::makePlan, this);
    clear_srv_ = pnh_.advertiseService("clear_costmaps", &MoveBaseNode::clearCostmaps, this);
    for (const CostmapConfig* cfg : {&global_cfg_, &local_cfg_})
      for (const auto& s : cfg->sources)
        if (scan_topics_.insert(s.topic).second)
        {
          // A scan waits until the global frame -> its sensor is known at its stamp (AMCL's map ->
          // odom comes after the scan it was computed from).
          ScanSource& src = sources_.emplace_back(s, nh_.resolveName(s.topic));
          src.sub = ls.subscribe<sensor_msgs::LaserScan>(
              nh_, s.topic, 5,
              [this, &src](const sensor_msgs::LaserScan::ConstPtr& m)
              {
                // A scan that contradicts itself is refused
                // on arrival, not after its wait for tf.
                if (!have_map_ || !scanGeometryOk("move_base", src.gate.topic(), *m))
                  return;
                src.gate.add(m);
                releaseScans();
              });
        }

    if (!global_cfg_.params.use_static_map)
      fatalParam(kNode, pnh_, "global_costmap/static_map", "must be true: this implementation needs a map");
    map_sub_ = ls.subscribe<nav_msgs::OccupancyGrid>(
        nh_, global_cfg_.map_topic, 1, [this](const nav_msgs::OccupancyGrid::ConstPtr& m) { mapReceived(m); });

    server_ = std::make_unique<Server>(
        nh_, "move_base", [this](const move_base_msgs::MoveBaseGoalConstPtr& goal) { goalCallback(goal); },
        [this] { preemptCallback(); });

    control_timer_ =
        ls.createTimer(nh_, 1.0 / controller_frequency_, [this](const ros::TimerEvent& e) { controlLoop(e); });
    update_timer_ = ls.createTimer(nh_, 1.0 / global_cfg_.update_frequency,
                                   [this](const ros::TimerEvent& e) { updateCostmaps(e); });
    const double pub_rate = std::max(global_cfg_.publish_frequency, local_cfg_.publish_frequency);
    if (pub_rate > 0.0)
      publish_timer_ = ls.createTimer(nh_, 1.0 / pub_rate, [this](const ros::TimerEvent& e) { publishCostmaps(e); });
    ROS_INFO("move_base: waiting for the map on %s", nh_.resolveName(global_cfg_.map_topic).c_str());
  }

private:
  void mapReceived(const nav_msgs::OccupancyGrid::ConstPtr& msg)
  {
    if (msg->info.width == 0 || msg->info.height == 0)
    {
      ROS_ERROR("move_base: ignoring an empty map");
      return;
    }
    const GridMap map = fromOccupancyGrid(*msg);
    global_.setStaticMap(map);
    local_.setStaticMap(map);
    have_map_ = true;
    ROS_INFO("move_base: costmaps use a %d x %d map @ %.3f m", map.info.width, map.info.height, map.info.resolution);
    publishCostmaps(ros::TimerEvent());
  }

  void odomReceived(const nav_msgs::Odometry::ConstPtr& msg)
  {
    // Odometry comes at the base's rate (50 Hz), faster than the control loop: the first place
    // a jump back in time is seen, so the robot stops within a message of it.
    checkTimeJump();
    velocity_ = {msg->twist.twist.linear.x, msg->twist.twist.linear.y, msg->twist.twist.angular.z};
    last_odom_ = ros::Time::now();
  }

  // Treats a jump of ROS time backwards as a reset (timeWentBack) once; any callback may call it.
  void checkTimeJump()
  {
    const ros::Time now = ros::Time::now();
    if (now < last_control_)
      timeWentBack(now);
    last_control_ = now;
  }

  // Hands each waiting scan to the costmaps once its sensor's pose is known at its stamp.
  void releaseScans()
  {
    checkTimeJump();
    for (ScanSource& src : sources_)
      src.gate.release(
          ros::Time::now(),
          [this](const sensor_msgs::LaserScan& scan)
          {
            return scan.header.frame_id.empty() ||
                   tf_buffer_.canTransform(global_frame_, scan.header.frame_id, scan.header.stamp);
          },
          [this, &src](const sensor_msgs::LaserScan::ConstPtr& m) { scanReceived(m, src.config); });
  }

  void scanReceived(const sensor_msgs::LaserScan::ConstPtr& scan, const CostmapConfig::Source& source)
  {
    if (!have_map_)
      return;
    Pose2D sensor;
    bool upside_down = false;
    try
    {
      sensor = mybot_navigation::toPose2D(
          tf_buffer_.lookupTransform(global_frame_, scan->header.frame_id, scan->header.stamp), &upside_down);
    }
    catch (const tf2::TransformException& e)
    {
      ROS_WARN_THROTTLE(5.0, "move_base: dropping scan from %s: %s", source.topic.c_str(), e.what());
      return;
    }
    for (Costmap* cm : {&global_, &local_})
    {
      std::vector<Point2D> hits, ends;
      scanEndPoints(*scan, sensor, upside_down, cm->params().raytrace_range, hits, ends, source.inf_is_valid);
      if (!source.marking)
      {
        ends.insert(ends.end(), hits.begin(), hits.end());
        hits.clear();
      }
      if (!source.clearing)
        ends.clear();
      if (cm == &local_)
        cm->updateOrigin(sensor.x, sensor.y);
      cm->updateWithScan({sensor.x, sensor.y}, hits, ends);
    }
  }

  void updateCostmaps(const ros::TimerEvent&)
  {
    Pose2D pose;
    if (robotPose(pose, false))
    {
      local_.updateOrigin(pose.x, pose.y);
      local_.clearFootprint(pose);
      global_.clearFootprint(pose);
    }
    global_.updateCosts();
    local_.updateCosts();
  }

  void publishCostmaps(const ros::TimerEvent&)
  {
    if (!have_map_)
      return;
    const ros::Time now = ros::Time::now();
    for (auto [cm, pub] :
         {std::make_pair(&global_, &global_costmap_pub_), std::make_pair(&local_, &local_costmap_pub_)})
    {
      nav_msgs::OccupancyGrid msg;
      msg.header.frame_id = global_frame_;
      msg.header.stamp = now;
      msg.info = toMapMetaData(cm->info());
      msg.info.map_load_time = now;
      msg.data = cm->toOccupancyValues();
      pub->publish(msg);
    }
  }

  bool robotPose(Pose2D& pose, bool warn)
  {
    try
    {
      const auto t = tf_buffer_.lookupTransform(global_frame_, base_frame_, ros::Time(0));
      // A stale pose (localization or odometry stopped) must not drive the robot.
      if (!t.header.stamp.isZero() && (ros::Time::now() - t.header.stamp).toSec() > maxPoseAge())
      {
        if (warn)
          ROS_WARN_THROTTLE(2.0, "move_base: the robot pose %s -> %s is %.2f s old", global_frame_.c_str(),
                            base_frame_.c_str(), (ros::Time::now() - t.header.stamp).toSec());
        return false;
      }
      pose = mybot_navigation::toPose2D(t);
      return true;
    }
    catch (const tf2::TransformException& e)
    {
      if (warn)
        ROS_WARN_THROTTLE(2.0, "move_base: unable to get the robot pose: %s", e.what());
      return false;
    }
  }

  double maxPoseAge() const { return global_cfg_.transform_tolerance + 1.0 / controller_frequency_ + 0.2; }

  bool toGlobalFrame(const geometry_msgs::PoseStamped& in, Pose2D& out, std::string& error)
  {
    if (in.header.frame_id.empty() || in.header.frame_id == global_frame_)
    {
      out = mybot_navigation::toPose2D(in.pose);
      return true;
    }
    try
    {
      // The goal's frame as it was at the goal's stamp, the global frame as it is now (the rviz
      // goal in base_link means "from where the robot was"). No timeout: nothing fills the buffer
      // while this callback runs (tf comes through the lockstep participant).
      geometry_msgs::PoseStamped g;
      tf2::doTransform(in, g,
                       tf_buffer_.lookupTransform(global_frame_, ros::Time(0), in.header.frame_id, in.header.stamp,
                                                  in.header.frame_id));
      out = mybot_navigation::toPose2D(g.pose);
      return true;
    }
    catch (const tf2::TransformException& e)
    {
      error = std::string("cannot transform the goal into ") + global_frame_ + ": " + e.what();
      return false;
    }
  }

  void goalCallback(const move_base_msgs::MoveBaseGoalConstPtr& goal)
  {
    pending_goal_ = goal;
    pending_since_ = ros::Time::now();
    const auto& o = pending_goal_->target_pose.pose.orientation;
    const double q = std::sqrt(o.x * o.x + o.y * o.y + o.z * o.z + o.w * o.w);
    if (!(std::abs(q - 1.0) < 0.01))
      abortPending("the goal has an invalid quaternion");
    else if (!have_map_)
      abortPending("no map received yet");
    else
      startPendingGoal();
  }

  // A goal that arrives while the pose is a moment old (start-up, a loaded machine, a late
  // odometry message) waits for a fresh one, as move_base does, instead of aborting at once.
  // The wait happens in the control loop, so scans, make_plan and the timers keep being served.
  void startPendingGoal()
  {
    Pose2D g, pose;
    std::string error;
    if (!robotPose(pose, false))
    {
      if (moving_)
        stop();
      if ((ros::Time::now() - pending_since_).toSec() > kPoseWait)
        abortPending("the robot pose is unknown");
      return;
    }
    if (toGlobalFrame(pending_goal_->target_pose, g, error))
      error = navigator_->setGoal(g, ros::Time::now().toSec(), pose);
    if (!error.empty())
    {
      abortPending(error);
      return;
    }
    pending_goal_.reset();
    geometry_msgs::PoseStamped current;
    current.header.frame_id = global_frame_;
    current.header.stamp = ros::Time::now();
    current.pose = toPoseMsg(g);
    goal_pub_.publish(current);
    publishPlan();
  }

  void abortPending(const std::string& error)
  {
    pending_goal_.reset();
    ROS_WARN("move_base: goal aborted: %s", error.c_str());
    stop();
    server_->setAborted(error);
  }

  void preemptCallback()
  {
    pending_goal_.reset();
    navigator_->cancel();
    stop();
    if (server_->isActive())
      server_->setPreempted();
  }

  void simpleGoal(const geometry_msgs::PoseStamped::ConstPtr& msg)
  {
    // move_base wraps the rviz goal into an action goal on its own server.
    move_base_msgs::MoveBaseActionGoal action_goal;
    action_goal.header.stamp = ros::Time::now();
    action_goal.goal.target_pose = *msg;
    action_goal_pub_.publish(action_goal);
  }

  void stop()
  {
    cmd_pub_.publish(geometry_msgs::Twist());
    moving_ = false;
  }

  void publishPlan()
  {
    const nav_msgs::Path path = toPath(navigator_->globalPlan(), global_frame_, ros::Time::now());
    plan_pub_.publish(path);
    dwa_global_plan_pub_.publish(path);
  }

  // Time went backwards (a simulation reset sends the robot back to its spawn pose; a bag played
  // again): the plan, the costmaps' marks and the odometry stamps belong to a past that did not
  // happen. Stop, abort the goal saying why, clear, and go on with the next goal.
  void timeWentBack(const ros::Time& now)
  {
    ROS_WARN("move_base: time went backwards (%.3f -> %.3f s); stopping, clearing the costmaps%s",
             last_control_.toSec(), now.toSec(), server_->isActive() ? " and aborting the goal" : "");
    pending_goal_.reset();
    navigator_->cancel();
    stop();
    if (server_->isActive())
      server_->setAborted("time went backwards (simulation reset?)");
    server_->forget();
    global_.reset();
    local_.reset();
    last_odom_ = ros::Time();
    velocity_ = {};
  }

  void controlLoop(const ros::TimerEvent&)
  {
    checkTimeJump();
    if (!server_->isActive())
      return;
    if (pending_goal_)
    {
      startPendingGoal();
      return;
    }
    Pose2D pose;
    if (!robotPose(pose, true))
    {
      stop();
      return;
    }
    // A velocity older than a few control periods is not a measurement: assume the command.
    Velocity2D vel = velocity_;
    if ((ros::Time::now() - last_odom_).toSec() > 0.5)
      vel = last_cmd_;
    local_.updateOrigin(pose.x, pose.y);
    local_.clearFootprint(pose);
    global_.clearFootprint(pose);
    local_.updateCosts();
    const NavOutput out = navigator_->step(ros::Time::now().toSec(), pose, vel);
    if (out.new_plan)
      publishPlan();
    if (!out.local.trajectory.empty())
      local_plan_pub_.publish(toPath(out.local.trajectory, global_frame_, ros::Time::now()));
    move_base_msgs::MoveBaseFeedback feedback;
    feedback.base_position.header.frame_id = global_frame_;
    feedback.base_position.header.stamp = ros::Time::now();
    feedback.base_position.pose = toPoseMsg(pose);
    server_->publishFeedback(feedback);
    switch (out.state)
    {
      case NavState::Succeeded:
        stop();
        server_->setSucceeded("Goal reached.");
        return;
      case NavState::Aborted:
        stop();
        ROS_WARN("move_base: aborting: %s", out.message.c_str());
        server_->setAborted(out.message);
        return;
      case NavState::Idle:
        stop();
        return;
      default:
        break;
    }
    if (out.state == NavState::Clearing && out.message != last_recovery_)
      ROS_WARN("move_base: running recovery behavior %s", out.message.c_str());
    last_recovery_ = out.state == NavState::Clearing ? out.message : "";
    geometry_msgs::Twist cmd;
    cmd.linear.x = out.cmd.vx;
    cmd.linear.y = out.cmd.vy;
    cmd.angular.z = out.cmd.wz;
    cmd_pub_.publish(cmd);
    last_cmd_ = out.cmd;
    moving_ = true;
  }

  bool makePlan(nav_msgs::GetPlan::Request& req, nav_msgs::GetPlan::Response& res)
  {
    Pose2D start, goal;
    std::string error;
    if (!have_map_)
    {
      ROS_ERROR("move_base: make_plan called before a map was received");
      return false;
    }
    // An empty start frame means "from the robot's current pose" (move_base does the same).
    if (req.start.header.frame_id.empty())
    {
      if (!robotPose(start, true))
        return false;
    }
    else if (!toGlobalFrame(req.start, start, error))
    {
      ROS_ERROR("move_base: make_plan: %s", error.c_str());
      return false;
    }
    if (!toGlobalFrame(req.goal, goal, error))
    {
      ROS_ERROR("move_base: make_plan: %s", error.c_str());
      return false;
    }
    PlannerParams pp = planner_->params();
    if (req.tolerance > 0.0)
      pp.default_tolerance = req.tolerance;
    const PlanResult r = GlobalPlanner(pp).makePlan(global_, start, goal);
    res.plan = toPath(r.path, global_frame_, ros::Time::now());
    if (r.status != PlanStatus::Ok)
      ROS_WARN("move_base: make_plan: %s", r.message.c_str());
    return true;
  }

  bool clearCostmaps(std_srvs::Empty::Request&, std_srvs::Empty::Response&)
  {
    global_.reset();
    local_.reset();
    global_.updateCosts();
    local_.updateCosts();
    ROS_INFO("move_base: costmaps cleared");
    return true;
  }

  ros::NodeHandle nh_, pnh_;
  tf2_ros::Buffer tf_buffer_;
  mybot_lockstep::TransformListener listener_;
  CostmapConfig global_cfg_, local_cfg_;
  Costmap global_, local_;
  std::unique_ptr<GlobalPlanner> planner_;
  std::unique_ptr<LocalPlanner> controller_;
  std::unique_ptr<Navigator> navigator_;
  std::unique_ptr<Server> server_;
  static constexpr double kPoseWait = 2.0;  // s of sim time a new goal waits for a robot pose
  move_base_msgs::MoveBaseGoalConstPtr pending_goal_;
  ros::Time pending_since_;
  std::string global_frame_, base_frame_;
  double controller_frequency_ = 20.0;
  bool have_map_ = false, moving_ = false;
  Velocity2D velocity_, last_cmd_;
  ros::Time last_odom_, last_control_;
  std::string last_recovery_;
  struct ScanSource
  {
    ScanSource(const CostmapConfig::Source& s, const std::string& resolved) : config(s), gate("move_base", resolved, 5)
    {
    }
    CostmapConfig::Source config;
    TfGate<sensor_msgs::LaserScan> gate;
    ros::Subscriber sub;
  };
  std::set<std::string> scan_topics_;
  std::list<ScanSource> sources_;  // a list: the subscriptions' callbacks hold references
  ros::Publisher cmd_pub_, plan_pub_, local_plan_pub_, dwa_global_plan_pub_, goal_pub_, global_costmap_pub_,
      local_costmap_pub_, action_goal_pub_;
  ros::Subscriber simple_goal_sub_, odom_sub_, map_sub_;
  ros::ServiceServer make_plan_srv_, clear_srv_;
  mybot_lockstep::Timer control_timer_, update_timer_, publish_timer_;
};

int main(int argc, char** argv)
{
  return mybot_common::runNode(argc, argv, "move_base",
                               []
                               {
                                 MoveBaseNode node;
                                 ros::spin();
                               });
}
