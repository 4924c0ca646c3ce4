// gripper_action_controller (ros_controllers, Noetic): position_controllers/ and
// effort_controllers/GripperActionController. One joint; a `gripper_cmd` action goal (the fields of
// control_msgs/GripperCommand, here mybot_gazebo_lite's) commands its position and the most effort
// to use. The position type commands the position itself (max_effort is only reported back, as
// upstream); the effort type drives a PID from `gains/<joint>` on the position error, its output
// clamped to the goal's max_effort (0: unclamped). The goal ends as mybot_ros_control/
// gripper_goal.h decides: succeeded with `reached_goal` within goal_tolerance, or aborted with
// `stalled` once the joint rests short of it for stall_timeout, still pushing with max_effort (a
// grasp holds). A cancel holds where the joint is, with the default max_effort.
#include "controllers.h"
#include "sim_action_wiring.h"

#include "mybot_ros_control/gripper_goal.h"

#include <control_msgs/GripperCommandAction.h>

#include <algorithm>
#include <cmath>
#include <optional>
#include <sstream>

namespace mybot_ros_control
{

namespace
{

using Action = control_msgs::GripperCommandAction;
using Result = control_msgs::GripperCommandResult;
using Server = SimActionServer<Action>;
using GoalHandle = Server::GoalHandle;

class GripperActionController : public Controller
{
public:
  GripperActionController(const ControllerContext& c, Interface i) : name_(c.name), interface_(i), hw_(c.hw)
  {
    const std::string joint = c.requiredString("joint");
    joint_ = &c.joint("joint", joint, i);
    claimed_[interfaceName(i)].push_back(joint);
    GripperGoalParams p;
    // Upstream takes the absolute value of goal_tolerance and max_effort; a negative one here is
    // more likely a slip than a wish, and is refused naming it.
    p.goal_tolerance = c.nonNegative("goal_tolerance", 0.01);
    p.stall_velocity_threshold = c.nonNegative("stall_velocity_threshold", 0.001);
    p.stall_timeout = c.nonNegative("stall_timeout", 1.0);
    monitor_ = GripperGoalMonitor(p);
    default_max_effort_ = c.nonNegative("max_effort", 0.0);
    monitor_period_ = 1.0 / c.positive("action_monitor_rate", 20.0);
    if (i == Interface::EFFORT)
      pid_.setConfig(readPid(c, "gains/" + joint, joint_->continuous));

    ros::NodeHandle nh = c.nh;
    server_ = std::make_unique<Server>(nh, "gripper_cmd", false, SimActionWiring{c.plugin});
    server_->registerGoalCallback([this](GoalHandle gh) { onGoal(gh); });
    server_->registerCancelCallback([this](GoalHandle gh) { onCancel(gh); });
    server_->start();
  }

  void starting(double t) override
  {
    if (t < now_)  // a simulation reset: a cancel remembered from before would recall new goals
      server_->forget();
    now_ = t;
    running_ = true;
    hold();
    hw_->claim(*joint_, interface_);
    pid_.reset();
    next_monitor_ = next_status_ = t;
  }

  void update(double t, double dt) override
  {
    if (t < now_)  // time went back without a restart: nothing is to move, and the past is gone
    {
      server_->forget();
      endGoal("the simulation was reset (time went back)");
      hold();
      next_monitor_ = next_status_ = t;
    }
    now_ = t;
    if (interface_ == Interface::POSITION)
    {
      joint_->command = target_;
      effort_ = max_effort_;  // what upstream's position adapter reports
    }
    else
    {
      double u = pid_.compute(target_, joint_->position, dt);
      if (max_effort_ > 0.0)
        u = std::max(-max_effort_, std::min(max_effort_, u));
      joint_->command = effort_ = u;
    }
    if (goal_)
      monitor(t);
    if (t >= next_status_)
    {
      server_->publishStatusNow();
      next_status_ = nextTick(t, kActionStatusPeriod);
    }
  }

  void stopping(double) override
  {
    endGoal("the controller was stopped (or restarted by a simulation reset)");
    running_ = false;
    joint_->command = interface_ == Interface::POSITION ? joint_->position : 0.0;
  }

private:
  // Holds where the joint is, with the default max_effort (starting, a cancel, a reset).
  void hold()
  {
    target_ = joint_->position;
    max_effort_ = default_max_effort_;
  }

  void onGoal(GoalHandle gh)
  {
    const auto& cmd = gh.getGoal()->command;
    std::string why;
    if (!std::isfinite(cmd.position))
      why = "command.position is not finite";
    else if (!std::isfinite(cmd.max_effort))
      why = "command.max_effort is not finite";
    else if (!running_)
      why = "the controller is not running";
    if (!why.empty())
    {
      ROS_ERROR("%s: goal rejected: %s", name_.c_str(), why.c_str());
      gh.setRejected(result(false, false), why);
      return;
    }
    if (goal_)  // upstream preempts the running goal: it ends cancelled
    {
      goal_->setCanceled(result(false, false), "replaced by a new goal");
      goal_.reset();
    }
    gh.setAccepted();
    target_ = cmd.position;
    max_effort_ = std::abs(cmd.max_effort);
    monitor_.start(now_);
    goal_ = gh;
    next_monitor_ = now_;
  }

  void onCancel(GoalHandle gh)
  {
    if (!goal_ || !(*goal_ == gh))
      return;
    hold();
    goal_->setCanceled(result(false, false), "cancelled");
    goal_.reset();
  }

  // The result, or the feedback (the same fields).
  template <class M = Result>
  M result(bool reached, bool stalled) const
  {
    M r;
    r.position = joint_->position;
    r.effort = effort_;
    r.reached_goal = reached;
    r.stalled = stalled;
    return r;
  }

  void monitor(double t)
  {
    const GripperGoalState s = monitor_.update(t, target_, joint_->position, joint_->velocity);
    if (t >= next_monitor_)
    {
      goal_->publishFeedback(
          result<control_msgs::GripperCommandFeedback>(s == GripperGoalState::REACHED, s == GripperGoalState::STALLED));
      next_monitor_ = nextTick(t, monitor_period_);
    }
    if (s == GripperGoalState::REACHED)
    {
      goal_->setSucceeded(result(true, false), "");
      goal_.reset();
    }
    else if (s == GripperGoalState::STALLED)
    {
      std::ostringstream why;
      why << "stalled at " << joint_->position << ", " << std::abs(target_ - joint_->position)
          << " from the command, at rest for over stall_timeout " << monitor_.params().stall_timeout << " s";
      ROS_WARN("%s: goal aborted: %s", name_.c_str(), why.str().c_str());
      goal_->setAborted(result(false, true), why.str());
      goal_.reset();
    }
  }

  void endGoal(const std::string& why)
  {
    if (!goal_)
      return;
    ROS_WARN("%s: goal aborted: %s", name_.c_str(), why.c_str());
    goal_->setAborted(result(false, false), why);
    goal_.reset();
  }

  std::string name_;
  Interface interface_;
  RobotHWSim* hw_;
  SimJoint* joint_ = nullptr;
  GripperGoalMonitor monitor_;
  mybot_control::Pid pid_;
  double default_max_effort_ = 0.0, monitor_period_ = 0.05;
  bool running_ = false;

  double target_ = 0.0, max_effort_ = 0.0, effort_ = 0.0;
  double now_ = 0.0, next_monitor_ = 0.0, next_status_ = 0.0;
  std::optional<GoalHandle> goal_;
  std::unique_ptr<Server> server_;
};

}  // namespace

std::unique_ptr<Controller> makeGripperActionController(const ControllerContext& c, Interface i)
{
  return std::make_unique<GripperActionController>(c, i);
}

}  // namespace mybot_ros_control
