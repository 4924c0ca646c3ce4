// actionlib's ActionServer with its goal and cancel topics and its status timer through the
// lockstep participant: under lockstep a goal a client published for period k is handed to
// the server in period k+1, on an idle and on a loaded machine alike, and the status array
// goes out at the whole multiples of its period in sim time. Off lockstep it is actionlib's
// ActionServer: the same topics, queue sizes, parameters and messages.
//
// actionlib::ActionServer subscribes with the NodeHandle it is given, so its goals reach the
// node whenever they arrive; ActionServerBase's bookkeeping (goal handles, status trackers,
// cancel rules) is what this class reuses, and it publishes exactly as ActionServer does.
#pragma once

#include <string>

#include <actionlib/server/action_server_base.h>
#include <actionlib_msgs/GoalStatusArray.h>
#include <ros/ros.h>

#include "mybot_lockstep/ros/participant.h"

namespace mybot_lockstep
{
// Where an ActionServer takes its goal and cancel topics and runs its status timer: through this
// process's lockstep participant. Another wiring (the simulator's controllers are run by the
// coordinator, not a participant) gives the same two members.
struct ParticipantWiring
{
  template <class M, class F>
  ros::Subscriber subscribe(ros::NodeHandle& nh, const std::string& topic, uint32_t queue_size, F cb) const
  {
    return Participant::instance().subscribe<M>(nh, topic, queue_size, cb);
  }
  template <class F>
  Timer timer(ros::NodeHandle& nh, double period, F cb) const
  {
    return Participant::instance().createTimer(nh, period, cb);
  }
};

template <class ActionSpec, class Wiring = ParticipantWiring>
class ActionServer : public actionlib::ActionServerBase<ActionSpec>
{
public:
  using Base = actionlib::ActionServerBase<ActionSpec>;
  ACTION_DEFINITION(ActionSpec)

  // As actionlib::ActionServer(n, name, auto_start): topics under `name` in `n`'s namespace.
  ActionServer(ros::NodeHandle n, const std::string& name, bool auto_start, Wiring wiring = Wiring())
      : Base(boost::function<void(typename Base::GoalHandle)>(), boost::function<void(typename Base::GoalHandle)>(),
             auto_start),
        node_(n, name),
        wiring_(std::move(wiring))
  {
    if (this->started_)
    {
      initialize();
      publishStatus();
    }
  }

  ~ActionServer() override = default;

  // Time went back (reset_simulation, a bag played again): the stamps remembered from before (the
  // last cancel request's) belong to a past that did not happen; without this, every new goal
  // stamped before it is cancelled as soon as it arrives.
  void forget()
  {
    boost::recursive_mutex::scoped_lock lock(this->lock_);
    this->last_cancel_ = ros::Time();
  }

  // The status array, now: for a wiring whose timer() makes none (the simulator's controllers
  // publish it from their update, at whole multiples of the status period in sim time).
  void publishStatusNow() { publishStatus(); }

private:
  void initialize() override
  {
    // actionlib's parameters and defaults (action_server_imp.h).
    int pub_queue_size = 50, sub_queue_size = 50;
    node_.param("actionlib_server_pub_queue_size", pub_queue_size, 50);
    node_.param("actionlib_server_sub_queue_size", sub_queue_size, 50);
    if (pub_queue_size < 0)
      pub_queue_size = 50;
    if (sub_queue_size < 0)
      sub_queue_size = 50;
    result_pub_ = node_.advertise<ActionResult>("result", static_cast<uint32_t>(pub_queue_size));
    feedback_pub_ = node_.advertise<ActionFeedback>("feedback", static_cast<uint32_t>(pub_queue_size));
    status_pub_ =
        node_.advertise<actionlib_msgs::GoalStatusArray>("status", static_cast<uint32_t>(pub_queue_size), true);

    double status_frequency = 5.0, status_list_timeout = 5.0;
    std::string freq_name;
    if (node_.searchParam("actionlib_status_frequency", freq_name))
      node_.param(freq_name, status_frequency, 5.0);
    node_.param("status_list_timeout", status_list_timeout, 5.0);
    this->status_list_timeout_ = ros::Duration(status_list_timeout);

    if (status_frequency > 0)
      status_timer_ = wiring_.timer(node_, 1.0 / status_frequency, [this](const ros::TimerEvent&) { publishStatus(); });
    goal_sub_ = wiring_.template subscribe<ActionGoal>(node_, "goal", static_cast<uint32_t>(sub_queue_size),
                                                       [this](const ActionGoalConstPtr& g) { this->goalCallback(g); });
    cancel_sub_ = wiring_.template subscribe<actionlib_msgs::GoalID>(
        node_, "cancel", static_cast<uint32_t>(sub_queue_size),
        [this](const actionlib_msgs::GoalID::ConstPtr& c) { this->cancelCallback(c); });
  }

  void publishResult(const actionlib_msgs::GoalStatus& status, const Result& result) override
  {
    boost::recursive_mutex::scoped_lock lock(this->lock_);
    boost::shared_ptr<ActionResult> ar(new ActionResult);
    ar->header.stamp = ros::Time::now();
    ar->status = status;
    ar->result = result;
    result_pub_.publish(ar);
    publishStatus();
  }

  void publishFeedback(const actionlib_msgs::GoalStatus& status, const Feedback& feedback) override
  {
    boost::recursive_mutex::scoped_lock lock(this->lock_);
    boost::shared_ptr<ActionFeedback> af(new ActionFeedback);
    af->header.stamp = ros::Time::now();
    af->status = status;
    af->feedback = feedback;
    feedback_pub_.publish(af);
  }

  // The status of every goal still tracked; a goal whose handles are all gone is forgotten
  // status_list_timeout after that, as in actionlib.
  void publishStatus() override
  {
    boost::recursive_mutex::scoped_lock lock(this->lock_);
    if (!this->started_)
      return;
    actionlib_msgs::GoalStatusArray status_array;
    status_array.header.stamp = ros::Time::now();
    status_array.status_list.reserve(this->status_list_.size());
    for (auto it = this->status_list_.begin(); it != this->status_list_.end();)
    {
      status_array.status_list.push_back(it->status_);
      if (it->handle_destruction_time_ != ros::Time() &&
          it->handle_destruction_time_ + this->status_list_timeout_ < ros::Time::now())
        it = this->status_list_.erase(it);
      else
        ++it;
    }
    status_pub_.publish(status_array);
  }

  ros::NodeHandle node_;
  Wiring wiring_;
  ros::Publisher status_pub_, result_pub_, feedback_pub_;
  ros::Subscriber goal_sub_, cancel_sub_;
  Timer status_timer_;
};
}  // namespace mybot_lockstep
