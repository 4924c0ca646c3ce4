// Waiting for a transform without outliving a reset.
#pragma once

#include <ros/ros.h>
#include <tf2_ros/buffer.h>

#include <string>

namespace mybot_navigation
{

// Waits up to `timeout` of ROS time until `buffer` can transform `source` into `target` at
// `stamp`. Returns false at once when ROS time goes back while it waits: after a simulation
// reset the stamp will not come until sim time catches up, and tf2's own timed lookup would
// hold the node that long -- long enough that it no longer sees that time went back (move_base
// kept a goal and drove on through a reset). The poll sleeps in ROS time, which returns as
// soon as time jumps back.
inline bool waitForTransform(const tf2_ros::Buffer& buffer, const std::string& target, const std::string& source,
                             const ros::Time& stamp, const ros::Duration& timeout)
{
  const ros::Time start = ros::Time::now();
  while (!buffer.canTransform(target, source, stamp))
  {
    const ros::Time now = ros::Time::now();
    if (now < start || now - start >= timeout || !ros::ok())
      return false;
    ros::Duration(0.001).sleep();
  }
  return true;
}

}  // namespace mybot_navigation
