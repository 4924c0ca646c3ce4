// move_base's action server: one goal at a time, as actionlib's SimpleActionServer, but the goal
// that arrives last wins, whatever its stamp.
//
// SimpleActionServer orders goals by the stamp of their goal id and cancels a goal stamped
// before the current one. After ROS time goes back (reset_simulation, a bag played again) every
// new goal is stamped before the aborted one, so it was recalled "because another goal was
// received" until simulated time caught up with the past. ActionServer's cancel-by-stamp memory
// (last_cancel_) has the same flaw. Arrival order is what a user at rviz means, and forget()
// (mybot_lockstep's ActionServer) drops the remembered stamps when time goes back.
//
// Its goal and cancel topics and its status timer go through the lockstep participant
// (mybot_lockstep's ActionServer): in the simulator a goal reaches move_base in the period after
// the client sent it, whatever the machine's load.
#pragma once

#include <functional>
#include <string>

#include <actionlib_msgs/GoalStatus.h>
#include <mybot_lockstep/ros/action_server.h>

namespace mybot_move_base
{
template <class Action>
class GoalServer : public mybot_lockstep::ActionServer<Action>
{
public:
  using Base = mybot_lockstep::ActionServer<Action>;
  using GoalHandle = typename Base::GoalHandle;
  using GoalConstPtr = typename Base::GoalConstPtr;
  using Result = typename Base::Result;
  using Feedback = typename Base::Feedback;

  // on_goal: a new goal is the current one; on_preempt: the current goal is to stop (a client
  // cancelled it, or a new goal arrived), which the owner does and then calls setPreempted.
  GoalServer(ros::NodeHandle nh, const std::string& name, std::function<void(const GoalConstPtr&)> on_goal,
             std::function<void()> on_preempt)
      : Base(nh, name, false), on_goal_(std::move(on_goal)), on_preempt_(std::move(on_preempt))
  {
    this->registerGoalCallback([this](GoalHandle gh) { goalReceived(gh); });
    this->registerCancelCallback([this](GoalHandle gh) { cancelReceived(gh); });
    this->start();
  }

  bool isActive() const
  {
    if (!current_.getGoal())
      return false;
    const auto status = current_.getGoalStatus().status;
    return status == actionlib_msgs::GoalStatus::ACTIVE || status == actionlib_msgs::GoalStatus::PREEMPTING;
  }

  void setSucceeded(const std::string& text)
  {
    finish([&] { current_.setSucceeded(Result(), text); });
  }
  void setAborted(const std::string& text)
  {
    finish([&] { current_.setAborted(Result(), text); });
  }
  void setPreempted()
  {
    finish([&] { current_.setCanceled(Result(), preempt_text_); });
  }
  void publishFeedback(const Feedback& feedback)
  {
    if (isActive())
      current_.publishFeedback(feedback);
  }

private:
  void goalReceived(GoalHandle gh)
  {
    if (isActive())
    {
      // As SimpleActionServer: the owner is told to stop first, and the goal ends preempted with
      // its words, so clients that match on them still do.
      preempt_text_ = "This goal was canceled because another goal was recieved by the simple action server";
      on_preempt_();
      setPreempted();
    }
    gh.setAccepted();
    current_ = gh;
    on_goal_(gh.getGoal());
  }

  void cancelReceived(GoalHandle gh)
  {
    if (isActive() && gh == current_)
    {
      preempt_text_.clear();
      on_preempt_();
    }
  }

  template <class F>
  void finish(F&& f)
  {
    if (!isActive())
      return;
    f();
    current_ = GoalHandle();
  }

  std::function<void(const GoalConstPtr&)> on_goal_;
  std::function<void()> on_preempt_;
  GoalHandle current_;
  std::string preempt_text_;
};
}  // namespace mybot_move_base
