// joint_trajectory_controller (ros_controllers, Noetic): position_controllers/,
// velocity_controllers/ and effort_controllers/JointTrajectoryController. A trajectory arrives on
// `command` (trajectory_msgs/JointTrajectory) or as a `follow_joint_trajectory` action goal (the
// fields of control_msgs/FollowJointTrajectory, here mybot_gazebo_lite's), is spliced onto the one
// being followed at the moment it takes over (mybot_ros_control/joint_trajectory.h), and the
// joints follow its samples: the position itself, or a PID from `gains/<joint>` on the position
// error (with the desired velocity fed forward on a velocity joint by `velocity_ff/<joint>`). A
// goal is checked against `constraints` (path tolerance while it runs, goal tolerance and
// `stopped_velocity_tolerance` at its end, within `goal_time`; a goal's own position and velocity
// tolerances per joint over those) and ends with
// FollowJointTrajectory's error codes and a text naming the joint and the figure. `state`
// (JointTrajectoryControllerState) and `query_state` as upstream.
#include "controllers.h"
#include "sim_action_wiring.h"

#include "mybot_ros_control/joint_trajectory.h"

#include <control_msgs/FollowJointTrajectoryAction.h>
#include <control_msgs/JointTrajectoryControllerState.h>
#include <control_msgs/QueryTrajectoryState.h>
#include <trajectory_msgs/JointTrajectory.h>

#include <algorithm>
#include <cmath>
#include <optional>
#include <sstream>

namespace mybot_ros_control
{

namespace
{

using Action = control_msgs::FollowJointTrajectoryAction;
using Result = control_msgs::FollowJointTrajectoryResult;
using Server = SimActionServer<Action>;
using GoalHandle = Server::GoalHandle;

std::string str(double v)
{
  std::ostringstream s;
  s << v;
  return s.str();
}

class TrajectoryController : public Controller
{
public:
  TrajectoryController(const ControllerContext& c, Interface i) : name_(c.name), interface_(i), hw_(c.hw)
  {
    names_ = c.stringList("joints", true);
    if (names_.empty())
      c.fail("joints", "no joints");
    const double stopped_velocity_tolerance = c.nonNegative("constraints/stopped_velocity_tolerance", 0.01);
    for (const std::string& n : names_)
    {
      if (std::count(names_.begin(), names_.end(), n) > 1)
        c.fail("joints", "joint '" + n + "' is listed twice");
      SimJoint& j = c.joint("joints", n, i);
      joints_.push_back(&j);
      wrap_.push_back(j.continuous);
      claimed_[interfaceName(i)].push_back(n);
      const std::string tol = "constraints/" + n + "/";
      // Upstream's defaults: a position tolerance on the path, and at the goal a position one
      // and stopped_velocity_tolerance on the velocity.
      default_tolerances_.path.push_back({c.nonNegative(tol + "trajectory", 0.0), 0.0, 0.0});
      default_tolerances_.goal.push_back({c.nonNegative(tol + "goal", 0.0), stopped_velocity_tolerance, 0.0});
      if (i != Interface::POSITION)
      {
        pids_.emplace_back();
        pids_.back().setConfig(readPid(c, "gains/" + n, j.continuous));
        velocity_ff_.push_back(c.number("velocity_ff/" + n, 0.0));
      }
    }
    default_tolerances_.goal_time = c.nonNegative("constraints/goal_time", 0.0);
    stop_duration_ = c.nonNegative("stop_trajectory_duration", 0.0);
    state_period_ = 1.0 / c.positive("state_publish_rate", 50.0);
    monitor_period_ = 1.0 / c.positive("action_monitor_rate", 20.0);
    allow_partial_ = c.boolean("allow_partial_joints_goal", false);

    ros::NodeHandle nh = c.nh;
    state_pub_ = nh.advertise<control_msgs::JointTrajectoryControllerState>("state", 1);
    command_sub_ = mybot_gazebo_lite::subscribeCommand<trajectory_msgs::JointTrajectory>(
        *c.plugin, nh, "command", [this](const trajectory_msgs::JointTrajectory::ConstPtr& m) { onCommand(*m); });
    query_srv_ =
        nh.advertiseService<control_msgs::QueryTrajectoryState::Request, control_msgs::QueryTrajectoryState::Response>(
            "query_state", [this](auto& req, auto& res) { return onQuery(req, res); });
    server_ = std::make_unique<Server>(nh, "follow_joint_trajectory", false, SimActionWiring{c.plugin});
    server_->registerGoalCallback([this](GoalHandle gh) { onGoal(gh); });
    server_->registerCancelCallback([this](GoalHandle gh) { onCancel(gh); });
    server_->start();
  }

  void starting(double t) override
  {
    // A simulation reset restarts the controllers at an earlier time: a cancel remembered from
    // before would recall every new goal (their stamps are earlier).
    if (t < now_)
      server_->forget();
    // Holding where the joints are, as upstream's controller starts.
    now_ = t;
    running_ = true;
    trajectory_ = JointTrajectory::hold(t, actual().positions);
    for (SimJoint* j : joints_)
      hw_->claim(*j, interface_);
    for (auto& p : pids_)
      p.reset();
    next_state_ = next_monitor_ = next_status_ = t;
  }

  void update(double t, double dt) override
  {
    if (t < now_)  // time went back without a restart: nothing is to move, and the past is gone
    {
      server_->forget();
      endGoal(Result::GOAL_TOLERANCE_VIOLATED, "the simulation was reset (time went back)", false);
      trajectory_ = JointTrajectory::hold(t, actual().positions);
      next_state_ = next_monitor_ = next_status_ = t;
    }
    now_ = t;
    const TrajectorySample desired = trajectory_.sample(t);
    const TrajectorySample now = actual();
    for (size_t k = 0; k < joints_.size(); ++k)
    {
      SimJoint& j = *joints_[k];
      if (interface_ == Interface::POSITION)
        j.command = desired.positions[k];
      else
      {
        const double feedback = pids_[k].compute(desired.positions[k], j.position, dt);
        j.command = interface_ == Interface::VELOCITY ? velocity_ff_[k] * desired.velocities[k] + feedback : feedback;
      }
    }
    if (goal_)
      monitor(t, desired, now);
    if (t >= next_state_)
    {
      publishState(t, desired, now);
      next_state_ = nextTick(t, state_period_);
    }
    if (t >= next_status_)
    {
      server_->publishStatusNow();
      next_status_ = nextTick(t, kActionStatusPeriod);
    }
  }

  void stopping(double) override
  {
    endGoal(Result::GOAL_TOLERANCE_VIOLATED, "the controller was stopped (or restarted by a simulation reset)", false);
    running_ = false;
    for (SimJoint* j : joints_)
      j->command = interface_ == Interface::POSITION ? j->position : 0.0;
  }

private:
  TrajectorySample actual() const
  {
    TrajectorySample s;
    for (const SimJoint* j : joints_)
    {
      s.positions.push_back(j->position);
      s.velocities.push_back(j->velocity);
      s.accelerations.push_back(0.0);
    }
    return s;
  }

  // A trajectory message as points in this controller's joint order and absolute times, or why
  // not (FollowJointTrajectory's error code and a text naming the joint or the point).
  struct Checked
  {
    std::vector<TrajectoryPoint> points;
    double start = 0.0;  // when the trajectory takes over (its header stamp; 0: on receipt)
    int code = Result::SUCCESSFUL;
    std::string error;
  };
  Checked check(const trajectory_msgs::JointTrajectory& msg) const
  {
    Checked out;
    auto fail = [&out](int code, const std::string& why)
    {
      out.code = code;
      out.error = why;
      return out;
    };
    std::vector<int> index(names_.size(), -1);  // our joint k -> its column in the message
    for (size_t m = 0; m < msg.joint_names.size(); ++m)
    {
      const auto it = std::find(names_.begin(), names_.end(), msg.joint_names[m]);
      if (it == names_.end())
        return fail(Result::INVALID_JOINTS,
                    "joint '" + msg.joint_names[m] + "' is not one of this controller's (" + joinNames() + ")");
      int& slot = index[static_cast<size_t>(it - names_.begin())];
      if (slot >= 0)
        return fail(Result::INVALID_JOINTS, "joint '" + msg.joint_names[m] + "' is named twice");
      slot = static_cast<int>(m);
    }
    for (size_t k = 0; k < names_.size(); ++k)
      if (index[k] < 0 && !allow_partial_ && !msg.points.empty())
        return fail(Result::INVALID_JOINTS,
                    "the trajectory leaves out joint '" + names_[k] + "' (allow_partial_joints_goal is false)");
    const double start = msg.header.stamp.isZero() ? now_ : msg.header.stamp.toSec();
    out.start = start;
    const size_t n = msg.joint_names.size();
    for (size_t p = 0; p < msg.points.size(); ++p)
    {
      const trajectory_msgs::JointTrajectoryPoint& q = msg.points[p];
      const std::string at = "point " + std::to_string(p) + ": ";
      if (q.positions.size() != n)
        return fail(Result::INVALID_GOAL,
                    at + std::to_string(q.positions.size()) + " positions for " + std::to_string(n) + " joints");
      if (!q.velocities.empty() && q.velocities.size() != n)
        return fail(Result::INVALID_GOAL,
                    at + std::to_string(q.velocities.size()) + " velocities for " + std::to_string(n) + " joints");
      if (!q.accelerations.empty() && q.accelerations.size() != n)
        return fail(Result::INVALID_GOAL, at + std::to_string(q.accelerations.size()) + " accelerations for " +
                                              std::to_string(n) + " joints");
      for (const auto* v : {&q.positions, &q.velocities, &q.accelerations})
        for (double x : *v)
          if (!std::isfinite(x))
            return fail(Result::INVALID_GOAL, at + "a value is not finite");
      if (p > 0 && !(q.time_from_start > msg.points[p - 1].time_from_start))
        return fail(Result::INVALID_GOAL, at + "time_from_start " + str(q.time_from_start.toSec()) +
                                              " s is not after the point before's " +
                                              str(msg.points[p - 1].time_from_start.toSec()) + " s");
      TrajectoryPoint tp;
      tp.time = start + q.time_from_start.toSec();
      // A joint the message leaves out follows the trajectory it had (allow_partial_joints_goal).
      const TrajectorySample kept = n < names_.size() ? trajectory_.sample(tp.time) : TrajectorySample();
      const bool vel = !q.velocities.empty(), acc = vel && !q.accelerations.empty();
      for (size_t k = 0; k < names_.size(); ++k)
      {
        const int m = index[k];
        tp.positions.push_back(m >= 0 ? q.positions[static_cast<size_t>(m)] : kept.positions[k]);
        if (vel)
          tp.velocities.push_back(m >= 0 ? q.velocities[static_cast<size_t>(m)] : kept.velocities[k]);
        if (acc)
          tp.accelerations.push_back(m >= 0 ? q.accelerations[static_cast<size_t>(m)] : kept.accelerations[k]);
      }
      out.points.push_back(std::move(tp));
    }
    if (!out.points.empty() && out.points.back().time < now_)
      return fail(Result::OLD_HEADER_TIMESTAMP,
                  "the trajectory ends at " + str(out.points.back().time) + " s, before now (" + str(now_) + " s)");
    return out;
  }

  std::string joinNames() const
  {
    std::string s;
    for (const std::string& n : names_)
      s += (s.empty() ? "" : ", ") + n;
    return s;
  }

  // Follows `points` from `start` on (the current trajectory until then, as upstream); an empty
  // trajectory stops where the setpoint is.
  void follow(const std::vector<TrajectoryPoint>& points, double start)
  {
    trajectory_.forgetBefore(now_);
    trajectory_ = points.empty() ? trajectory_.stopAt(now_, stop_duration_)
                                 : trajectory_.splice(std::max(now_, start), points, wrap_);
  }

  void onCommand(const trajectory_msgs::JointTrajectory& msg)
  {
    if (!running_)
    {
      ROS_ERROR("%s: trajectory on command ignored: the controller is not running", name_.c_str());
      return;
    }
    const Checked c = check(msg);
    if (c.code != Result::SUCCESSFUL)
    {
      ROS_ERROR("%s: trajectory on command ignored: %s", name_.c_str(), c.error.c_str());
      return;
    }
    endGoal(Result::SUCCESSFUL, "replaced by a trajectory on the command topic", true);
    follow(c.points, c.start);
  }

  void onGoal(GoalHandle gh)
  {
    const auto& goal = *gh.getGoal();
    Checked c = check(goal.trajectory);
    Tolerances tol = default_tolerances_;
    if (c.code == Result::SUCCESSFUL)
    {
      c.error = readTolerances(goal, tol);
      if (!c.error.empty())
        c.code = Result::INVALID_GOAL;
    }
    if (c.code == Result::SUCCESSFUL && !running_)
    {
      c.code = Result::INVALID_GOAL;
      c.error = "the controller is not running";
    }
    if (c.code != Result::SUCCESSFUL)
    {
      Result r;
      r.error_code = c.code;
      r.error_string = c.error;
      ROS_ERROR("%s: goal rejected: %s", name_.c_str(), c.error.c_str());
      gh.setRejected(r, c.error);
      return;
    }
    endGoal(Result::SUCCESSFUL, "replaced by a new goal", true);
    gh.setAccepted();
    follow(c.points, c.start);
    if (c.points.empty())  // upstream: an empty trajectory stops the joints, and that is the goal
    {
      Result r;
      r.error_string = "an empty trajectory: the joints stop";
      gh.setSucceeded(r, r.error_string);
      return;
    }
    goal_ = gh;
    tolerances_ = tol;
    next_monitor_ = now_;
  }

  void onCancel(GoalHandle gh)
  {
    if (!goal_ || !(*goal_ == gh))
      return;
    trajectory_ = trajectory_.stopAt(now_, stop_duration_);
    Result r;
    r.error_string = "cancelled";
    goal_->setCanceled(r, r.error_string);
    goal_.reset();
  }

  // control_msgs/JointTolerance's three figures; 0: not checked.
  struct StateTolerance
  {
    double position = 0.0, velocity = 0.0, acceleration = 0.0;
  };
  struct Tolerances
  {
    std::vector<StateTolerance> path, goal;  // per joint
    double goal_time = 0.0;
  };
  // The goal's own tolerances over the defaults, figure by figure as upstream: > 0 replaces, < 0
  // (-1 by convention) removes, 0 keeps the default.
  std::string readTolerances(const control_msgs::FollowJointTrajectoryGoal& goal, Tolerances& tol) const
  {
    for (const auto* list : {&goal.path_tolerance, &goal.goal_tolerance})
      for (const auto& jt : *list)
      {
        const auto it = std::find(names_.begin(), names_.end(), jt.name);
        if (it == names_.end())
          return "a tolerance for joint '" + jt.name + "', which is not one of this controller's (" + joinNames() + ")";
        StateTolerance& t =
            (list == &goal.path_tolerance ? tol.path : tol.goal)[static_cast<size_t>(it - names_.begin())];
        const std::pair<double, double*> figures[] = {
            {jt.position, &t.position}, {jt.velocity, &t.velocity}, {jt.acceleration, &t.acceleration}};
        for (const auto& [value, into] : figures)
        {
          if (!std::isfinite(value))
            return "joint '" + jt.name + "''s tolerance is not finite";
          if (value > 0.0)
            *into = value;
          else if (value < 0.0)
            *into = 0.0;
        }
      }
    if (!goal.goal_time_tolerance.isZero())
      tol.goal_time = std::max(0.0, goal.goal_time_tolerance.toSec());
    return "";
  }

  // Why joint k is outside `tol` (its path tolerance, or its goal tolerance at the end), or "". The
  // acceleration is not measured: its error is 0, as upstream sets it, so an acceleration
  // tolerance never fails.
  std::string violation(size_t k, const StateTolerance& tol, bool path, const TrajectorySample& desired,
                        const TrajectorySample& now) const
  {
    const std::string kind = path ? "path" : "goal";
    const double position_error = std::abs(desired.positions[k] - now.positions[k]);
    const double velocity_error = std::abs(desired.velocities[k] - now.velocities[k]);
    if (tol.position > 0.0 && position_error > tol.position)
      return "joint '" + names_[k] + "' is " + str(position_error) + " from its " + (path ? "setpoint" : "goal") +
             ", over its " + kind + " tolerance " + str(tol.position);
    if (tol.velocity > 0.0 && velocity_error > tol.velocity)
      return "joint '" + names_[k] + "' moves at " + str(now.velocities[k]) + " where its setpoint moves at " +
             str(desired.velocities[k]) + ", over its " + kind + " velocity tolerance " + str(tol.velocity);
    return "";
  }

  void monitor(double t, const TrajectorySample& desired, const TrajectorySample& now)
  {
    if (t >= next_monitor_)
    {
      control_msgs::FollowJointTrajectoryFeedback fb;
      fill(fb, t, desired, now);
      goal_->publishFeedback(fb);
      next_monitor_ = nextTick(t, monitor_period_);
    }
    const double end = trajectory_.endTime();
    if (t < end)
    {
      for (size_t k = 0; k < joints_.size(); ++k)
      {
        const std::string why = violation(k, tolerances_.path[k], true, desired, now);
        if (!why.empty())
        {
          trajectory_ = JointTrajectory::stopFrom(t, now, stop_duration_);
          endGoal(Result::PATH_TOLERANCE_VIOLATED, why + " at " + str(t) + " s", false);
          return;
        }
      }
      return;
    }
    std::string outside;
    for (size_t k = 0; k < joints_.size() && outside.empty(); ++k)
      outside = violation(k, tolerances_.goal[k], false, desired, now);
    if (outside.empty())
      endGoal(Result::SUCCESSFUL, "", true);
    else if (t >= end + tolerances_.goal_time)
    {
      trajectory_ = JointTrajectory::stopFrom(t, now, stop_duration_);
      endGoal(Result::GOAL_TOLERANCE_VIOLATED,
              outside + ", " + str(t - end) + " s after the trajectory's end (goal_time " + str(tolerances_.goal_time) +
                  " s)",
              false);
    }
  }

  // Ends the active goal, if any: succeeded (also when a new trajectory replaces it, as a
  // preemption upstream reports it cancelled) or aborted with `code`.
  void endGoal(int code, const std::string& why, bool ok)
  {
    if (!goal_)
      return;
    Result r;
    r.error_code = code;
    r.error_string = why;
    if (!ok)
    {
      ROS_WARN("%s: goal aborted: %s", name_.c_str(), why.c_str());
      goal_->setAborted(r, why);
    }
    else if (code == Result::SUCCESSFUL && why.empty())
      goal_->setSucceeded(r, "");
    else
      goal_->setCanceled(r, why);
    goal_.reset();
  }

  template <class M>
  void fill(M& m, double t, const TrajectorySample& desired, const TrajectorySample& now) const
  {
    m.header.stamp = ros::Time(t);
    m.joint_names = names_;
    m.desired.positions = desired.positions;
    m.desired.velocities = desired.velocities;
    m.desired.accelerations = desired.accelerations;
    m.actual.positions = now.positions;
    m.actual.velocities = now.velocities;
    for (size_t k = 0; k < names_.size(); ++k)
    {
      m.error.positions.push_back(desired.positions[k] - now.positions[k]);
      m.error.velocities.push_back(desired.velocities[k] - now.velocities[k]);
    }
  }

  void publishState(double t, const TrajectorySample& desired, const TrajectorySample& now)
  {
    control_msgs::JointTrajectoryControllerState s;
    fill(s, t, desired, now);
    state_pub_.publish(s);
  }

  bool onQuery(control_msgs::QueryTrajectoryState::Request& req, control_msgs::QueryTrajectoryState::Response& res)
  {
    const TrajectorySample s = trajectory_.sample(req.time.toSec());
    res.name = names_;
    res.position = s.positions;
    res.velocity = s.velocities;
    res.acceleration = s.accelerations;
    return true;
  }

  std::string name_;
  Interface interface_;
  RobotHWSim* hw_;
  std::vector<std::string> names_;
  std::vector<SimJoint*> joints_;
  std::vector<bool> wrap_;
  std::vector<mybot_control::Pid> pids_;
  std::vector<double> velocity_ff_;
  Tolerances default_tolerances_;
  double stop_duration_ = 0.0;
  double state_period_ = 0.02, monitor_period_ = 0.05;
  bool allow_partial_ = false;
  bool running_ = false;

  JointTrajectory trajectory_;
  double now_ = 0.0, next_state_ = 0.0, next_monitor_ = 0.0, next_status_ = 0.0;
  std::optional<GoalHandle> goal_;
  Tolerances tolerances_;
  ros::Publisher state_pub_;
  ros::Subscriber command_sub_;
  ros::ServiceServer query_srv_;
  std::unique_ptr<Server> server_;
};

}  // namespace

std::unique_ptr<Controller> makeTrajectoryController(const ControllerContext& c, Interface i)
{
  return std::make_unique<TrajectoryController>(c, i);
}

}  // namespace mybot_ros_control
