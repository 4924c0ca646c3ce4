// swerve_controller, swerve_module and swerve_odom as nodelets (nodelet_plugins.xml).
#include <pluginlib/class_list_macros.hpp>

#include "nodelet_host.hpp"
#include "swerve_nodes.hpp"

namespace mybot_control
{
class SwerveControllerNodelet : public NodeletHost<mybot_control_nodes::makeSwerveController>
{
};
class SwerveModuleNodelet : public NodeletHost<mybot_control_nodes::makeSwerveModule>
{
};
class SwerveOdomNodelet : public NodeletHost<mybot_control_nodes::makeSwerveOdom>
{
};
}  // namespace mybot_control

PLUGINLIB_EXPORT_CLASS(mybot_control::SwerveControllerNodelet, nodelet::Nodelet)
PLUGINLIB_EXPORT_CLASS(mybot_control::SwerveModuleNodelet, nodelet::Nodelet)
PLUGINLIB_EXPORT_CLASS(mybot_control::SwerveOdomNodelet, nodelet::Nodelet)
