// twist_mux, diffdrive_controller, wheel_controller and diffdrive_odom as nodelets
// (nodelet_plugins.xml).
#include <pluginlib/class_list_macros.hpp>

#include "diffdrive_nodes.hpp"
#include "nodelet_host.hpp"

namespace mybot_control
{
class TwistMuxNodelet : public NodeletHost<mybot_control_nodes::makeTwistMux>
{
};
class DiffDriveControllerNodelet : public NodeletHost<mybot_control_nodes::makeDiffDriveController>
{
};
class WheelControllerNodelet : public NodeletHost<mybot_control_nodes::makeWheelController>
{
};
class DiffDriveOdomNodelet : public NodeletHost<mybot_control_nodes::makeDiffDriveOdom>
{
};
}  // namespace mybot_control

PLUGINLIB_EXPORT_CLASS(mybot_control::TwistMuxNodelet, nodelet::Nodelet)
PLUGINLIB_EXPORT_CLASS(mybot_control::DiffDriveControllerNodelet, nodelet::Nodelet)
PLUGINLIB_EXPORT_CLASS(mybot_control::WheelControllerNodelet, nodelet::Nodelet)
PLUGINLIB_EXPORT_CLASS(mybot_control::DiffDriveOdomNodelet, nodelet::Nodelet)
