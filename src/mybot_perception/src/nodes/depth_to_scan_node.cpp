// depth_to_scan: one band of a depth image -> sensor_msgs/LaserScan (depthimage_to_laserscan's
// interface; mybot_perception's README).
#include "mybot_common/ros/node_main.h"

#include "mybot_perception/ros/depth_to_scan.h"

int main(int argc, char** argv)
{
  return mybot_common::runNode(argc, argv, "depth_to_scan",
                               []
                               {
                                 mybot_perception::DepthToScanRos node(ros::NodeHandle(), ros::NodeHandle("~"), true);
                                 ros::spin();
                               });
}
