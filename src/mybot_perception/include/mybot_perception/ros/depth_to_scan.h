// depth_to_scan's ROS side, shared by the node and the nodelet: depthimage_to_laserscan's
// interface. Subscribes `image` (16UC1 mm or 32FC1 m) and `camera_info`, publishes `scan`.
// Parameters (its names and defaults): ~scan_height (1 row), ~scan_time (0.033 s), ~range_min
// (0.45 m), ~range_max (10 m), ~output_frame_id ("camera_depth_frame").
#pragma once

#include <ros/ros.h>
#include <sensor_msgs/CameraInfo.h>
#include <sensor_msgs/Image.h>

#include <string>

#include "mybot_perception/depth_to_scan.h"

namespace mybot_perception
{

class DepthToScanRos
{
public:
  // Throws mybot_common::ParamError naming a bad parameter. lockstep: take part in the
  // simulator's lockstep (the node; a nodelet's manager does not take part).
  DepthToScanRos(ros::NodeHandle nh, ros::NodeHandle pnh, bool lockstep);

private:
  void onInfo(const sensor_msgs::CameraInfo& info);
  void onImage(const sensor_msgs::Image::ConstPtr& image);

  ros::NodeHandle nh_;
  DepthToScanParams params_;
  double scan_time_ = 0.033;
  std::string frame_;
  sensor_msgs::CameraInfo::ConstPtr info_;
  ros::Subscriber image_sub_, info_sub_;
  ros::Publisher scan_pub_;
};

}  // namespace mybot_perception
