// amcl: thin ROS wrapper around mybot_navigation::Amcl with amcl's interface
// (scan + tf odom->base + map in; amcl_pose, particlecloud, tf map->odom out; initialpose,
// global_localization, request_nomotion_update).
#include <cmath>
#include <cstdio>
#include <memory>
#include <optional>
#include <string>

#include <geometry_msgs/PoseArray.h>
#include <geometry_msgs/PoseWithCovarianceStamped.h>
#include <nav_msgs/GetMap.h>
#include <nav_msgs/OccupancyGrid.h>
#include <ros/ros.h>
#include <sensor_msgs/LaserScan.h>
#include <std_srvs/Empty.h>
#include <tf2_ros/buffer.h>
#include <tf2_ros/transform_broadcaster.h>

#include "mybot_common/checks.h"
#include "mybot_common/ros/node_main.h"
#include "mybot_amcl/amcl.h"
#include "mybot_lockstep/ros/participant.h"
#include "mybot_lockstep/ros/transform_listener.h"
#include "mybot_nav_common/ros/node_params.h"
#include "mybot_nav_common/ros/conversions.h"
#include "mybot_nav_common/ros/tf_gate.h"

using namespace mybot_navigation;

namespace
{
const char* kNode = "amcl";

AmclParams readAmclParams(const ros::NodeHandle& pnh)
{
  AmclParams p;
  auto d = [&](const std::string& n, double def) { return readParam<double>(kNode, pnh, n, def); };
  auto i = [&](const std::string& n, int def) { return readParam<int>(kNode, pnh, n, def); };
  p.filter.min_particles = i("min_particles", p.filter.min_particles);
  p.filter.max_particles = i("max_particles", p.filter.max_particles);
  p.filter.kld_err = d("kld_err", p.filter.kld_err);
  p.filter.kld_z = d("kld_z", p.filter.kld_z);
  p.filter.alpha_slow = d("recovery_alpha_slow", p.filter.alpha_slow);
  p.filter.alpha_fast = d("recovery_alpha_fast", p.filter.alpha_fast);
  p.filter.recovery_trigger_ratio = d("recovery_trigger_ratio", p.filter.recovery_trigger_ratio);
  p.filter.recovery_release_ratio = d("recovery_release_ratio", p.filter.recovery_release_ratio);
  p.filter.recovery_accept_ratio = d("recovery_accept_ratio", p.filter.recovery_accept_ratio);
  p.filter.recovery_accept_updates = i("recovery_accept_updates", p.filter.recovery_accept_updates);
  p.filter.recovery_max_see_through = d("recovery_max_see_through", p.filter.recovery_max_see_through);
  p.laser.max_beams = i("laser_max_beams", p.laser.max_beams);
  p.laser.z_hit = d("laser_z_hit", p.laser.z_hit);
  p.laser.z_rand = d("laser_z_rand", p.laser.z_rand);
  p.laser.sigma_hit = d("laser_sigma_hit", p.laser.sigma_hit);
  p.laser.likelihood_max_dist = d("laser_likelihood_max_dist", p.laser.likelihood_max_dist);
  const std::string model = readParam<std::string>(kNode, pnh, "odom_model_type", "diff");
  if (!parseOdomModelType(model, p.odom_model))
    fatalParam(kNode, pnh, "odom_model_type",
               "unknown model \"" + model + "\" (diff, omni, diff-corrected or omni-corrected)");
  p.odom_noise.alpha1 = d("odom_alpha1", p.odom_noise.alpha1);
  p.odom_noise.alpha2 = d("odom_alpha2", p.odom_noise.alpha2);
  p.odom_noise.alpha3 = d("odom_alpha3", p.odom_noise.alpha3);
  p.odom_noise.alpha4 = d("odom_alpha4", p.odom_noise.alpha4);
  p.odom_noise.alpha5 = d("odom_alpha5", p.odom_noise.alpha5);
  p.update_min_d = d("update_min_d", p.update_min_d);
  p.update_min_a = d("update_min_a", p.update_min_a);
  p.resample_interval = i("resample_interval", p.resample_interval);
  p.initial_pose = {d("initial_pose_x", 0.0), d("initial_pose_y", 0.0), d("initial_pose_a", 0.0)};
  p.initial_cov_xx = d("initial_cov_xx", p.initial_cov_xx);
  p.initial_cov_yy = d("initial_cov_yy", p.initial_cov_yy);
  p.initial_cov_aa = d("initial_cov_aa", p.initial_cov_aa);
  p.seed = static_cast<unsigned>(i("seed", 0));
  const std::string error = validate(p);
  if (!error.empty())
    fatalParam(kNode, pnh, "", error);
  return p;
}
}  // namespace

class AmclNode
{
public:
  AmclNode()
      : pnh_("~"), listener_(tf_buffer_, [this] { releaseScans(); }), params_(readAmclParams(pnh_)), amcl_(params_)
  {
    odom_frame_ = readParam<std::string>(kNode, pnh_, "odom_frame_id", "odom");
    base_frame_ = readParam<std::string>(kNode, pnh_, "base_frame_id", "base_link");
    global_frame_ = readParam<std::string>(kNode, pnh_, "global_frame_id", "map");
    const bool tf_broadcast = readParam<bool>(kNode, pnh_, "tf_broadcast", true);
    transform_tolerance_ = readParam<double>(kNode, pnh_, "transform_tolerance", 0.1);
    laser_min_range_ = readParam<double>(kNode, pnh_, "laser_min_range", -1.0);
    laser_max_range_ = readParam<double>(kNode, pnh_, "laser_max_range", -1.0);
    gui_publish_rate_ = readParam<double>(kNode, pnh_, "gui_publish_rate", -1.0);
    save_pose_rate_ = readParam<double>(kNode, pnh_, "save_pose_rate", 0.5);
    use_map_topic_ = readParam<bool>(kNode, pnh_, "use_map_topic", false);
    first_map_only_ = readParam<bool>(kNode, pnh_, "first_map_only", false);
    const std::string laser_model = readParam<std::string>(kNode, pnh_, "laser_model_type", "likelihood_field");
    if (laser_model != "likelihood_field")
      fatalParam(kNode, pnh_, "laser_model_type",
                 "only \"likelihood_field\" is implemented (got \"" + laser_model + "\")");
    if (odom_frame_.empty() || base_frame_.empty() || global_frame_.empty())
      fatalParam(kNode, pnh_, "odom_frame_id/base_frame_id/global_frame_id", "frame names must not be empty");
    if (transform_tolerance_ < 0.0)
      fatalParam(kNode, pnh_, "transform_tolerance", "must be >= 0");

    pose_pub_ = nh_.advertise<geometry_msgs::PoseWithCovarianceStamped>("amcl_pose", 2, true);
    if (tf_broadcast)
      broadcaster_.emplace();
    cloud_pub_ = nh_.advertise<geometry_msgs::PoseArray>("particlecloud", 2, true);
    global_loc_srv_ = nh_.advertiseService("global_localization", &AmclNode::globalLocalization, this);
    nomotion_srv_ = nh_.advertiseService("request_nomotion_update", &AmclNode::nomotionUpdate, this);
    // In lockstep when the simulator runs it (mybot_lockstep): scans, tf, poses and the map are
    // handled period by period, so the filter sees the same inputs on a busy machine.
    auto& ls = mybot_lockstep::Participant::instance();
    initial_pose_sub_ = ls.subscribe<geometry_msgs::PoseWithCovarianceStamped>(
        nh_, "initialpose", 2, [this](const geometry_msgs::PoseWithCovarianceStamped::ConstPtr& m) { initialPose(m); });
    // A scan waits (up to 100, as amcl's message filter) until odom -> base is known at its stamp.
    scan_sub_ = ls.subscribe<sensor_msgs::LaserScan>(nh_, "scan", 100,
                                                     [this](const sensor_msgs::LaserScan::ConstPtr& m)
                                                     {
                                                       scans_.add(m);
                                                       releaseScans();
                                                     });

    if (use_map_topic_)
    {
      map_sub_ = ls.subscribe<nav_msgs::OccupancyGrid>(
          nh_, "map", 1, [this](const nav_msgs::OccupancyGrid::ConstPtr& m) { mapReceived(m); });
      ROS_INFO("amcl: subscribed to map topic %s", nh_.resolveName("map").c_str());
    }
    else
    {
      requestMap();
    }
    if (save_pose_rate_ > 0.0)
      save_timer_ = ls.createTimer(nh_, 1.0 / save_pose_rate_, [this](const ros::TimerEvent& e) { savePose(e); });
  }

private:
  void releaseScans()
  {
    scans_.release(
        ros::Time::now(),
        [this](const sensor_msgs::LaserScan& s) {
          return s.header.frame_id.empty() || tf_buffer_.canTransform(odom_frame_, s.header.frame_id, s.header.stamp);
        },
        [this](const sensor_msgs::LaserScan::ConstPtr& s) { scanReceived(s); });
  }

  void requestMap()
  {
    nav_msgs::GetMap srv;
    ROS_INFO("amcl: requesting the map from %s", nh_.resolveName("static_map").c_str());
    while (ros::ok() && !ros::service::call("static_map", srv))
    {
      ROS_WARN_THROTTLE(5.0, "amcl: request for map failed; trying again...");
      ros::Duration(0.5).sleep();
    }
    if (ros::ok())
      handleMap(srv.response.map);
  }

  void mapReceived(const nav_msgs::OccupancyGrid::ConstPtr& msg)
  {
    if (first_map_only_ && amcl_.hasMap())
      return;
    handleMap(*msg);
  }

  void handleMap(const nav_msgs::OccupancyGrid& msg)
  {
    if (msg.header.frame_id != global_frame_ && !msg.header.frame_id.empty())
      ROS_WARN("amcl: map frame \"%s\" differs from global_frame_id \"%s\"", msg.header.frame_id.c_str(),
               global_frame_.c_str());
    if (msg.info.width == 0 || msg.info.height == 0 || msg.data.size() != size_t(msg.info.width) * msg.info.height)
    {
      ROS_ERROR("amcl: ignoring an empty or malformed map (%u x %u, %zu cells)", msg.info.width, msg.info.height,
                msg.data.size());
      return;
    }
    ROS_INFO("amcl: received a %d X %d map @ %.3f m/pix", msg.info.width, msg.info.height, msg.info.resolution);
    // amcl re-initialises around the last saved / configured initial pose on every new map.
    amcl_.setMap(fromOccupancyGrid(msg));
    if (have_pose_)
      amcl_.setInitialPose(last_pose_, params_.initial_cov_xx, params_.initial_cov_yy, params_.initial_cov_aa);
    publishCloud(ros::Time::now());
  }

  bool globalLocalization(std_srvs::Empty::Request&, std_srvs::Empty::Response&)
  {
    if (!amcl_.hasMap())
    {
      ROS_WARN("amcl: global_localization requested before a map was received");
      return false;
    }
    ROS_INFO("amcl: initializing with uniform distribution over free space");
    amcl_.globalLocalization();
    publishCloud(ros::Time::now());
    return true;
  }

  bool nomotionUpdate(std_srvs::Empty::Request&, std_srvs::Empty::Response&)
  {
    amcl_.requestNoMotionUpdate();
    ROS_INFO("amcl: requesting no-motion update");
    return true;
  }

  void initialPose(const geometry_msgs::PoseWithCovarianceStamped::ConstPtr& msg)
  {
    if (msg->header.frame_id.empty())
      ROS_WARN("amcl: received initial pose with empty frame_id; assuming %s", global_frame_.c_str());
    else if ((msg->header.frame_id[0] == '/' ? msg->header.frame_id.substr(1) : msg->header.frame_id) != global_frame_)
    {
      ROS_WARN("amcl: ignoring initial pose in frame \"%s\"; it must be in the global frame \"%s\"",
               msg->header.frame_id.c_str(), global_frame_.c_str());
      return;
    }
    // A NaN here would become a NaN map -> odom for every node downstream.
    const auto& in = msg->pose.pose;
    const auto& cov = msg->pose.covariance;
    std::string bad = mybot_common::firstInvalid({{"pose.pose.position.x", in.position.x},
                                                  {"pose.pose.position.y", in.position.y},
                                                  {"pose.pose.orientation.x", in.orientation.x},
                                                  {"pose.pose.orientation.y", in.orientation.y},
                                                  {"pose.pose.orientation.z", in.orientation.z},
                                                  {"pose.pose.orientation.w", in.orientation.w}},
                                                 kMaxCoordinate);
    if (bad.empty())
      bad = mybot_common::firstInvalid(
          {{"pose.covariance[0]", cov[0]}, {"pose.covariance[7]", cov[7]}, {"pose.covariance[35]", cov[35]}});
    for (int i : {0, 7, 35})
      if (bad.empty() && cov[i] < 0)
      {
        char text[96];
        std::snprintf(text, sizeof text, "pose.covariance[%d] is %g, a negative variance", i, cov[i]);
        bad = text;
      }
    const double qn = std::sqrt(in.orientation.x * in.orientation.x + in.orientation.y * in.orientation.y +
                                in.orientation.z * in.orientation.z + in.orientation.w * in.orientation.w);
    if (bad.empty() && qn < 1e-6)
      bad = "pose.pose.orientation is a zero quaternion";
    if (!bad.empty())
    {
      ROS_ERROR("amcl: ignoring initial pose: %s", bad.c_str());
      return;
    }
    Pose2D pose = mybot_navigation::toPose2D(msg->pose.pose);
    // The robot kept moving since the pose was stamped: apply the odometry motion since then.
    try
    {
      const Pose2D then =
          mybot_navigation::toPose2D(tf_buffer_.lookupTransform(odom_frame_, base_frame_, msg->header.stamp));
      const Pose2D now = mybot_navigation::toPose2D(tf_buffer_.lookupTransform(odom_frame_, base_frame_, ros::Time(0)));
      pose = compose(pose, between(then, now));
    }
    catch (const tf2::TransformException& e)
    {
      ROS_DEBUG("amcl: initial pose used as is: %s", e.what());
    }
    const auto& c = msg->pose.covariance;
    ROS_INFO("amcl: setting pose: %.3f %.3f %.3f", pose.x, pose.y, pose.theta);
    amcl_.setInitialPose(pose, c[0], c[7], c[35]);
    last_pose_ = pose;
    have_pose_ = true;
    publishCloud(ros::Time::now());
  }

  bool laserPose(const std::string& frame, const ros::Time& stamp, Pose2D& pose, bool& upside_down)
  {
    try
    {
      const auto t = tf_buffer_.lookupTransform(base_frame_, frame, stamp);
      pose = mybot_navigation::toPose2D(t, &upside_down);
      return true;
    }
    catch (const tf2::TransformException& e)
    {
      ROS_WARN_THROTTLE(5.0, "amcl: cannot place laser frame \"%s\" on the base \"%s\": %s", frame.c_str(),
                        base_frame_.c_str(), e.what());
      return false;
    }
  }

  void scanReceived(const sensor_msgs::LaserScan::ConstPtr& scan)
  {
    if (!amcl_.hasMap() || !scanGeometryOk("amcl", scans_.topic(), *scan))
      return;
    // ROS time itself going back, not a scan older than the last (a tf message filter can release
    // scans a few milliseconds out of order; that is no reset).
    const ros::Time now = ros::Time::now();
    if (!last_now_.isZero() && now < last_now_)
    {
      // Time went backwards (tf2's listener has cleared the buffer): start over as at launch.
      ROS_WARN("amcl: time went backwards (%.3f -> %.3f s); starting over at the initial pose (%.3f, %.3f, %.3f)",
               last_now_.toSec(), now.toSec(), params_.initial_pose.x, params_.initial_pose.y,
               params_.initial_pose.theta);
      amcl_.restart(params_.initial_pose, params_.initial_cov_xx, params_.initial_cov_yy, params_.initial_cov_aa);
      last_pose_ = params_.initial_pose;
      last_cloud_ = ros::Time();
    }
    last_now_ = now;
    Pose2D odom_pose;
    try
    {
      odom_pose = mybot_navigation::toPose2D(tf_buffer_.lookupTransform(odom_frame_, base_frame_, scan->header.stamp));
    }
    catch (const tf2::TransformException& e)
    {
      ROS_WARN_THROTTLE(5.0, "amcl: no odometry pose at the scan time: %s", e.what());
      return;
    }
    const std::string broken = poseError(odom_pose);
    if (!broken.empty())
    {
      ROS_WARN_THROTTLE(5.0, "amcl: scan not used: the odometry (%s -> %s) %s; is it broken?", odom_frame_.c_str(),
                        base_frame_.c_str(), broken.c_str());
      return;
    }
    Pose2D sensor_in_base;
    bool upside_down = false;
    if (!laserPose(scan->header.frame_id, scan->header.stamp, sensor_in_base, upside_down))
      return;
    const LaserScanData data =
        laserScanData(scan->ranges, scan->angle_min, scan->angle_increment, scan->range_min, scan->range_max,
                      laser_min_range_, laser_max_range_, sensor_in_base, upside_down);
    const bool updated = amcl_.processScan(odom_pose, data);
    if (updated && amcl_.filter().releaseVetoed() && !veto_logged_)
    {
      // Once per search: the check runs at every update until the cloud is somewhere plausible.
      veto_logged_ = true;
      ROS_INFO(
          "amcl: the scan fits %.0f %% as well as when localized, but from there %.0f %% of its beams would "
          "pass through walls: searching on",
          100.0 * amcl_.filter().wFast() / amcl_.filter().wSlow(), 100.0 * amcl_.lastSeeThrough());
    }
    if (updated && amcl_.filter().lost() != lost_)
    {
      lost_ = amcl_.filter().lost();
      veto_logged_ = false;
      const ParticleFilter& f = amcl_.filter();
      if (lost_)
        ROS_WARN("amcl: the scan fits %.0f %% as well as when localized: adding random particles",
                 100.0 * f.wFast() / f.wSlow());
      else if (f.wFast() >= f.params().recovery_release_ratio * f.wSlow())
        ROS_INFO("amcl: the scan fits %.0f %% as well as when localized again: recovery stops",
                 100.0 * f.wFast() / f.wSlow());
      else
        ROS_WARN(
            "amcl: the scan fits %.0f %% as well as when localized, and %d updates of search found no better "
            "place: recovery stops here",
            100.0 * f.wFast() / f.wSlow(), f.params().recovery_accept_updates);
    }
    if (updated)
    {
      const PoseEstimate& e = amcl_.estimate();
      geometry_msgs::PoseWithCovarianceStamped msg;
      msg.header.frame_id = global_frame_;
      msg.header.stamp = scan->header.stamp;
      msg.pose.pose = toPoseMsg(e.mean);
      msg.pose.covariance[0] = e.cov[0];
      msg.pose.covariance[1] = e.cov[1];
      msg.pose.covariance[6] = e.cov[3];
      msg.pose.covariance[7] = e.cov[4];
      msg.pose.covariance[35] = e.cov[8];
      pose_pub_.publish(msg);
      last_pose_ = e.mean;
      have_pose_ = true;
      if (gui_publish_rate_ <= 0.0 || (scan->header.stamp - last_cloud_).toSec() >= 1.0 / gui_publish_rate_)
        publishCloud(scan->header.stamp);
    }
    if (broadcaster_ && amcl_.hasEstimate())
    {
      // map -> odom, future-dated by transform_tolerance so consumers can use it until the next scan.
      geometry_msgs::TransformStamped t;
      t.header.frame_id = global_frame_;
      t.header.stamp = scan->header.stamp + ros::Duration(transform_tolerance_);
      t.child_frame_id = odom_frame_;
      t.transform = toTransform(amcl_.mapToOdom());
      broadcaster_->sendTransform(t);
    }
  }

  void publishCloud(const ros::Time& stamp)
  {
    geometry_msgs::PoseArray cloud;
    cloud.header.frame_id = global_frame_;
    cloud.header.stamp = stamp;
    for (const Particle& p : amcl_.particles())
      cloud.poses.push_back(toPoseMsg(p.pose));
    cloud_pub_.publish(cloud);
    last_cloud_ = stamp;
  }

  void savePose(const ros::TimerEvent&)
  {
    // amcl stores the last estimate so a restart (or a new map) resumes from it.
    if (!have_pose_)
      return;
    pnh_.setParam("initial_pose_x", last_pose_.x);
    pnh_.setParam("initial_pose_y", last_pose_.y);
    pnh_.setParam("initial_pose_a", last_pose_.theta);
  }

  ros::NodeHandle nh_, pnh_;
  tf2_ros::Buffer tf_buffer_;
  mybot_lockstep::TransformListener listener_;
  // Made once the parameters are valid, and only with tf_broadcast: a member advertised /tf from a
  // node about to refuse its configuration, or told never to send map -> odom.
  std::optional<tf2_ros::TransformBroadcaster> broadcaster_;
  AmclParams params_;
  Amcl amcl_;
  std::string odom_frame_, base_frame_, global_frame_;
  bool use_map_topic_ = false, first_map_only_ = false;
  double transform_tolerance_ = 0.1, laser_min_range_ = -1, laser_max_range_ = -1;
  double gui_publish_rate_ = -1, save_pose_rate_ = 0.5;
  ros::Publisher pose_pub_, cloud_pub_;
  ros::ServiceServer global_loc_srv_, nomotion_srv_;
  ros::Subscriber initial_pose_sub_, map_sub_;
  ros::Subscriber scan_sub_;
  TfGate<sensor_msgs::LaserScan> scans_{"amcl", ros::NodeHandle().resolveName("scan"), 100};
  mybot_lockstep::Timer save_timer_;
  Pose2D last_pose_;
  bool lost_ = false;
  bool veto_logged_ = false;
  bool have_pose_ = false;
  ros::Time last_now_;
  ros::Time last_cloud_;
};

int main(int argc, char** argv)
{
  return mybot_common::runNode(argc, argv, "amcl",
                               []
                               {
                                 AmclNode node;
                                 ros::spin();
                               });
}
