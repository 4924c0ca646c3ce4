// The built-in controller types, one family a file in this folder.
#pragma once

#include "mybot_ros_control/ros/controller.h"

namespace mybot_ros_control
{

std::unique_ptr<Controller> makeJointStateController(const ControllerContext& c);
std::unique_ptr<Controller> makeDiffDriveController(const ControllerContext& c);
std::unique_ptr<Controller> makeAckermannSteeringController(const ControllerContext& c);
std::unique_ptr<Controller> makeFourWheelSteeringController(const ControllerContext& c);
// position_controllers / velocity_controllers / effort_controllers JointXController that
// forward the command to the interface.
std::unique_ptr<Controller> makeForwardController(const ControllerContext& c, Interface i);
std::unique_ptr<Controller> makeForwardGroupController(const ControllerContext& c, Interface i);
// effort_controllers/JointPositionController, JointVelocityController,
// velocity_controllers/JointPositionController: a PID from the `pid` parameters.
std::unique_ptr<Controller> makePidController(const ControllerContext& c, Interface output, bool on_position);
std::unique_ptr<Controller> makePidGroupPositionController(const ControllerContext& c, Interface output);
// position_controllers / velocity_controllers / effort_controllers JointTrajectoryController:
// joint_trajectory_controller's splines, `command` topic, follow_joint_trajectory action, state.
std::unique_ptr<Controller> makeTrajectoryController(const ControllerContext& c, Interface i);
// position_controllers / effort_controllers GripperActionController: gripper_action_controller's
// gripper_cmd action on one joint.
std::unique_ptr<Controller> makeGripperActionController(const ControllerContext& c, Interface i);

// control_toolbox::Pid's parameters under `ns` ("pid", "<joint>/pid", "gains/<joint>").
mybot_control::PidConfig readPid(const ControllerContext& c, const std::string& ns, bool angle_wrap);

}  // namespace mybot_ros_control
