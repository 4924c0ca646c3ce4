// The plugin interface of gazebo_lite: what an emulated gazebo_ros plugin sees of the simulator
// (its robot, the world, the tf broadcaster, lockstep) and the helpers every plugin uses to read
// its XML parameters. The built-in plugins live in src/node/plugins/, one a file; a plugin from
// another package is a shared library named `libgazebo_lite_<name>.so` for the URDF's
// `lib<name>.so`, found on LD_LIBRARY_PATH, exporting MYBOT_GAZEBO_LITE_PLUGIN's factory.
#pragma once

#include "mybot_gazebo_lite/camera_model.h"
#include "mybot_gazebo_lite/model.h"
#include "mybot_gazebo_lite/physics.h"
#include "mybot_gazebo_lite/raycast2d.h"

#include <geometry_msgs/Pose.h>
#include <geometry_msgs/Twist.h>
#include <geometry_msgs/TransformStamped.h>
#include <mybot_lockstep/ros/coordinator.h>
#include <ros/ros.h>
#include <tf2_ros/transform_broadcaster.h>

#include <algorithm>
#include <map>
#include <memory>
#include <random>
#include <set>
#include <string>

namespace mybot_gazebo_lite
{

// Static world cross-sections shared by all lasers (one per height).
class StaticSliceCache
{
public:
  explicit StaticSliceCache(const WorldSpec& w) : world_(w) {}
  const RayCaster2D& at(double z);
  const PrismScene& prisms();  // the cameras' 2.5D view, built on first use
  // The static world changed (a static model spawned or deleted): rebuilt on next use.
  void invalidate()
  {
    cache_.clear();
    prisms_.reset();
  }

private:
  const WorldSpec& world_;
  std::map<long, std::unique_ptr<RayCaster2D>> cache_;
  std::unique_ptr<PrismScene> prisms_;
};

struct PluginContext
{
  PhysicsWorld* world;
  Robot* robot;
  const PluginSpec* spec;
  std::string ns;         // robot namespace (plugin's <robotNamespace> wins)
  std::string tf_prefix;  // from the tf_prefix parameter in the namespace
  tf2_ros::TransformBroadcaster* tf;
  StaticSliceCache* slices;
  std::mt19937* rng;
  mybot_lockstep::Coordinator* lockstep = nullptr;  // set when the simulation runs in lockstep
  const bool* paused = nullptr;                     // the simulation is paused (pause_physics)
};

// A command input. Under lockstep it is counted (the period waits until every command a
// participant sent for it is handled) and queued deep enough that none is dropped; otherwise
// only the latest matters (queue of 1), unless each message counts (an action's goals: its queue).
template <class M, class F>
ros::Subscriber subscribeCommand(const PluginContext& c, ros::NodeHandle& nh, const std::string& topic, F cb,
                                 uint32_t queue_size = 1)
{
  if (c.lockstep)
    return c.lockstep->subscribe<M>(nh, topic, std::max<uint32_t>(100, queue_size), cb);
  return nh.subscribe<M>(topic, queue_size, boost::function<void(const typename M::ConstPtr&)>(cb));
}

// A sensor's updates so far, for /gazebo/performance_metrics: how many times it fired, and a
// camera's frames rendered (null for other sensors).
struct SensorUpdates
{
  const uint64_t* updates = nullptr;
  const uint64_t* frames = nullptr;
};

class SimPlugin
{
public:
  virtual ~SimPlugin() = default;
  virtual void preStep(double /*t*/) {}                       // apply commands
  virtual void update(double t) = 0;                          // after a physics step
  virtual void reset() {}                                     // reset_world / reset_simulation
  virtual SensorUpdates sensorUpdates() const { return {}; }  // a sensor plugin's
};

// Reads plugin/sensor parameters; every error names tag, link and file.
class PluginParams
{
public:
  PluginParams(const PluginContext& c, const XmlNode& x) : c_(c), x_(x) {}
  [[noreturn]] void fail(const std::string& tag, const std::string& msg) const;  // tag "": the plugin's own
  const XmlNode* node(const std::string& path) const;                            // "a/b/c"
  bool has(const std::string& tag) const { return node(tag) != nullptr; }
  std::vector<const XmlNode*> all(const std::string& tag) const;  // every child named `tag`
  std::string str(const std::string& tag, const std::string& def) const;
  std::string requiredStr(const std::string& tag) const;
  double num(const std::string& tag, double def) const;
  double requiredNum(const std::string& tag) const;
  double positive(const std::string& tag, double def) const;     // > 0, else fails naming the tag
  double nonNegative(const std::string& tag, double def) const;  // >= 0, else fails naming the tag
  bool boolean(const std::string& tag, bool def) const;
  std::string joint(const std::string& tag, const std::string& def) const;  // must be a movable joint
  // A list of movable joints split at any of `separators` (as written; each checked as joint()'s).
  std::vector<std::string> jointList(const std::string& tag, const std::string& separators) const;
  // A link of the robot, as the plugin's own model scopes it; required when `def` is empty.
  std::string link(const std::string& tag, const std::string& def = "") const;
  btTransform pose(const std::string& tag) const;  // "x y z r p y"
  // The topic (or service) named by parameter `tag`, `def` when absent: a ROS graph name, else fails
  // naming the tag (roscpp's own refusal names neither the tag nor the file).
  std::string topic(const std::string& tag, const std::string& def) const;
  // M advertised on `topic`, which parameter `tag` named ("" for a fixed name). roscpp refuses a
  // second message type on a topic this process already publishes (another plugin's), with an
  // error naming neither plugin, and the publisher then sends nothing: fails naming the tag.
  template <class M>
  ros::Publisher advertise(ros::NodeHandle& nh, const std::string& tag, const std::string& topic, uint32_t queue) const
  {
    checkTopic(tag, topic);
    ros::Publisher pub = nh.advertise<M>(topic, queue);
    if (!pub)
      fail(tag, "topic '" + nh.resolveName(topic) + "' is already published with another message type than " +
                    ros::message_traits::datatype<M>() + " (by another plugin, or the simulator itself)");
    return pub;
  }
  // Whether any plugin looked this child of a <plugin> block up (warnUnknownTags uses it).
  static bool wasRead(const XmlNode& child);
  // Clears the record for `parent`'s children (before and after a plugin is made: a later spec
  // may be allocated where this one was).
  static void forgetReads(const XmlNode& parent);

private:
  double parse(const std::string& tag, const std::string& t) const;
  void checkTopic(const std::string& tag, const std::string& topic) const;
  std::string movableJoint(const std::string& tag, const std::string& name) const;  // scoped, checked
  const PluginContext& c_;
  const XmlNode& x_;
};

// Fires at a fixed sim-time period (0 = every step). Time going backwards (reset_simulation
// sends the clock back, as Gazebo does) starts it over: the next step fires.
struct Rate
{
  double period = 0, next = 0, last = -1;
  uint64_t fired = 0;  // how many times it was due
  explicit Rate(double hz = 0) : period(hz > 0 ? 1.0 / hz : 0) {}
  bool due(double t)
  {
    if (period <= 0)
      return ++fired, true;
    if (t < last)
      next = t;
    if (t + 1e-9 < next)
      return false;
    last = t;
    next = (next + period < t) ? t + period : next + period;
    ++fired;
    return true;
  }
};

// A frame name with the namespace's tf_prefix, leading slashes dropped (gazebo_ros's tf_prefix rule).
std::string resolveFrame(const PluginContext& c, std::string f);
// The robot's joint or link a plugin names: its own model's first, for a nested model's plugin
// (PluginSpec::scope), else the name as given.
std::string scopedJoint(const PluginContext& c, const std::string& name);
std::string scopedLink(const PluginContext& c, const std::string& name);
// `v` with a draw of `noise` added to x, y, then z, in that order: a constructor's arguments are
// evaluated in any order, and a seeded run must repeat. No draw when its deviation is 0.
btVector3 addNoise(btVector3 v, std::normal_distribution<double>& noise, std::mt19937& rng);
// Bullet's types as geometry_msgs: their one home, for the plugins and the node's services.
geometry_msgs::Vector3 toMsg(const btVector3& v);
geometry_msgs::Quaternion toMsg(const btQuaternion& q);
void toMsg(const btTransform& tf, geometry_msgs::Pose& p);
// A state's velocities (world axes) as a Twist.
geometry_msgs::Twist twistMsg(const Pose& s);
geometry_msgs::TransformStamped toTf(const btTransform& tf, double t, const std::string& parent,
                                     const std::string& child);

// After the plugin is made: one warning per child of <plugin> it did not read, naming it, the
// plugin, the link and the file -- "not simulated" for a parameter of `known` (those upstream
// reads), "unknown" with the closest known name otherwise (a misspelling, most likely).
// robotNamespace (read by the simulator), alwaysOn and rosDebugLevel are silent.
void warnUnknownTags(const PluginContext& c, const std::set<std::string>& known);

// A plugin library's factory: throws LoadError naming tag, link and file on a bad parameter.
using PluginFactory = SimPlugin* (*)(const PluginContext&);
#define MYBOT_GAZEBO_LITE_PLUGIN(CLASS)                                                                               \
  extern "C" mybot_gazebo_lite::SimPlugin* mybot_gazebo_lite_create_plugin(const mybot_gazebo_lite::PluginContext& c) \
  {                                                                                                                   \
    return new CLASS(c);                                                                                              \
  }

// nullptr + one warning naming the file when the plugin is unknown.
// Throws LoadError naming tag, link and file on a missing/malformed parameter.
std::unique_ptr<SimPlugin> createPlugin(const PluginContext& ctx);

}  // namespace mybot_gazebo_lite
