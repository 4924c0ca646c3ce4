// swerve_controller, swerve_module and swerve_odom in one process with one callback thread:
// their 50 Hz messages pass without sockets and without waking another thread. Each keeps
// its own private namespace (/swerve_controller, /swerve_module, /swerve_odom), so the
// parameters are those of the three separate nodes.
#include <ros/ros.h>

#include "mybot_control/ros/params.hpp"
#include "swerve_nodes.hpp"

int main(int argc, char** argv)
{
  return mybot_control::runNode(
      argc, argv, "swerve_chain",
      []
      {
        ros::NodeHandle nh;
        const bool odom = mybot_common::ParamReader(ros::NodeHandle("~")).boolean("odom", true);
        const auto controller = mybot_control_nodes::makeSwerveController(nh, ros::NodeHandle("swerve_controller"));
        const auto module = mybot_control_nodes::makeSwerveModule(nh, ros::NodeHandle("swerve_module"));
        const auto odometry = odom ? mybot_control_nodes::makeSwerveOdom(nh, ros::NodeHandle("swerve_odom")) : nullptr;
        ros::spin();
      });
}
