// Runs a node object as a nodelet. A bad configuration (ParamError) fails the load with the
// node's one-line message.
#pragma once

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
    // Every subscription and timer of our nodes goes through the lockstep Participant. Under
    // lockstep they all run on the manager's global queue, period by period, so the manager
    // takes part as one process (as diffdrive_chain does); off lockstep, on this nodelet's own
    // queue (one worker thread at a time), timers included.
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
