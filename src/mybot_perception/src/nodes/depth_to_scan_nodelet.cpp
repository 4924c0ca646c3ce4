// depth_to_scan as a nodelet (nodelet_plugins.xml): mybot_perception/DepthToScan.
#include <mybot_common/ros/params.h>
#include <mybot_lockstep/ros/participant.h>
#include <nodelet/nodelet.h>
#include <pluginlib/class_list_macros.hpp>

#include <memory>

#include "mybot_perception/ros/depth_to_scan.h"

namespace mybot_perception
{
class DepthToScanNodelet : public nodelet::Nodelet
{
  void onInit() override
  {
    // A manager's callbacks run on worker threads: it does not take part in lockstep.
    mybot_lockstep::Participant::optOut("a nodelet manager: callbacks on worker threads");
    try
    {
      node_ = std::make_unique<DepthToScanRos>(getNodeHandle(), getPrivateNodeHandle(), false);
    }
    catch (const mybot_common::ParamError& e)
    {
      NODELET_FATAL("%s: %s", getName().c_str(), e.what());
      throw std::runtime_error(getName() + ": " + e.what());
    }
  }
  std::unique_ptr<DepthToScanRos> node_;
};
}  // namespace mybot_perception

PLUGINLIB_EXPORT_CLASS(mybot_perception::DepthToScanNodelet, nodelet::Nodelet)
