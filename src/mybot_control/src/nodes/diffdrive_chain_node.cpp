// twist_mux, diffdrive_controller, wheel_controller and diffdrive_odom in one process with
// one callback thread: their 50 Hz messages pass without sockets and without waking other
// processes. Each keeps its own private namespace (/twist_mux, /diffdrive_controller,
// /wheel_controller, /diffdrive_odom), so the parameters are those of the separate nodes.
// ~twist_mux, ~wheel_controller and ~odom (default true) leave a part out, e.g. the wheel
// controller when it runs on the robot.
#include <ros/ros.h>

#include "diffdrive_nodes.hpp"
#include "mybot_control/ros/params.hpp"

int main(int argc, char** argv)
{
  return mybot_control::runNode(
      argc, argv, "diffdrive_chain",
      []
      {
        using namespace mybot_control_nodes;
        ros::NodeHandle nh;
        const mybot_common::ParamReader p(ros::NodeHandle("~"));
        const bool mux = p.boolean("twist_mux", true), wheels = p.boolean("wheel_controller", true),
                   odom = p.boolean("odom", true);
        const auto n1 = mux ? makeTwistMux(nh, ros::NodeHandle("twist_mux")) : nullptr;
        const auto n2 = makeDiffDriveController(nh, ros::NodeHandle("diffdrive_controller"));
        const auto n3 = wheels ? makeWheelController(nh, ros::NodeHandle("wheel_controller")) : nullptr;
        const auto n4 = odom ? makeDiffDriveOdom(nh, ros::NodeHandle("diffdrive_odom")) : nullptr;
        ros::spin();
      });
}
