// Runs a node object as a nodelet. A bad configuration (ParamError) fails the load with the
// node's one-line message.
#pragma once

#include <mybot_lockstep/ros/participant.h>
#include <nodelet/nodelet.h>

#include <memory>
#include <stdexcept>

#include "mybot_control/ros/params.hpp"

namespace mybot_control
{
using NodeFactory = std::shared_ptr<void> (*)(const ros::NodeHandle&, const ros::NodeHandle&);

template <NodeFactory make>
class NodeletHost : public nodelet::Nodelet
{
private:
  void onInit() override
  {
    // A nodelet's callbacks run on the manager's worker threads, which lockstep's tick-driven
    // timers (run from the global queue) would race with: a manager does not take part.
    mybot_lockstep::Participant::optOut("a nodelet manager: callbacks on worker threads");
    try
    {
      node_ = make(getNodeHandle(), getPrivateNodeHandle());
    }
    catch (const ParamError& e)
    {
      NODELET_FATAL("%s: %s", getName().c_str(), e.what());
      throw std::runtime_error(getName() + ": " + e.what());
    }
  }

  std::shared_ptr<void> node_;
};
}  // namespace mybot_control
