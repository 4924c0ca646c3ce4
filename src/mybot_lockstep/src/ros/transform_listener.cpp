#include "mybot_lockstep/ros/transform_listener.h"

#include "mybot_lockstep/ros/participant.h"

namespace mybot_lockstep
{

TransformListener::TransformListener(tf2_ros::Buffer& buffer, std::function<void()> on_update,
                                     const ros::NodeHandle& nh)
    : buffer_(buffer), on_update_(std::move(on_update))
{
  ros::NodeHandle n(nh);
  auto& ls = Participant::instance();
  // 1000 messages (tf2_ros's listener: 100): a node whose constructor blocks (amcl waiting for
  // its map) receives nothing until it spins, and under lockstep every message a period owes is
  // waited for; with 100, amcl once lost 20 of the simulator's and held a period for 2 s.
  tf_sub_ = ls.subscribe<tf2_msgs::TFMessage>(
      n, "/tf", 1000, [this](const tf2_msgs::TFMessage& m) { received(m, false); }, ros::TransportHints().tcpNoDelay());
  static_sub_ = ls.subscribe<tf2_msgs::TFMessage>(
      n, "/tf_static", 1000, [this](const tf2_msgs::TFMessage& m) { received(m, true); },
      ros::TransportHints().tcpNoDelay());
}

void TransformListener::received(const tf2_msgs::TFMessage& msg, bool is_static)
{
  const ros::Time now = ros::Time::now();
  if (jump_.wentBack(now.toSec()))
  {
    // As tf2_ros::TransformListener: after time went back, the old transforms lie in the
    // future of the new clock and would be used for stamps they never described.
    ROS_WARN("tf: time went backwards (%.3f -> %.3f s); clearing the transform buffer", last_now_.toSec(), now.toSec());
    buffer_.clear();
  }
  last_now_ = now;
  const std::string authority = is_static ? "tf_static" : "tf";
  std::string dropped;
  for (const auto& t : msg.transforms)
  {
    // One sent just before the jump and received after the clear (time_jump.h): kept, it would
    // make tf2 refuse the frame's new transforms for the buffer's cache_time.
    if (!is_static && jump_.stale(t.header.stamp.toSec(), now.toSec()))
    {
      dropped += (dropped.empty() ? "" : ", ") + t.header.frame_id + " -> " + t.child_frame_id + " at " +
                 std::to_string(t.header.stamp.toSec());
      continue;
    }
    try
    {
      buffer_.setTransform(t, authority, is_static);
    }
    catch (const tf2::TransformException& e)
    {
      ROS_WARN_THROTTLE(5.0, "tf: rejected a transform %s -> %s: %s", t.header.frame_id.c_str(),
                        t.child_frame_id.c_str(), e.what());
    }
  }
  if (!dropped.empty())
    ROS_WARN("tf: dropped what was sent before time went back: %s", dropped.c_str());
  if (on_update_)
    on_update_();
}

}  // namespace mybot_lockstep
