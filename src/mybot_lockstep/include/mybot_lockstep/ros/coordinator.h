// The simulator's side of lockstep. The simulator's loop, per period:
//
//   coordinator.waitForParticipants();   // every participant acknowledged the period, and
//                                        // every message they sent to the simulator is handled
//   ... step the physics to the next period boundary t, publish sensors and /clock at t ...
//   coordinator.beginPeriod(t);          // publishes /lockstep/tick
//
// The simulator's own inputs (joint and wheel commands) are subscribed through subscribe(),
// so they are counted like a participant's.
#pragma once

#include <ros/callback_queue.h>
#include <ros/ros.h>

#include <string>
#include <type_traits>
#include <vector>

#include "mybot_lockstep/Ack.h"
#include "mybot_lockstep/Tick.h"
#include "mybot_lockstep/barrier.h"

namespace mybot_lockstep
{

class Coordinator
{
public:
  // timeout: wall seconds a participant may take over a period before it is dropped.
  Coordinator(double timeout, ros::CallbackQueue* queue);

  template <class M, class F>
  ros::Subscriber subscribe(ros::NodeHandle& nh, const std::string& topic, uint32_t queue_size, F cb)
  {
    const std::string resolved = nh.resolveName(topic);
    ledger_.count(resolved);
    ros::SubscribeOptions ops;
    ops.template initByFullCallbackType<const ros::MessageEvent<M const>&>(
        topic, queue_size,
        [this, resolved, cb](const ros::MessageEvent<M const>& e)
        {
          if constexpr (std::is_invocable_v<F, const boost::shared_ptr<M const>&>)
            cb(e.getConstMessage());
          else
            cb(*e.getConstMessage());
          ledger_.received(resolved, e.getPublisherName());
        });
    ops.transport_hints = ros::TransportHints().tcpNoDelay();
    return nh.subscribe(ops);
  }

  // Processes callbacks until the current period is finished by everyone. Participants that
  // stay silent past the timeout are dropped with a warning naming them; messages owed to
  // the simulator that do not arrive within it are given up with a warning.
  // Returns false if ROS is shutting down.
  bool waitForParticipants();
  // Starts the period at sim time `t` (publish /clock at t first).
  void beginPeriod(const ros::Time& t);
  // Publishes the current tick again (nothing advanced), so nodes that start while the
  // simulation waits can join.
  void republish();
  // Before the next period starts, every connection the master knows of between the
  // participants and the simulator must be open (and reported in their Acks): a connection
  // that opens a period later or earlier, as the scheduler pleases, would change what each
  // side sees. Called on start, on a spawn (new command subscriptions), on unpause; a join
  // does it by itself.
  void requireConnections() { settle_ = true; }
  std::size_t participants() const { return roster_.size(); }
  bool has(const std::string& node) const { return roster_.has(node); }

private:
  void onAck(const Ack::ConstPtr& ack);
  void dropDisconnected();
  // Empty if complete, else the first missing connection ("topic: from -> to").
  std::string missingConnection();

  Roster roster_;
  Ledger ledger_;
  double timeout_;
  ros::CallbackQueue* queue_;
  std::string self_;
  std::uint64_t seq_ = 0;
  Tick::Ptr tick_;
  bool settle_ = true;
  ros::Publisher tick_pub_;
  ros::Subscriber ack_sub_;
};

}  // namespace mybot_lockstep
