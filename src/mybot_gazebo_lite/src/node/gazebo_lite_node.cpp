// gazebo_lite: the headless simulator node. Steps the Bullet world at a fixed
// step, publishes /clock, runs the plugin emulations and the /gazebo services.
#include "mybot_gazebo_lite/ros/sim_plugin.h"

#include "gazebo_msgs/ApplyBodyWrench.h"
#include "gazebo_msgs/ApplyJointEffort.h"
#include "gazebo_msgs/BodyRequest.h"
#include "gazebo_msgs/DeleteModel.h"
#include "gazebo_msgs/GetJointProperties.h"
#include "gazebo_msgs/GetLinkProperties.h"
#include "gazebo_msgs/GetLinkState.h"
#include "gazebo_msgs/GetModelProperties.h"
#include "gazebo_msgs/GetModelState.h"
#include "gazebo_msgs/GetPhysicsProperties.h"
#include "gazebo_msgs/GetWorldProperties.h"
#include "gazebo_msgs/JointRequest.h"
#include "gazebo_msgs/LinkStates.h"
#include "gazebo_msgs/ModelStates.h"
#include "gazebo_msgs/PerformanceMetrics.h"
#include "gazebo_msgs/SetJointProperties.h"
#include "gazebo_msgs/SetLinkProperties.h"
#include "gazebo_msgs/SetLinkState.h"
#include "gazebo_msgs/SetModelConfiguration.h"
#include "gazebo_msgs/SetModelState.h"
#include "gazebo_msgs/SetPhysicsProperties.h"
#include "gazebo_msgs/SpawnModel.h"
#include "mybot_gazebo_lite/ModelContacts.h"
#include "mybot_gazebo_lite/parsing.h"
#include "mybot_gazebo_lite/physics.h"
#include "mybot_common/checks.h"
#include "mybot_common/ros/node_main.h"
#include "mybot_common/ros/params.h"

#include <ros/names.h>
#include <ros/ros.h>
#include <ros/callback_queue.h>
#include <rosgraph_msgs/Clock.h>
#include <std_srvs/Empty.h>
#include <tf2_ros/transform_broadcaster.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <sstream>
#include <memory>
#include <thread>

namespace mybot_gazebo_lite
{
using gazebo_msgs::ApplyBodyWrench;
using gazebo_msgs::ApplyJointEffort;
using gazebo_msgs::BodyRequest;
using gazebo_msgs::DeleteModel;
using gazebo_msgs::GetJointProperties;
using gazebo_msgs::GetLinkProperties;
using gazebo_msgs::GetLinkState;
using gazebo_msgs::GetModelProperties;
using gazebo_msgs::GetModelState;
using gazebo_msgs::GetPhysicsProperties;
using gazebo_msgs::GetWorldProperties;
using gazebo_msgs::JointRequest;
using gazebo_msgs::SetJointProperties;
using gazebo_msgs::SetLinkProperties;
using gazebo_msgs::SetLinkState;
using gazebo_msgs::SetModelConfiguration;
using gazebo_msgs::SetModelState;
using gazebo_msgs::SetPhysicsProperties;
using gazebo_msgs::SpawnModel;

class SimNode
{
public:
  SimNode() : pnh_("~") {}

  bool init()
  {
    // A value of the wrong type stops the node naming the parameter (never a silent default).
    using mybot_common::readParam;
    const std::string node = "gazebo_lite";
    const std::string world_file = readParam<std::string>(node, pnh_, "world", "");
    const int max_image_side = readParam<int>(node, pnh_, "max_image_side", mybot_common::kDefaultMaxImageSide);
    if (max_image_side <= 0)
      return bad("max_image_side", "must be a positive number of pixels");
    WorldSpec spec;
    try
    {
      if (world_file.empty())
      {
        spec.ground_plane = true;
        spec.name = "empty";
      }
      else
      {
        spec = loadWorldFile(world_file, defaultResolveUri, max_image_side);
      }
    }
    catch (const std::exception& e)
    {
      ROS_FATAL("gazebo_lite: cannot load world: %s", e.what());
      return false;
    }
    // The world's <physics> block sets the defaults; parameters (launch args) win, as in Gazebo.
    const PhysicsSpec& wp = spec.physics;
    double step = readParam<double>(node, pnh_, "max_step_size", wp.max_step_size);
    int iters = readParam<int>(node, pnh_, "solver_iterations", wp.iterations);
    rtf_ = readParam<double>(node, pnh_, "real_time_factor", wp.real_time_factor);
    paused_ = readParam<bool>(node, pnh_, "paused", false);
    clock_hz_ = readParam<double>(node, pnh_, "pub_clock_frequency", 100.0);
    int seed = readParam<int>(node, pnh_, "seed", 0);
    const bool lockstep = readParam<bool>(node, pnh_, "lockstep", false);
    const double period = readParam<double>(node, pnh_, "lockstep_period", 0.01);
    const double timeout = readParam<double>(node, pnh_, "lockstep_timeout", 10.0);
    // A list of node names, or one string of names separated by spaces or commas.
    std::string names;
    if (pnh_.getParam("lockstep_wait_for", names))
    {
      std::replace(names.begin(), names.end(), ',', ' ');
      std::istringstream in(names);
      for (std::string n; in >> n;)
        wait_for_.push_back(n);
    }
    else if (pnh_.hasParam("lockstep_wait_for") && !pnh_.getParam("lockstep_wait_for", wait_for_))
    {
      return bad("lockstep_wait_for", "expected a list of node names or a string of them");
    }
    if (!(step > 0 && step <= 0.01))
      return bad("max_step_size", "must be in (0, 0.01] s");
    if (iters < 1)
      return bad("solver_iterations", "must be >= 1");
    if (!(rtf_ >= 0) || !std::isfinite(rtf_))
      return bad("real_time_factor", "must be >= 0 (0 = as fast as possible)");
    if (clock_hz_ < 0)
      return bad("pub_clock_frequency", "must be >= 0 (0 = every step)");
    if (lockstep)
    {
      steps_per_period_ = static_cast<int>(std::lround(period / step));
      if (!(period > 0) || steps_per_period_ < 1 || std::fabs(steps_per_period_ * step - period) > 1e-9)
        return bad("lockstep_period", "must be a positive whole multiple of max_step_size (" + std::to_string(step) +
                                          " s), got " + std::to_string(period));
      if (!(timeout > 0) || !std::isfinite(timeout))
        return bad("lockstep_timeout", "must be > 0 s of wall time");
      for (auto& n : wait_for_)
        if (!n.empty() && n[0] != '/')
          n = "/" + n;
    }
    PhysicsWorld::Options opt;
    opt.step = step;
    opt.solver_iterations = iters;
    world_ = std::make_unique<PhysicsWorld>(spec, opt);
    slices_ = std::make_unique<StaticSliceCache>(world_->worldSpec());
    seed_ = seed;
    clock_pub_ = nh_.advertise<rosgraph_msgs::Clock>("/clock", 10);
    ros::NodeHandle g("/gazebo");
    contacts_pub_ = g.advertise<ModelContacts>("model_contacts", 10);
    model_states_pub_ = g.advertise<gazebo_msgs::ModelStates>("model_states", 10);
    link_states_pub_ = g.advertise<gazebo_msgs::LinkStates>("link_states", 10);
    metrics_pub_ = g.advertise<gazebo_msgs::PerformanceMetrics>("performance_metrics", 10);
    srvs_.push_back(g.advertiseService("reset_world", &SimNode::resetWorld, this));
    srvs_.push_back(g.advertiseService("reset_simulation", &SimNode::resetSimulation, this));
    srvs_.push_back(g.advertiseService("pause_physics", &SimNode::pause, this));
    srvs_.push_back(g.advertiseService("unpause_physics", &SimNode::unpause, this));
    srvs_.push_back(g.advertiseService("spawn_urdf_model", &SimNode::spawn, this));
    srvs_.push_back(g.advertiseService("spawn_sdf_model", &SimNode::spawn, this));
    srvs_.push_back(g.advertiseService("delete_model", &SimNode::remove, this));
    srvs_.push_back(g.advertiseService("get_model_state", &SimNode::getState, this));
    srvs_.push_back(g.advertiseService("get_link_state", &SimNode::getLinkState, this));
    srvs_.push_back(g.advertiseService("get_world_properties", &SimNode::getWorldProperties, this));
    srvs_.push_back(g.advertiseService("apply_body_wrench", &SimNode::applyBodyWrench, this));
    srvs_.push_back(g.advertiseService("clear_body_wrenches", &SimNode::clearBodyWrenches, this));
    srvs_.push_back(g.advertiseService("apply_joint_effort", &SimNode::applyJointEffort, this));
    srvs_.push_back(g.advertiseService("clear_joint_forces", &SimNode::clearJointForces, this));
    srvs_.push_back(g.advertiseService("set_model_state", &SimNode::setState, this));
    srvs_.push_back(g.advertiseService("set_link_state", &SimNode::setLinkState, this));
    srvs_.push_back(g.advertiseService("get_model_properties", &SimNode::getModelProperties, this));
    srvs_.push_back(g.advertiseService("get_joint_properties", &SimNode::getJointProperties, this));
    srvs_.push_back(g.advertiseService("set_model_configuration", &SimNode::setModelConfiguration, this));
    srvs_.push_back(g.advertiseService("get_link_properties", &SimNode::getLinkProperties, this));
    srvs_.push_back(g.advertiseService("set_link_properties", &SimNode::setLinkProperties, this));
    srvs_.push_back(g.advertiseService("set_joint_properties", &SimNode::setJointProperties, this));
    srvs_.push_back(g.advertiseService("get_physics_properties", &SimNode::getPhysicsProperties, this));
    srvs_.push_back(g.advertiseService("set_physics_properties", &SimNode::setPhysicsProperties, this));
    if (lockstep)
      lockstep_ = std::make_unique<mybot_lockstep::Coordinator>(timeout, ros::getGlobalCallbackQueue());
    // Under lockstep, counted as the simulator's other inputs: a state sent for period k is set in it.
    set_model_state_sub_ = subscribeCounted<gazebo_msgs::ModelState>(
        g, "set_model_state", [this](const gazebo_msgs::ModelState& m) { applyModelState(m); });
    set_link_state_sub_ = subscribeCounted<gazebo_msgs::LinkState>(
        g, "set_link_state", [this](const gazebo_msgs::LinkState& m) { applyLinkState(m); });
    // The world file's models with joints or plugins are robots, as Gazebo loads them.
    for (const WorldRobot& r : spec.robots)
    {
      SpawnModel::Request req;
      req.model_name = r.name;
      SpawnModel::Response res;
      try
      {
        addRobotModel(r.spec, r.model_pose * r.root_in_model, req, res);
      }
      catch (const std::exception& e)
      {
        ROS_FATAL("gazebo_lite: cannot load world: model '%s': %s", r.name.c_str(), e.what());
        return false;
      }
    }
    publishClock(true);
    ROS_INFO("gazebo_lite: world '%s' (%zu models), step %.4f s, real_time_factor %g%s%s", spec.name.c_str(),
             spec.models.size() + spec.robots.size(), step, rtf_, paused_ ? ", paused" : "",
             lockstep ? (", lockstep every " + std::to_string(period) + " s").c_str() : "");
    return true;
  }

  // Lockstep: one period per turn. Time advances only when every participant has finished
  // the previous period (mybot_lockstep's README has the protocol).
  void runLockstep()
  {
    auto* queue = ros::getGlobalCallbackQueue();
    waitForNamedParticipants();  // begins the first period
    anchor();
    ros::WallTime next_tick = ros::WallTime::now();
    while (ros::ok())
    {
      if (paused_)
      {
        // Time stands; the current period is published again now and then so nodes that start
        // meanwhile join before time moves (waitForParticipants then waits for them too).
        const ros::WallTime now = ros::WallTime::now();
        if (now >= next_tick)
        {
          publishClock(true);
          lockstep_->republish();
          next_tick = now + ros::WallDuration(0.1);
        }
        queue->callAvailable(ros::WallDuration(0.005));
        anchor();
        continue;
      }
      if (!lockstep_->waitForParticipants())
        return;
      if (paused_)
        continue;  // paused while it waited
      double t = world_->time();
      for (int i = 0; i < steps_per_period_; ++i)
      {
        t = stepOnce();
        // Within the period too, at pub_clock_frequency: nodes that do not take part keep the
        // clock they had without lockstep; participants act only on the period's boundary.
        if (i + 1 < steps_per_period_)
          publishClock(false);
      }
      publishClock(true);
      lockstep_->beginPeriod(ros::Time(t));
      pace(t);
    }
  }

  void run()
  {
    if (lockstep_)
      return runLockstep();
    auto* queue = ros::getGlobalCallbackQueue();
    anchor();
    while (ros::ok())
    {
      queue->callAvailable();
      if (paused_)
      {
        publishClock(true);  // ~200 Hz wall, so late subscribers still learn the time
        queue->callAvailable(ros::WallDuration(0.005));
        anchor();
        continue;
      }
      const double t = stepOnce();
      publishClock(false);
      pace(t);
    }
  }

private:
  static constexpr double kMaxLagWall = 0.02;
  static constexpr double kContactsPeriod = 0.1;  // s of sim time
  // Poses farther out than this are a mistake (the 1e30 of a bad script), not a world.
  static constexpr double kMaxCoordinate = 1e6;
  struct ModelEntry
  {
    std::string name;
    std::vector<std::unique_ptr<std::mt19937>> noise;  // one per plugin; outlives the plugins
    std::vector<std::unique_ptr<SimPlugin>> plugins;
    // Its sensors, for /gazebo/performance_metrics: Gazebo's scoped name, the plugin, and its
    // counts at the last report.
    struct Sensor
    {
      std::string name;
      const SimPlugin* plugin;
      uint64_t updates = 0, frames = 0;
    };
    std::vector<Sensor> sensors;
  };

  // Each plugin draws its noise from its own stream, seeded by ~seed, the model and the plugin
  // (its place in the URDF and its name). One stream shared by the world would hand a robot's
  // sensors different draws depending on which other robots are in it and in which order they
  // were spawned (a probe's first scan moved by 8.8 mm, the median beam, when another robot was
  // spawned before it: sim_test.py's multi suite).
  static std::mt19937 noiseStream(int seed, const std::string& model, size_t index, const std::string& plugin)
  {
    std::vector<uint32_t> key{static_cast<uint32_t>(seed), static_cast<uint32_t>(index)};
    for (const std::string* s : {&model, &plugin})
    {
      key.push_back(static_cast<uint32_t>(s->size()));
      for (unsigned char c : *s)
        key.push_back(c);
    }
    std::seed_seq seq(key.begin(), key.end());
    return std::mt19937(seq);
  }

  // A topic the simulator takes commands on: under lockstep a message sent in period k is handled in it.
  template <class Msg>
  ros::Subscriber subscribeCounted(ros::NodeHandle& nh, const std::string& topic, std::function<void(const Msg&)> cb)
  {
    if (lockstep_)
      return lockstep_->subscribe<Msg>(nh, topic, 100, cb);
    return nh.subscribe<Msg>(
        topic, 10,
        boost::function<void(const typename Msg::ConstPtr&)>([cb](const typename Msg::ConstPtr& m) { cb(*m); }));
  }

  bool bad(const std::string& param, const std::string& msg)
  {
    ROS_FATAL("gazebo_lite: parameter ~%s: %s", param.c_str(), msg.c_str());
    return false;
  }
  // One physics step with the plugins around it (commands in, sensors out) and the contact
  // counts. Returns the new sim time.
  double stepOnce()
  {
    double t = world_->time();
    for (auto& m : models_)
      for (auto& p : m.plugins)
        p->preStep(t);
    world_->step();
    t = world_->time();
    for (auto& m : models_)
      for (auto& p : m.plugins)
        p->update(t);
    if (t + 1e-9 >= last_contacts_ + kContactsPeriod)
      publishContacts();
    publishStates();
    publishMetrics(t);
    return t;
  }

  // /gazebo/performance_metrics, as gazebo_ros relays Gazebo's: at most 5 a wall second while
  // someone subscribes, the real-time factor and each sensor's rates over the time since the last
  // one (Gazebo gives a sensor's rates from its last two updates; counted over the report's span
  // here, they do not jump by one update's lateness).
  void publishMetrics(double t)
  {
    const auto now = std::chrono::steady_clock::now();
    if (now < next_metrics_)
      return;
    next_metrics_ = now + std::chrono::milliseconds(200);
    const bool report = metrics_pub_.getNumSubscribers() > 0 && t > metrics_sim_ && metrics_sim_ >= 0;
    const double sim = t - metrics_sim_;
    const double wall = std::chrono::duration<double>(now - metrics_wall_).count();
    gazebo_msgs::PerformanceMetrics m;
    m.header.stamp = ros::Time(t);
    m.real_time_factor = wall > 0 ? sim / wall : 0;
    for (auto& model : models_)
      for (auto& s : model.sensors)
      {
        const SensorUpdates u = s.plugin->sensorUpdates();
        const uint64_t frames = u.frames ? *u.frames : 0;
        if (report)
        {
          gazebo_msgs::SensorPerformanceMetric sm;
          sm.name = s.name;
          sm.sim_update_rate = (*u.updates - s.updates) / sim;
          sm.real_update_rate = wall > 0 ? (*u.updates - s.updates) / wall : 0;
          sm.fps = u.frames ? (wall > 0 ? (frames - s.frames) / wall : 0) : -1;
          m.sensors.push_back(sm);
        }
        s.updates = *u.updates;
        s.frames = frames;
      }
    if (report)
      metrics_pub_.publish(m);
    // A window starts here (also after a reset sent time back, or while nobody listened).
    metrics_sim_ = t;
    metrics_wall_ = now;
  }
  // real_time_factor is an upper bound: never run ahead of the wall clock times it.
  void pace(double t)
  {
    if (!(rtf_ > 0))
      return;
    // Pace against the wall clock from an anchor so errors do not accumulate.
    ros::WallTime target = wall0_ + ros::WallDuration((t - sim0_) / rtf_);
    ros::WallTime now = ros::WallTime::now();
    if (target > now)
    {
      std::this_thread::sleep_for(std::chrono::nanoseconds((target - now).toNSec()));
    }
    else if ((now - target).toSec() > kMaxLagWall)
    {
      // Behind (a starved CPU): run slower than asked, as Gazebo does, rather than catch up in
      // a burst that the controllers, themselves starved, would see as open-loop time.
      anchor();
    }
  }
  // ~lockstep_wait_for: time does not start until these nodes take part, so a test's start
  // does not depend on how fast its nodes came up.
  void waitForNamedParticipants()
  {
    auto* queue = ros::getGlobalCallbackQueue();
    lockstep_->beginPeriod(ros::Time(world_->time()));
    ros::WallTime next_tick = ros::WallTime::now(), next_note = next_tick + ros::WallDuration(10.0);
    for (;;)
    {
      std::vector<std::string> missing;
      for (const auto& n : wait_for_)
        if (!lockstep_->has(n))
          missing.push_back(n);
      if (missing.empty() || !ros::ok())
        return;
      queue->callAvailable(ros::WallDuration(0.01));
      const ros::WallTime now = ros::WallTime::now();
      if (now >= next_tick)
      {  // the same period again, for nodes that connect late
        publishClock(true);
        lockstep_->republish();
        next_tick = now + ros::WallDuration(0.1);
      }
      if (now >= next_note)
      {
        std::string names;
        for (const auto& n : missing)
          names += " " + n;
        ROS_WARN("gazebo_lite: lockstep_wait_for: still waiting for%s", names.c_str());
        next_note = now + ros::WallDuration(10.0);
      }
    }
  }
  void anchor()
  {
    wall0_ = ros::WallTime::now();
    sim0_ = world_->time();
  }
  void publishContacts()
  {
    last_contacts_ = world_->time();
    if (contacts_pub_.getNumSubscribers() == 0)
      return;
    for (Robot* r : world_->robots())
    {
      const auto& c = r->contacts();
      ModelContacts m;
      m.header.stamp = ros::Time(world_->time());
      m.header.frame_id = "world";
      m.model_name = r->name();
      m.touching = c.now;
      m.contact_steps = c.steps;
      m.contact_time = c.time;
      m.max_depth = c.max_depth;
      m.first_time = c.first_time;
      m.first_model = c.first_model;
      contacts_pub_.publish(m);
    }
  }
  void publishClock(bool force)
  {
    double t = world_->time();
    if (!force && clock_hz_ > 0 && t + 1e-9 < last_clock_ + 1.0 / clock_hz_)
      return;
    rosgraph_msgs::Clock c;
    c.clock = ros::Time(t);
    clock_pub_.publish(c);
    last_clock_ = t;
  }

  bool resetWorld(std_srvs::Empty::Request&, std_srvs::Empty::Response&)
  {
    if (world_->resetWorld())
      slices_->invalidate();
    for (auto& m : models_)
      for (auto& p : m.plugins)
        p->reset();
    return true;
  }
  bool resetSimulation(std_srvs::Empty::Request& a, std_srvs::Empty::Response& b)
  {
    // Time first: the plugins' reset reads it (gazebo_ros_control restarts its controllers at
    // the new time; restarted at the old one, joint_state_controller stayed silent until sim
    // time came back to where the reset had been).
    world_->resetTime();
    world_->clearBodyWrenches();  // their times were of the old clock
    world_->clearJointForces();
    resetWorld(a, b);
    last_clock_ = -1;
    last_contacts_ = -1;
    // In lockstep the new time goes out with the next period's tick, as every clock does: a
    // participant still handling this period keeps its time, and all of them see time go back
    // at the same boundary (while paused, the loop publishes the clock as it waits).
    if (!lockstep_)
      publishClock(true);
    anchor();
    return true;
  }
  bool pause(std_srvs::Empty::Request&, std_srvs::Empty::Response&)
  {
    paused_ = true;
    return true;
  }
  bool unpause(std_srvs::Empty::Request&, std_srvs::Empty::Response&)
  {
    paused_ = false;
    if (lockstep_)
      lockstep_->requireConnections();
    anchor();
    return true;
  }

  bool spawn(SpawnModel::Request& req, SpawnModel::Response& res)
  {
    res.success = false;
    if (req.model_name.empty())
    {
      res.status_message = "model_name is empty";
      return true;
    }
    if (!req.reference_frame.empty() && req.reference_frame != "world" && req.reference_frame != "map")
    {
      res.status_message = "reference_frame '" + req.reference_frame + "' not supported (use world)";
      return true;
    }
    const auto& ip = req.initial_pose;
    const std::string bad = mybot_common::firstInvalid({{"initial_pose.position.x", ip.position.x},
                                                        {"initial_pose.position.y", ip.position.y},
                                                        {"initial_pose.position.z", ip.position.z},
                                                        {"initial_pose.orientation.x", ip.orientation.x},
                                                        {"initial_pose.orientation.y", ip.orientation.y},
                                                        {"initial_pose.orientation.z", ip.orientation.z},
                                                        {"initial_pose.orientation.w", ip.orientation.w}},
                                                       kMaxCoordinate);
    if (!bad.empty())
    {
      res.status_message = "refused: " + bad;
      ROS_ERROR("gazebo_lite: spawn '%s' refused: %s", req.model_name.c_str(), bad.c_str());
      return true;
    }
    // As gazebo_ros, either service takes either format: a URDF <robot> is simulated as a robot
    // (its joints and plugins), an SDF <model> as spawnSdf says.
    if (req.model_xml.find("<robot") == std::string::npos &&
        (req.model_xml.find("<sdf") != std::string::npos || req.model_xml.find("<model") != std::string::npos))
      return spawnSdf(req, res);
    try
    {
      auto spec = std::make_shared<RobotSpec>(parseUrdf(req.model_xml, "URDF of model '" + req.model_name + "'"));
      addRobotModel(spec, initialPose(req), req, res);
    }
    catch (const std::exception& e)
    {
      res.status_message = e.what();
      ROS_ERROR("gazebo_lite: spawn '%s' failed: %s", req.model_name.c_str(), e.what());
    }
    return true;
  }

  static btTransform initialPose(const SpawnModel::Request& req)
  {
    const auto& p = req.initial_pose;
    btQuaternion q(p.orientation.x, p.orientation.y, p.orientation.z, p.orientation.w);
    if (q.length2() < 1e-12)
      q = btQuaternion::getIdentity();
    q.normalize();
    return btTransform(q, btVector3(p.position.x, p.position.y, p.position.z));
  }

  // A robot (from a URDF, or an SDF model with joints or plugins) with its root link at `pose`, and
  // its plugins. Throws, having added nothing, when the physics or a plugin refuses it.
  void addRobotModel(const std::shared_ptr<RobotSpec>& spec, const btTransform& pose, const SpawnModel::Request& req,
                     SpawnModel::Response& res)
  {
    for (const std::string& w : spec->warnings)
      ROS_WARN("gazebo_lite: %s", w.c_str());
    std::string ns = req.robot_namespace;
    Robot& robot = world_->addRobot(spec, req.model_name, ns, pose);
    ModelEntry entry;
    entry.name = req.model_name;
    try
    {
      for (size_t i = 0; i < spec->plugins.size(); ++i)
      {
        const PluginSpec& ps = spec->plugins[i];
        PluginContext ctx;
        ctx.world = world_.get();
        ctx.robot = &robot;
        ctx.spec = &ps;
        ctx.ns = ns;
        const XmlNode* rn = ps.xml.child("robotNamespace");
        if (rn)
          ctx.ns = rn->text;
        if (std::string why; !ros::names::validate(ctx.ns, why))  // roscpp's exception would name no plugin
          throw LoadError(spec->source + ": plugin '" + ps.name + "' (" + ps.filename +
                          "): " + (rn ? "<robotNamespace>" : "the spawn's robot_namespace") + " '" + ctx.ns +
                          "' is not a ROS name: " + why);
        ros::NodeHandle nsh(ctx.ns);
        std::string key;
        if (nsh.searchParam("tf_prefix", key))
          nsh.getParam(key, ctx.tf_prefix);
        while (!ctx.tf_prefix.empty() && ctx.tf_prefix[0] == '/')
          ctx.tf_prefix.erase(0, 1);
        ctx.tf = &tfb_;
        ctx.slices = slices_.get();
        entry.noise.push_back(std::make_unique<std::mt19937>(noiseStream(seed_, req.model_name, i, ps.name)));
        ctx.rng = entry.noise.back().get();
        ctx.lockstep = lockstep_.get();
        ctx.paused = &paused_;
        if (auto plugin = createPlugin(ctx))
        {
          const auto sensor = ps.sensor.attributes.find("name");
          if (ps.has_sensor && plugin->sensorUpdates().updates && sensor != ps.sensor.attributes.end())
            entry.sensors.push_back({world_->worldSpec().name + "::" + req.model_name + "::" +
                                         world_->bodyLinkOf(req.model_name, ps.reference) + "::" + sensor->second,
                                     plugin.get()});
          entry.plugins.push_back(std::move(plugin));
        }
      }
    }
    catch (...)
    {
      world_->removeRobot(req.model_name);
      throw;
    }
    models_.push_back(std::move(entry));
    if (lockstep_)
      lockstep_->requireConnections();  // its command inputs must connect first
    res.success = true;
    res.status_message = "spawned '" + req.model_name + "'";
    ROS_INFO("gazebo_lite: spawned '%s' (namespace '%s') with %zu plugins", req.model_name.c_str(), ns.c_str(),
             models_.back().plugins.size());
  }

  // An SDF model (spawn_sdf_model) at initial_pose times its own <pose>: a robot when it has joints
  // or plugins (as Gazebo simulates it), else a world model, static or dynamic. The plugins of a
  // static model are not run (said once).
  bool spawnSdf(SpawnModel::Request& req, SpawnModel::Response& res)
  {
    try
    {
      SdfSpawn sdf = parseSdfSpawn(req.model_xml, "SDF of model '" + req.model_name + "'", ".");
      if (sdf.robot)
      {
        addRobotModel(sdf.robot, initialPose(req) * sdf.model.pose * sdf.root_in_model, req, res);
        return true;
      }
      WorldModel& m = sdf.model;
      if (req.model_xml.find("<plugin") != std::string::npos)
        ROS_WARN("gazebo_lite: spawn '%s': the static model's <plugin>s are not run", req.model_name.c_str());
      m.name = req.model_name;
      m.pose = initialPose(req) * m.pose;
      world_->addModel(m);
      if (m.is_static)
        slices_->invalidate();  // the lasers' slices and the cameras' scene of the static world
      res.success = true;
      res.status_message = "spawned '" + req.model_name + "'";
      ROS_INFO("gazebo_lite: spawned SDF model '%s' (%s, %zu links)", req.model_name.c_str(),
               m.is_static ? "static" : "dynamic", m.links.size());
    }
    catch (const std::exception& e)
    {
      res.success = false;
      res.status_message = e.what();
      ROS_ERROR("gazebo_lite: spawn '%s' failed: %s", req.model_name.c_str(), e.what());
    }
    return true;
  }

  bool remove(DeleteModel::Request& req, DeleteModel::Response& res)
  {
    bool was_static = false;
    if (world_->removeModel(req.model_name, &was_static))
    {
      if (was_static)
        slices_->invalidate();
      res.success = true;
      res.status_message = "deleted '" + req.model_name + "'";
      return true;
    }
    for (auto it = models_.begin(); it != models_.end(); ++it)
      if (it->name == req.model_name)
      {
        models_.erase(it);  // plugins first: they reference the robot
        world_->removeRobot(req.model_name);
        res.success = true;
        res.status_message = "deleted '" + req.model_name + "'";
        return true;
      }
    res.success = false;
    res.status_message = "no model named '" + req.model_name + "'";
    return true;
  }

  // `relative_to` "", "world" or "map": the world; else a model or a "model::link", as gazebo_ros.
  // False, saying why, when either entity is missing.
  bool stateOf(const std::string& name, const std::string& relative_to, const char* what, Pose& out,
               std::string& why) const
  {
    if (!world_->entityState(name, out))
    {
      why = std::string("no ") + what + " named '" + name + "'";
      return false;
    }
    if (relative_to.empty() || relative_to == "world" || relative_to == "map")
      return true;
    Pose frame;
    if (!world_->entityState(relative_to, frame))
    {
      why = "no model or link named '" + relative_to + "' to give the state relative to";
      return false;
    }
    out = relativeTo(out, frame);
    return true;
  }

  bool getState(GetModelState::Request& req, GetModelState::Response& res)
  {
    res.header.stamp = ros::Time(world_->time());
    res.header.frame_id = req.relative_entity_name.empty() ? "world" : req.relative_entity_name;
    Pose s;
    if (req.model_name.find("::") != std::string::npos ||
        !stateOf(req.model_name, req.relative_entity_name, "model", s, res.status_message))
    {
      res.success = false;
      if (res.status_message.empty())
        res.status_message = "no model named '" + req.model_name + "' (a link: get_link_state)";
      return true;
    }
    res.pose = poseMsg(s);
    res.twist = twistMsg(s);
    res.success = true;
    res.status_message = "GetModelState: got properties";
    return true;
  }

  bool getLinkState(GetLinkState::Request& req, GetLinkState::Response& res)
  {
    Pose s;
    res.link_state.link_name = req.link_name;
    res.link_state.reference_frame = req.reference_frame;
    res.success = req.link_name.find("::") != std::string::npos &&
                  stateOf(req.link_name, req.reference_frame, "link", s, res.status_message);
    if (!res.success)
    {
      if (res.status_message.empty())
        res.status_message = "no link named '" + req.link_name + "' (links are named model::link)";
      return true;
    }
    res.link_state.pose = poseMsg(s);
    res.link_state.twist = twistMsg(s);
    res.status_message = "GetLinkState: got state";
    return true;
  }

  bool getWorldProperties(GetWorldProperties::Request&, GetWorldProperties::Response& res)
  {
    res.sim_time = world_->time();
    for (const auto& [name, state] : world_->modelStates())
      res.model_names.push_back(name);
    res.rendering_enabled = false;  // headless
    res.success = true;
    res.status_message = "GetWorldProperties: got properties";
    return true;
  }

  // From start_time (or now, if that is past) for duration (< 0: until cleared; 0: nothing), as
  // gazebo_ros. A body that is not there, a bad number or an unknown reference frame is refused,
  // saying which.
  bool applyBodyWrench(ApplyBodyWrench::Request& req, ApplyBodyWrench::Response& res)
  {
    const auto& f = req.wrench.force;
    const auto& t = req.wrench.torque;
    const auto& p = req.reference_point;
    const std::string bad = mybot_common::firstInvalid({{"wrench.force.x", f.x},
                                                        {"wrench.force.y", f.y},
                                                        {"wrench.force.z", f.z},
                                                        {"wrench.torque.x", t.x},
                                                        {"wrench.torque.y", t.y},
                                                        {"wrench.torque.z", t.z},
                                                        {"reference_point.x", p.x},
                                                        {"reference_point.y", p.y},
                                                        {"reference_point.z", p.z}},
                                                       kMaxCoordinate);
    res.success = false;
    btVector3 com;
    if (!bad.empty())
      res.status_message = "refused: " + bad;
    else if (!world_->centreOfMass(req.body_name, com))
      res.status_message =
          "no body named '" + req.body_name + "' to push (a robot's or a dynamic model's link, named model::link)";
    if (!res.status_message.empty())
    {
      ROS_ERROR("gazebo_lite: apply_body_wrench: %s", res.status_message.c_str());
      return true;
    }
    Pose frame;
    const bool in_world = req.reference_frame.empty() || req.reference_frame == "world" || req.reference_frame == "map";
    if (!in_world && !world_->entityState(req.reference_frame, frame))
    {
      res.status_message = "no model or link named '" + req.reference_frame + "' for reference_frame";
      ROS_ERROR("gazebo_lite: apply_body_wrench: %s", res.status_message.c_str());
      return true;
    }
    btVector3 force, torque;
    worldWrench(btVector3(f.x, f.y, f.z), btVector3(t.x, t.y, t.z), btVector3(p.x, p.y, p.z),
                in_world ? nullptr : &frame.tf, com, force, torque);
    res.success = true;
    if (req.duration.isZero())
    {
      res.status_message = "duration 0: nothing applied";
      return true;
    }
    const double start = std::max(req.start_time.toSec(), world_->time());
    world_->applyBodyWrench(req.body_name, force, torque, start, req.duration.toSec());
    return true;
  }

  bool clearBodyWrenches(BodyRequest::Request& req, BodyRequest::Response&)
  {
    if (!req.body_name.empty())  // an empty name would clear every body's, which upstream does not
      world_->clearBodyWrenches(req.body_name);
    return true;
  }

  // As apply_body_wrench's times; the joint "model::joint", or a name one robot alone has.
  bool applyJointEffort(ApplyJointEffort::Request& req, ApplyJointEffort::Response& res)
  {
    res.status_message = mybot_common::firstInvalid({{"effort", req.effort}}, kMaxCoordinate);
    if (!res.status_message.empty())
      res.status_message = "refused: " + res.status_message;
    else if (!req.duration.isZero())
      res.status_message = world_->applyJointEffort(
          req.joint_name, req.effort, std::max(req.start_time.toSec(), world_->time()), req.duration.toSec());
    res.success = res.status_message.empty();
    if (!res.success)
      ROS_ERROR("gazebo_lite: apply_joint_effort: %s", res.status_message.c_str());
    else if (req.duration.isZero())
      res.status_message = "duration 0: nothing applied";
    return true;
  }

  bool clearJointForces(JointRequest::Request& req, JointRequest::Response&)
  {
    if (!req.joint_name.empty())
      world_->clearJointForces(req.joint_name);
    return true;
  }

  // As gazebo_ros: links and collisions unscoped, as Gazebo names them (see ModelProperties). One
  // difference: canonical_body_name is given (gazebo_ros leaves it empty).
  bool getModelProperties(GetModelProperties::Request& req, GetModelProperties::Response& res)
  {
    ModelProperties p;
    res.success = world_->modelProperties(req.model_name, p);
    if (!res.success)
    {
      res.status_message = "GetModelProperties: no model named '" + req.model_name + "'";
      return true;
    }
    res.canonical_body_name = p.canonical_link;
    res.body_names = p.links;
    res.geom_names = p.collisions;
    res.joint_names = p.joints;
    res.child_model_names = p.child_models;
    res.is_static = p.is_static;
    res.status_message = "GetModelProperties: got properties";
    return true;
  }

  // The joint's own type and damping (gazebo_ros says REVOLUTE and no damping for every joint).
  bool getJointProperties(GetJointProperties::Request& req, GetJointProperties::Response& res)
  {
    JointProperties p;
    res.status_message = world_->jointProperties(req.joint_name, p);
    res.success = res.status_message.empty();
    if (!res.success)
    {
      res.status_message = "GetJointProperties: " + res.status_message;
      return true;
    }
    switch (p.type)
    {
      case JointSpec::CONTINUOUS:
        res.type = GetJointProperties::Response::CONTINUOUS;
        break;
      case JointSpec::PRISMATIC:
        res.type = GetJointProperties::Response::PRISMATIC;
        break;
      case JointSpec::FIXED:  // an SDF model's (a URDF's are lumped away)
        res.type = GetJointProperties::Response::FIXED;
        break;
      case JointSpec::BALL:
        res.type = GetJointProperties::Response::BALL;
        break;
      default:
        res.type = GetJointProperties::Response::REVOLUTE;
    }
    res.damping = {p.damping};
    res.position = {p.position};
    res.rate = {p.rate};
    res.status_message = "GetJointProperties: got properties";
    return true;
  }

  // As gazebo_ros: the centre of mass in the link frame (no rotation) and the inertia in the link
  // frame's axes. A link is "model::link" or a name one model alone has.
  bool getLinkProperties(GetLinkProperties::Request& req, GetLinkProperties::Response& res)
  {
    LinkProperties p;
    res.status_message = world_->linkProperties(req.link_name, p);
    res.success = res.status_message.empty();
    if (!res.success)
    {
      res.status_message = "GetLinkProperties: " + res.status_message;
      return true;
    }
    res.com.position.x = p.com.x();
    res.com.position.y = p.com.y();
    res.com.position.z = p.com.z();
    res.com.orientation.w = 1;
    res.gravity_mode = p.gravity_mode;
    res.mass = p.mass;
    res.ixx = p.inertia[0][0];
    res.ixy = p.inertia[0][1];
    res.ixz = p.inertia[0][2];
    res.iyy = p.inertia[1][1];
    res.iyz = p.inertia[1][2];
    res.izz = p.inertia[2][2];
    res.status_message = "GetLinkProperties: got properties";
    return true;
  }

  // Mass, inertia and gravity from the next step on (com.orientation is not read, as gazebo_ros).
  // Refused, naming why, where gazebo_ros would take it without a word: a centre of mass moved,
  // the inertia's axes turned, a mass or inertia no body has.
  bool setLinkProperties(SetLinkProperties::Request& req, SetLinkProperties::Response& res)
  {
    const auto& c = req.com.position;
    res.status_message = mybot_common::firstInvalid({{"com.position.x", c.x},
                                                     {"com.position.y", c.y},
                                                     {"com.position.z", c.z},
                                                     {"mass", req.mass},
                                                     {"ixx", req.ixx},
                                                     {"ixy", req.ixy},
                                                     {"ixz", req.ixz},
                                                     {"iyy", req.iyy},
                                                     {"iyz", req.iyz},
                                                     {"izz", req.izz}},
                                                    kMaxCoordinate);
    if (res.status_message.empty())
    {
      LinkProperties p;
      p.com = btVector3(c.x, c.y, c.z);
      p.gravity_mode = req.gravity_mode;
      p.mass = req.mass;
      p.inertia = btMatrix3x3(req.ixx, req.ixy, req.ixz, req.ixy, req.iyy, req.iyz, req.ixz, req.iyz, req.izz);
      res.status_message = world_->setLinkProperties(req.link_name, p);
    }
    res.success = res.status_message.empty();
    if (!res.success)
    {
      res.status_message = "SetLinkProperties: " + res.status_message;
      ROS_ERROR("gazebo_lite: %s", res.status_message.c_str());
      return true;
    }
    res.status_message = "SetLinkProperties: properties set";
    return true;
  }

  // damping, hiStop, loStop, and the joint motor's fmax and vel (ODE's motor: vel at up to fmax).
  // ODE's erp, cfm, stop_erp, stop_cfm and fudge_factor have no counterpart here: not applied.
  bool setJointProperties(SetJointProperties::Request& req, SetJointProperties::Response& res)
  {
    const auto& o = req.ode_joint_config;
    JointSettings settings;
    settings.damping = o.damping;
    settings.lower = o.loStop;
    settings.upper = o.hiStop;
    settings.fmax = o.fmax;
    settings.vel = o.vel;
    res.status_message = world_->setJointProperties(req.joint_name, settings);
    res.success = res.status_message.empty();
    if (!res.success)
    {
      res.status_message = "SetJointProperties: " + res.status_message;
      ROS_ERROR("gazebo_lite: %s", res.status_message.c_str());
      return true;
    }
    res.status_message = "SetJointProperties: properties set";
    return true;
  }

  // Joint positions at once, between two steps (gazebo_ros pauses the world for it). spawn_model -J.
  bool setModelConfiguration(SetModelConfiguration::Request& req, SetModelConfiguration::Response& res)
  {
    res.status_message = world_->setJointPositions(req.model_name, req.joint_names, req.joint_positions);
    res.success = res.status_message.empty();
    if (!res.success)
    {
      res.status_message = "SetModelConfiguration: " + res.status_message;
      ROS_ERROR("gazebo_lite: %s", res.status_message.c_str());
      return true;
    }
    res.status_message = "SetModelConfiguration: success";
    return true;
  }

  // max_update_rate is steps per wall second: real_time_factor / time_step. Of ode_config only
  // sor_pgs_iters means something here (Bullet's solver iterations); the rest is given as 0.
  bool getPhysicsProperties(GetPhysicsProperties::Request&, GetPhysicsProperties::Response& res)
  {
    res.time_step = world_->stepSize();
    res.pause = paused_;
    res.max_update_rate = rtf_ / world_->stepSize();
    const btVector3& g = world_->gravity();
    res.gravity = toMsg(g);
    res.ode_config.sor_pgs_iters = world_->solverIterations();
    res.success = true;
    res.status_message = "GetPhysicsProperties: got properties";
    return true;
  }

  // Takes effect from the next step. A value out of range is refused naming its field, and then
  // nothing is changed. Under lockstep the period must stay a whole number of steps.
  bool setPhysicsProperties(SetPhysicsProperties::Request& req, SetPhysicsProperties::Response& res)
  {
    const auto& g = req.gravity;
    std::string why = mybot_common::firstInvalid({{"time_step", req.time_step},
                                                  {"max_update_rate", req.max_update_rate},
                                                  {"gravity.x", g.x},
                                                  {"gravity.y", g.y},
                                                  {"gravity.z", g.z}},
                                                 kMaxCoordinate);
    const double period = steps_per_period_ * world_->stepSize();
    long steps = 0;  // of the new size in a lockstep period
    if (!why.empty())
      why = "refused: " + why;
    else if (!(req.time_step > 0 && req.time_step <= 0.01))
      why = "time_step " + mybot_common::formatNumber(req.time_step) + " out of (0, 0.01] s";
    else if (req.max_update_rate < 0)
      why = "max_update_rate must be >= 0 (0: as fast as possible)";
    else if (req.ode_config.sor_pgs_iters < 1 || req.ode_config.sor_pgs_iters > 1000)
      why = "ode_config.sor_pgs_iters " + std::to_string(req.ode_config.sor_pgs_iters) +
            " out of [1, 1000] (the solver's iterations a step)";
    else if (lockstep_ &&
             (steps = std::lround(period / req.time_step), std::fabs(steps * req.time_step - period) > 1e-9))
      why = "time_step " + mybot_common::formatNumber(req.time_step) + " s does not divide the lockstep period (" +
            mybot_common::formatNumber(period) + " s)";
    res.success = why.empty();
    if (!res.success)
    {
      res.status_message = "SetPhysicsProperties: " + why;
      ROS_ERROR("gazebo_lite: %s", res.status_message.c_str());
      return true;
    }
    if (req.time_step != world_->stepSize())
    {
      world_->setStepSize(req.time_step);
      if (lockstep_)
        steps_per_period_ = static_cast<int>(steps);
    }
    world_->setSolverIterations(static_cast<int>(req.ode_config.sor_pgs_iters));
    world_->setGravity(btVector3(g.x, g.y, g.z));
    rtf_ = req.max_update_rate * req.time_step;
    anchor();
    res.status_message = "physics engine updated";
    return true;
  }

  static geometry_msgs::Pose poseMsg(const Pose& s)
  {
    geometry_msgs::Pose p;
    toMsg(s.tf, p);
    return p;
  }

  bool setLinkState(SetLinkState::Request& req, SetLinkState::Response& res)
  {
    const std::string why = applyLinkState(req.link_state);
    res.success = why.empty();
    res.status_message = res.success ? "SetLinkState: success" : why;
    return true;
  }
  // Teleports a link (the service, and the topic /gazebo/set_link_state): see
  // PhysicsWorld::setLinkState. "" or why it refused, which is logged too.
  std::string applyLinkState(const gazebo_msgs::LinkState& m)
  {
    btTransform pose;
    btVector3 lin, ang;
    std::string why = readState("link_state", m.pose, m.twist, m.reference_frame, pose, lin, ang);
    bool moved_static = false;
    if (why.empty())
      why = world_->setLinkState(m.link_name, pose, lin, ang, &moved_static);
    if (moved_static)
      slices_->invalidate();  // the lasers' and cameras' static world
    if (!why.empty())
      ROS_ERROR("gazebo_lite: set_link_state '%s': %s", m.link_name.c_str(), why.c_str());
    return why;
  }
  // A ModelState's or LinkState's pose and twist, checked (`field` names the message in errors):
  // "" or why it is refused.
  static std::string readState(const std::string& field, const geometry_msgs::Pose& mp, const geometry_msgs::Twist& mt,
                               const std::string& reference_frame, btTransform& pose, btVector3& lin, btVector3& ang)
  {
    const std::string bad = mybot_common::firstInvalid({{"pose.position.x", mp.position.x},
                                                        {"pose.position.y", mp.position.y},
                                                        {"pose.position.z", mp.position.z},
                                                        {"pose.orientation.x", mp.orientation.x},
                                                        {"pose.orientation.y", mp.orientation.y},
                                                        {"pose.orientation.z", mp.orientation.z},
                                                        {"pose.orientation.w", mp.orientation.w},
                                                        {"twist.linear.x", mt.linear.x},
                                                        {"twist.linear.y", mt.linear.y},
                                                        {"twist.linear.z", mt.linear.z},
                                                        {"twist.angular.x", mt.angular.x},
                                                        {"twist.angular.y", mt.angular.y},
                                                        {"twist.angular.z", mt.angular.z}},
                                                       kMaxCoordinate);
    btQuaternion q(mp.orientation.x, mp.orientation.y, mp.orientation.z, mp.orientation.w);
    if (!bad.empty())
      return "refused: " + field + "." + bad;
    if (q.length2() < 1e-12)
      return "refused: " + field + ".pose.orientation is a zero quaternion";
    if (!reference_frame.empty() && reference_frame != "world" && reference_frame != "map")
      // Gazebo would place it relative to that entity; a pose taken as the world's instead
      // would teleport it somewhere else.
      return "refused: " + field + ".reference_frame '" + reference_frame + "' not supported (use world)";
    q.normalize();
    pose = btTransform(q, btVector3(mp.position.x, mp.position.y, mp.position.z));
    lin = btVector3(mt.linear.x, mt.linear.y, mt.linear.z);
    ang = btVector3(mt.angular.x, mt.angular.y, mt.angular.z);
    return "";
  }

  bool setState(SetModelState::Request& req, SetModelState::Response& res)
  {
    const std::string why = applyModelState(req.model_state);
    res.success = why.empty();
    res.status_message = res.success ? "SetModelState: set model state" : why;
    return true;
  }
  // Teleports a model (the service, and the topic /gazebo/set_model_state); "" or why it
  // refused, which is logged too (a topic has no reply).
  std::string applyModelState(const gazebo_msgs::ModelState& m)
  {
    btTransform pose;
    btVector3 lin, ang;
    const std::string why = readState("model_state", m.pose, m.twist, m.reference_frame, pose, lin, ang);
    if (!why.empty())
    {
      ROS_ERROR("gazebo_lite: set_model_state '%s' %s", m.model_name.c_str(), why.c_str());
      return why;
    }
    bool moved_static = false;
    const bool found = world_->setModelState(m.model_name, pose, lin, ang, &moved_static);
    if (moved_static)
      slices_->invalidate();  // the lasers' and cameras' static world
    if (!found)
    {
      ROS_ERROR("gazebo_lite: set_model_state: no model named '%s'", m.model_name.c_str());
      return "no model named '" + m.model_name + "'";
    }
    return "";
  }

  // /gazebo/model_states and /gazebo/link_states, as gazebo_ros publishes them: after every
  // physics step, while anyone listens (in the world frame; names as Gazebo's).
  void publishStates()
  {
    if (model_states_pub_.getNumSubscribers() > 0)
      model_states_pub_.publish(statesMessage<gazebo_msgs::ModelStates>(world_->modelStates()));
    if (link_states_pub_.getNumSubscribers() > 0)
      link_states_pub_.publish(statesMessage<gazebo_msgs::LinkStates>(world_->linkStates()));
  }
  template <class Msg>
  static Msg statesMessage(const std::vector<std::pair<std::string, Pose>>& states)
  {
    Msg m;
    for (const auto& [name, s] : states)
    {
      m.name.push_back(name);
      m.pose.push_back(poseMsg(s));
      m.twist.push_back(twistMsg(s));
    }
    return m;
  }

  ros::NodeHandle nh_, pnh_;
  std::unique_ptr<PhysicsWorld> world_;
  std::unique_ptr<StaticSliceCache> slices_;
  std::vector<ModelEntry> models_;
  std::vector<ros::ServiceServer> srvs_;
  ros::Publisher clock_pub_, contacts_pub_, model_states_pub_, link_states_pub_, metrics_pub_;
  std::chrono::steady_clock::time_point next_metrics_{}, metrics_wall_{};
  double metrics_sim_ = -1;  // sim time of the last performance report
  ros::Subscriber set_model_state_sub_, set_link_state_sub_;
  tf2_ros::TransformBroadcaster tfb_;
  int seed_ = 0;
  double rtf_ = 1, clock_hz_ = 100, last_clock_ = -1, last_contacts_ = -1, sim0_ = 0;
  bool paused_ = false;
  ros::WallTime wall0_;
  std::unique_ptr<mybot_lockstep::Coordinator> lockstep_;
  std::vector<std::string> wait_for_;
  int steps_per_period_ = 10;
};

}  // namespace mybot_gazebo_lite

int main(int argc, char** argv)
{
  bool loaded = true;  // init() has named what it refused (world, model, plugin, parameter)
  const int rc = mybot_common::runNode(argc, argv, "gazebo_lite",
                                       [&]
                                       {
                                         mybot_gazebo_lite::SimNode node;
                                         loaded = node.init();
                                         if (loaded)
                                           node.run();
                                       });
  return loaded ? rc : 1;
}
