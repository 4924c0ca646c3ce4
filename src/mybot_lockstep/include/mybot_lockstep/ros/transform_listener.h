// A tf listener whose transforms reach the buffer in lockstep: /tf and /tf_static are
// subscribed through the Participant, so a transform published by a participant for period k
// is in the buffer when this node handles period k+1, and never earlier: what a lookup finds
// does not depend on how busy the machine is. tf2_ros::TransformListener fills the buffer from
// a thread of its own, whenever the messages arrive; that is the one input of the navigation
// nodes that lockstep could not order.
//
//   tf2_ros::Buffer buffer;
//   mybot_lockstep::TransformListener listener(buffer, [this] { releaseWaitingScans(); });
//
// Off lockstep it is a plain subscriber on the node's own callback queue (the spinner that
// also runs the node's callbacks; no thread of its own), so code waiting for a transform
// must not block inside a callback: keep the message and retry from `on_update` (as
// mybot_nav_common's TfGate does). As tf2_ros's listener, it clears the buffer when ROS time
// goes back (a simulation reset, a bag played again), and `on_update` runs after the clear;
// unlike it, it then drops the transforms stamped before the jump that arrive late (time_jump.h).
#pragma once

#include <ros/ros.h>
#include <tf2_msgs/TFMessage.h>
#include <tf2_ros/buffer.h>

#include "mybot_lockstep/time_jump.h"

#include <functional>

namespace mybot_lockstep
{

class TransformListener
{
public:
  // on_update runs after each /tf or /tf_static message was put into the buffer.
  explicit TransformListener(tf2_ros::Buffer& buffer, std::function<void()> on_update = {},
                             const ros::NodeHandle& nh = ros::NodeHandle());

private:
  void received(const tf2_msgs::TFMessage& msg, bool is_static);

  tf2_ros::Buffer& buffer_;
  std::function<void()> on_update_;
  ros::Time last_now_;
  TimeJump jump_;
  ros::Subscriber tf_sub_, static_sub_;
};

}  // namespace mybot_lockstep
