// depth_to_scan: one band of a depth image -> sensor_msgs/LaserScan (depthimage_to_laserscan's
// interface; mybot_perception's README).
#include <mybot_common/params.h>

#include "mybot_perception/depth_to_scan_ros.h"

int main(int argc, char** argv)
{
  ros::init(argc, argv, "depth_to_scan");
  try
  {
    mybot_perception::DepthToScanRos node(ros::NodeHandle(), ros::NodeHandle("~"), true);
    ros::spin();
  }
  catch (const mybot_common::ParamError& e)
  {
    ROS_FATAL("depth_to_scan: %s", e.what());
    return 1;
  }
  return 0;
}
