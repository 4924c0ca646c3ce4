// ROS-side emulations of the gazebo_ros plugins a URDF names in <gazebo>.
#pragma once

#include "mybot_gazebo_lite/camera.h"
#include "mybot_gazebo_lite/model.h"
#include "mybot_gazebo_lite/physics.h"
#include "mybot_gazebo_lite/raycast2d.h"

#include <mybot_lockstep/coordinator.h>
#include <ros/ros.h>
#include <tf2_ros/transform_broadcaster.h>

#include <map>
#include <memory>
#include <random>
#include <string>

namespace mybot_gazebo_lite {

// Static world cross-sections shared by all lasers (one per height).
class StaticSliceCache {
 public:
  explicit StaticSliceCache(const WorldSpec& w) : world_(w) {}
  const RayCaster2D& at(double z);
  const PrismScene& prisms();  // the cameras' 2.5D view, built on first use

 private:
  const WorldSpec& world_;
  std::map<long, std::unique_ptr<RayCaster2D>> cache_;
  std::unique_ptr<PrismScene> prisms_;
};

struct PluginContext {
  PhysicsWorld* world;
  Robot* robot;
  const PluginSpec* spec;
  std::string ns;         // robot namespace (plugin's <robotNamespace> wins)
  std::string tf_prefix;  // from the tf_prefix parameter in the namespace
  tf2_ros::TransformBroadcaster* tf;
  StaticSliceCache* slices;
  std::mt19937* rng;
  mybot_lockstep::Coordinator* lockstep = nullptr;  // set when the simulation runs in lockstep
};

// A command input. Under lockstep it is counted (the period waits until every command a
// participant sent for it is handled) and queued deep enough that none is dropped; otherwise
// only the latest matters (queue of 1).
template <class M, class F>
ros::Subscriber subscribeCommand(const PluginContext& c, ros::NodeHandle& nh, const std::string& topic, F cb) {
  if (c.lockstep) return c.lockstep->subscribe<M>(nh, topic, 100, cb);
  return nh.subscribe<M>(topic, 1, boost::function<void(const typename M::ConstPtr&)>(cb));
}

class SimPlugin {
 public:
  virtual ~SimPlugin() = default;
  virtual void preStep(double /*t*/) {}  // apply commands
  virtual void update(double t) = 0;     // after a physics step
  virtual void reset() {}
};

// nullptr + one warning naming the file when the plugin is unknown.
// Throws LoadError naming tag, link and file on a missing/malformed parameter.
std::unique_ptr<SimPlugin> createPlugin(const PluginContext& ctx);

}  // namespace mybot_gazebo_lite
