// libgazebo_ros_joint_pose_trajectory.so: a trajectory_msgs/JointTrajectory on <topicName>
// (set_joint_trajectory) sets the named joints to each point's positions in turn, at once and at
// rest, the model's root staying where it is (set_model_configuration's way). As upstream times
// it: the first point at the header's stamp (now if that is past), and each next one
// time_from_start of the point before it later (upstream adds each point's time_from_start to the
// last start, so they act as durations, not as offsets from the start). Physics runs between
// points (gravity acts on the joints). A joint the robot does not have, a NaN, a point of another
// length or a position beyond a joint's limits refuses the whole trajectory, naming it; so does a
// reference frame other than the world or the root link (upstream keeps that link still: not
// simulated). A reset drops the trajectory.
#include "builtin.h"

#include "mybot_common/checks.h"

#include <trajectory_msgs/JointTrajectory.h>

#include <cmath>

namespace mybot_gazebo_lite
{

namespace
{
class JointPoseTrajectory : public SimPlugin
{
public:
  explicit JointPoseTrajectory(const PluginContext& c) : c_(c)
  {
    PluginParams p(c, c.spec->xml);
    topic_ = p.str("topicName", "set_joint_trajectory");
    ros::NodeHandle nh(c.ns);
    sub_ = subscribeCommand<trajectory_msgs::JointTrajectory>(
        c, nh, topic_, [this](const trajectory_msgs::JointTrajectory::ConstPtr& m) { onTrajectory(*m); }, 100);
  }
  void preStep(double t) override
  {
    if (next_ >= points_.size() || t + 1e-9 < start_)
      return;
    const std::string why = c_.world->setJointPositions(c_.robot->name(), joints_, points_[next_].first);
    if (!why.empty())  // checked on arrival; a joint's limits changed since (set_joint_properties)
      ROS_ERROR("gazebo_lite: %s: point %zu: %s", topic_.c_str(), next_, why.c_str());
    start_ += points_[next_].second;
    ++next_;
  }
  void update(double) override {}
  void reset() override { points_.clear(); }

private:
  void onTrajectory(const trajectory_msgs::JointTrajectory& m)
  {
    const std::string frame = m.header.frame_id;
    const std::string& root = c_.robot->spec().root;
    if (!frame.empty() && frame != "world" && frame != "map" && frame != "/map" && frame != root &&
        frame != c_.robot->name() + "::" + root)
      return refuse("header.frame_id '" + frame +
                    "': only the world (or the root link) is simulated as the reference; the model's root stays put");
    for (size_t j = 0; j < m.joint_names.size(); ++j)
      if (!c_.robot->hasJoint(scopedJoint(c_, m.joint_names[j])))
        return refuse("joint_names[" + std::to_string(j) + "] '" + m.joint_names[j] +
                      "': no movable joint of that name");
    std::vector<std::pair<std::vector<double>, double>> points;
    for (size_t i = 0; i < m.points.size(); ++i)
    {
      const auto& pt = m.points[i];
      if (pt.positions.size() != m.joint_names.size())
        return refuse("points[" + std::to_string(i) + "] has " + std::to_string(pt.positions.size()) +
                      " positions for " + std::to_string(m.joint_names.size()) + " joints");
      for (size_t j = 0; j < pt.positions.size(); ++j)
        if (!std::isfinite(pt.positions[j]))
          return refuse("points[" + std::to_string(i) + "].positions[" + std::to_string(j) + "] is not finite");
      const double d = pt.time_from_start.toSec();
      if (!std::isfinite(d) || d < 0)
        return refuse("points[" + std::to_string(i) + "].time_from_start is negative");
      points.emplace_back(pt.positions, d);
    }
    std::vector<std::string> joints;
    for (const std::string& j : m.joint_names)
      joints.push_back(scopedJoint(c_, j));
    // Every point within the joints' limits, before any moves.
    for (size_t i = 0; i < points.size(); ++i)
      for (size_t j = 0; j < joints.size(); ++j)
      {
        const Robot::Joint& jt = c_.robot->joint(joints[j]);
        const double q = points[i].first[j];
        if (jt.limited && (q < jt.lower || q > jt.upper))
          return refuse("points[" + std::to_string(i) + "].positions[" + std::to_string(j) +
                        "] = " + mybot_common::formatNumber(q) + " is beyond the limits [" +
                        mybot_common::formatNumber(jt.lower) + ", " + mybot_common::formatNumber(jt.upper) +
                        "] of joint '" + joints[j] + "'");
      }
    joints_ = std::move(joints);
    points_ = std::move(points);
    next_ = 0;
    start_ = std::max(m.header.stamp.toSec(), c_.world->time());
  }
  void refuse(const std::string& why)
  {
    ROS_ERROR("gazebo_lite: %s: trajectory refused: %s", topic_.c_str(), why.c_str());
  }

  PluginContext c_;
  std::string topic_;
  std::vector<std::string> joints_;
  std::vector<std::pair<std::vector<double>, double>> points_;  // positions, time_from_start
  size_t next_ = 0;
  double start_ = 0;
  ros::Subscriber sub_;
};
}  // namespace

std::unique_ptr<SimPlugin> makeJointPoseTrajectory(const PluginContext& c)
{
  return std::make_unique<JointPoseTrajectory>(c);
}

}  // namespace mybot_gazebo_lite
