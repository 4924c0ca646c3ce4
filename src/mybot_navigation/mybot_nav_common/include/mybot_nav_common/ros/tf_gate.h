// Messages that wait for their transform, without blocking a callback: tf2_ros::MessageFilter's
// job, done on the node's own thread so that it works with mybot_lockstep::TransformListener
// (which fills the buffer from the node's callbacks, in lockstep) and so that the order in which
// messages are handed on depends only on what is in the buffer.
//
//   TfGate<sensor_msgs::LaserScan> gate("amcl", "scan", 100);
//   on a scan:        gate.add(scan); release();
//   on a tf update:   release();
//   release():        gate.release(ros::Time::now(), ready, [this](const auto& scan) { process(scan); });
//
// A message is handed on, in arrival order, once `ready(msg)` is true (usually
// buffer.canTransform(target, msg.header.frame_id, msg.header.stamp)); when more than
// `capacity` wait, the oldest is dropped with a throttled warning naming the node and the topic
// (the consumer is behind its sensor, or the transform never comes). When ROS time has gone
// back since the last release (a simulation reset, a bag played again), the waiting messages
// are forgotten: they belong to the time before, and the transforms of their stamps that will
// come describe another run.
#pragma once

#include <ros/console.h>
#include <ros/time.h>

#include <cstddef>
#include <deque>
#include <string>
#include <utility>

#include <boost/shared_ptr.hpp>

namespace mybot_navigation
{

template <class M>
class TfGate
{
public:
  using Ptr = boost::shared_ptr<M const>;

  TfGate(std::string node, std::string topic, std::size_t capacity)
      : node_(std::move(node)), topic_(std::move(topic)), capacity_(capacity)
  {
  }

  void add(const Ptr& msg)
  {
    waiting_.push_back(msg);
    while (waiting_.size() > capacity_)
    {
      ROS_WARN_THROTTLE(5.0,
                        "%s: dropping a message on %s stamped %.3f: its transform did not come before %zu newer ones",
                        node_.c_str(), topic_.c_str(), waiting_.front()->header.stamp.toSec(), capacity_);
      waiting_.pop_front();
      ++dropped_;
    }
  }

  // Hands on every waiting message whose transform is there, oldest first; the others wait on.
  template <class Ready, class Handle>
  void release(const ros::Time& now, Ready ready, Handle handle)
  {
    if (now < last_now_)
      waiting_.clear();
    last_now_ = now;
    for (auto it = waiting_.begin(); it != waiting_.end();)
    {
      if (!ready(**it))
      {
        ++it;
        continue;
      }
      const Ptr msg = *it;
      it = waiting_.erase(it);
      handle(msg);
    }
  }

  void clear() { waiting_.clear(); }
  std::size_t waiting() const { return waiting_.size(); }
  std::size_t dropped() const { return dropped_; }
  const std::string& topic() const { return topic_; }

private:
  std::string node_, topic_;
  std::size_t capacity_;
  std::deque<Ptr> waiting_;
  std::size_t dropped_ = 0;
  ros::Time last_now_;
};

}  // namespace mybot_navigation
