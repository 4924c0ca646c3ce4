// Twist multiplexer with twist_mux's YAML (~topics, ~locks: name, topic, timeout, priority).
// Output cmd_vel. Unlike upstream, losing the active input publishes one zero twist
// (~publish_zero_on_timeout), so nothing keeps moving on a stale command.
#include <diagnostic_msgs/DiagnosticArray.h>
#include <geometry_msgs/Twist.h>
#include <mybot_lockstep/ros/participant.h>
#include <ros/ros.h>
#include <std_msgs/Bool.h>
#include <std_msgs/String.h>

#include "diffdrive_nodes.hpp"
#include "mybot_control/ros/params.hpp"
#include "mybot_control/twist_mux.hpp"

using namespace mybot_control;

namespace
{
// Accepts the list form [{name, topic, timeout, priority}, ...] and the map form
// {name: {topic, timeout, priority}} that twist_mux also reads.
std::vector<MuxSource> loadSources(const ParamReader& p, const std::string& key, bool required)
{
  std::vector<MuxSource> out;
  XmlRpc::XmlRpcValue v;
  if (!p.nh().getParam(key, v))
  {
    if (required)
      p.fail(key, "is required: a list of {name, topic, timeout, priority}");
    return out;
  }
  auto parse = [&](XmlRpc::XmlRpcValue& e, const std::string& where, const std::string& name_from_key)
  {
    if (e.getType() != XmlRpc::XmlRpcValue::TypeStruct)
      p.fail(where, "must be a mapping with name, topic, timeout, priority");
    MuxSource s;
    s.name = name_from_key;
    for (const char* field : {"name", "topic", "timeout", "priority"})
    {
      if (!e.hasMember(field))
      {
        if (std::string(field) == "name" && !name_from_key.empty())
          continue;
        p.fail(where, std::string("has no '") + field + "'");
      }
      XmlRpc::XmlRpcValue& f = e[field];
      const std::string fw = where + "." + field;
      if (std::string(field) == "name" || std::string(field) == "topic")
      {
        if (f.getType() != XmlRpc::XmlRpcValue::TypeString)
          p.fail(fw, "must be a string");
        (std::string(field) == "name" ? s.name : s.topic) = static_cast<std::string>(f);
      }
      else if (std::string(field) == "timeout")
      {
        if (f.getType() == XmlRpc::XmlRpcValue::TypeDouble)
          s.timeout = static_cast<double>(f);
        else if (f.getType() == XmlRpc::XmlRpcValue::TypeInt)
          s.timeout = static_cast<int>(f);
        else
          p.fail(fw, "must be a number (s)");
      }
      else
      {
        if (f.getType() != XmlRpc::XmlRpcValue::TypeInt)
          p.fail(fw, "must be an integer in [0, 255]");
        s.priority = static_cast<int>(f);
      }
    }
    out.push_back(s);
  };
  if (v.getType() == XmlRpc::XmlRpcValue::TypeArray)
  {
    for (int k = 0; k < v.size(); ++k)
      parse(v[k], key + "[" + std::to_string(k) + "]", "");
  }
  else if (v.getType() == XmlRpc::XmlRpcValue::TypeStruct)
  {
    for (auto& kv : v)
      parse(kv.second, key + "/" + kv.first, kv.first);
  }
  else
  {
    p.fail(key, "must be a list of {name, topic, timeout, priority}");
  }
  return out;
}

class TwistMuxNode
{
public:
  TwistMuxNode(const ros::NodeHandle& nh, const ros::NodeHandle& pnh) : nh_(nh), pnh_(pnh)
  {
    const ParamReader p(pnh_);
    for (const auto& s : loadSources(p, "topics", true))
      mux_.addTopic(s);
    for (const auto& s : loadSources(p, "locks", false))
      mux_.addLock(s);
    const std::string err = mux_.validate();
    if (!err.empty())
      throw ParamError("parameter " + p.full("") + "/" + err);
    zero_on_timeout_ = p.boolean("publish_zero_on_timeout", true);
    const double check_rate = p.positive("check_rate", 50.0);
    const double diag_rate = p.positive("diagnostics_rate", 1.0);

    out_pub_ = nh_.advertise<geometry_msgs::Twist>("cmd_vel", 10);
    active_pub_ = pnh_.advertise<std_msgs::String>("active", 1, true);
    diag_pub_ = nh_.advertise<diagnostic_msgs::DiagnosticArray>("/diagnostics", 5);
    for (std::size_t k = 0; k < mux_.topics().size(); ++k)
      subs_.push_back(mybot_lockstep::Participant::instance().subscribe<geometry_msgs::Twist>(
          nh_, mux_.topics()[k].topic, 10,
          [this, k](const geometry_msgs::Twist::ConstPtr& m) { onTwist(static_cast<int>(k), *m); },
          ros::TransportHints().tcpNoDelay()));
    for (std::size_t k = 0; k < mux_.locks().size(); ++k)
      subs_.push_back(mybot_lockstep::Participant::instance().subscribe<std_msgs::Bool>(
          nh_, mux_.locks()[k].topic, 10,
          [this, k](const std_msgs::Bool::ConstPtr& m)
          {
            mux_.lockReceived(static_cast<int>(k), m->data, ros::Time::now().toSec());
            check();
          }));
    check_timer_ = mybot_lockstep::Participant::instance().createTimer(nh_, 1.0 / check_rate,
                                                                       [this](const ros::TimerEvent&) { check(); });
    diag_timer_ = mybot_lockstep::Participant::instance().createTimer(
        nh_, 1.0 / diag_rate, [this](const ros::TimerEvent&) { diagnostics(); });
    announce("idle");
  }

private:
  void onTwist(int k, const geometry_msgs::Twist& m)
  {
    const double now = ros::Time::now().toSec();
    mux_.topicReceived(k, now);
    stopIfLost(now);  // before a lower priority takes over, as the timer would have
    if (!mux_.shouldForward(k, now))
      return;
    out_pub_.publish(m);
    announce(mux_.topics()[k].name);
  }

  void check() { stopIfLost(ros::Time::now().toSec()); }

  void stopIfLost(double now)
  {
    if (!mux_.checkStop(now))
      return;
    if (zero_on_timeout_)
      out_pub_.publish(geometry_msgs::Twist());
    announce("idle");
  }

  void announce(const std::string& name)
  {
    if (name == active_name_)
      return;
    active_name_ = name;
    std_msgs::String s;
    s.data = name;
    active_pub_.publish(s);
  }

  void diagnostics()
  {
    const double now = ros::Time::now().toSec();
    diagnostic_msgs::DiagnosticArray arr;
    arr.header.stamp = ros::Time::now();
    diagnostic_msgs::DiagnosticStatus st;
    st.name = pnh_.getNamespace() + ": twist mux";
    st.hardware_id = "none";
    const int active = mux_.active(now);
    const int lock = mux_.lockPriority(now);
    st.level = diagnostic_msgs::DiagnosticStatus::OK;
    st.message = active >= 0 ? "active: " + mux_.topics()[active].name : "idle (no input alive)";
    if (lock >= 0)
      st.message += ", locked at priority " + std::to_string(lock);
    auto kv = [&](const std::string& k, const std::string& v)
    {
      diagnostic_msgs::KeyValue e;
      e.key = k;
      e.value = v;
      st.values.push_back(e);
    };
    kv("active", active >= 0 ? mux_.topics()[active].name : "");
    kv("lock_priority", std::to_string(lock));
    for (std::size_t k = 0; k < mux_.topics().size(); ++k)
      kv("topic " + mux_.topics()[k].name,
         mux_.topics()[k].topic + " priority " + std::to_string(mux_.topics()[k].priority));
    arr.status.push_back(st);
    diag_pub_.publish(arr);
  }

  ros::NodeHandle nh_, pnh_;
  TwistMux mux_;
  bool zero_on_timeout_ = true;
  std::string active_name_;
  ros::Publisher out_pub_, active_pub_, diag_pub_;
  std::vector<ros::Subscriber> subs_;
  mybot_lockstep::Timer check_timer_, diag_timer_;
};

}  // namespace

namespace mybot_control_nodes
{
std::shared_ptr<void> makeTwistMux(const ros::NodeHandle& nh, const ros::NodeHandle& pnh)
{
  return std::make_shared<TwistMuxNode>(nh, pnh);
}
}  // namespace mybot_control_nodes

#ifndef MYBOT_CONTROL_NODE_LIBRARY
int main(int argc, char** argv)
{
  return runNode(argc, argv, "twist_mux",
                 []
                 {
                   const auto node = mybot_control_nodes::makeTwistMux(ros::NodeHandle(), ros::NodeHandle("~"));
                   ros::spin();
                 });
}
#endif
