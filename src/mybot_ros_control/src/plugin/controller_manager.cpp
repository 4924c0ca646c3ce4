#include "mybot_ros_control/ros/controller_manager.h"

#include <algorithm>
#include <set>

namespace mybot_ros_control
{

namespace mgl = mybot_gazebo_lite;
namespace cmm = controller_manager_msgs;

namespace
{
constexpr int kBestEffort = cmm::SwitchController::Request::BEST_EFFORT;
constexpr int kStrict = cmm::SwitchController::Request::STRICT;

std::set<std::string> resources(const Controller& c)
{
  std::set<std::string> out;
  for (const auto& [iface, joints] : c.claimed())
    out.insert(joints.begin(), joints.end());
  return out;
}
}  // namespace

ControllerManager::ControllerManager(RobotHWSim& hw, const mgl::PluginContext& plugin, const ros::NodeHandle& root)
    : hw_(hw), plugin_(plugin), root_(root)
{
  ros::NodeHandle cm(root_, "controller_manager");
  services_.push_back(cm.advertiseService("load_controller", &ControllerManager::onLoad, this));
  services_.push_back(cm.advertiseService("unload_controller", &ControllerManager::onUnload, this));
  services_.push_back(cm.advertiseService("switch_controller", &ControllerManager::onSwitch, this));
  services_.push_back(cm.advertiseService("list_controllers", &ControllerManager::onList, this));
  services_.push_back(cm.advertiseService("list_controller_types", &ControllerManager::onListTypes, this));
  services_.push_back(cm.advertiseService("reload_controller_libraries", &ControllerManager::onReload, this));
}

std::string ControllerManager::service(const std::string& name) const
{
  return root_.resolveName("controller_manager/" + name);
}

ControllerManager::Entry* ControllerManager::find(const std::string& name)
{
  for (auto& e : entries_)
    if (e.name == name)
      return &e;
  return nullptr;
}

void ControllerManager::update(double t, double dt)
{
  for (auto& e : entries_)
    if (e.state == State::RUNNING && e.start_pending)
    {
      e.controller->starting(t);
      e.start_pending = false;
    }
  for (auto& e : entries_)
    if (e.state == State::RUNNING)
      e.controller->update(t, dt);
}

void ControllerManager::restart(double t)
{
  for (auto& e : entries_)
    if (e.state == State::RUNNING && !e.start_pending)  // a pending one starts at the next update
    {
      e.controller->stopping(t);
      e.controller->starting(t);
    }
}

std::string ControllerManager::load(const std::string& name)
{
  if (name.empty())
    return "the controller name is empty";
  if (find(name))
    return "a controller named '" + name + "' is already loaded";
  ros::NodeHandle nh(root_, name);
  std::string type;
  if (!nh.getParam("type", type))
    return "controller '" + name + "': no parameter " + nh.resolveName("type") +
           " (load the controller's YAML onto the parameter server first)";
  const auto& types = controllerTypes();
  auto it = types.find(type);
  if (it == types.end())
  {
    std::string known;
    for (const auto& [k, f] : types)
      known += (known.empty() ? "" : ", ") + k;
    return "controller '" + name + "': parameter " + nh.resolveName("type") + ": unknown type '" + type +
           "' (known: " + known + ")";
  }
  ControllerContext ctx{name, type, &hw_, &plugin_, root_, nh};
  try
  {
    Entry e;
    e.name = name;
    e.type = type;
    e.controller = it->second(ctx);
    entries_.push_back(std::move(e));
  }
  catch (const ControllerError& err)
  {
    return err.what();
  }
  catch (const std::runtime_error& err)
  {  // a ParamError of the readers shared with mybot_control
    return "controller '" + name + "' (" + type + "): " + err.what();
  }
  return "";
}

std::string ControllerManager::unload(const std::string& name)
{
  Entry* e = find(name);
  if (!e)
    return "no controller named '" + name + "' is loaded";
  if (e->state == State::RUNNING)
    return "controller '" + name + "' is running: stop it before unloading it";
  entries_.erase(entries_.begin() + (e - entries_.data()));
  return "";
}

std::string ControllerManager::switchControllers(const std::vector<std::string>& start,
                                                 const std::vector<std::string>& stop, int strictness)
{
  if (strictness == 0)
    strictness = kBestEffort;  // as upstream, with its warning
  if (strictness != kBestEffort && strictness != kStrict)
    return "strictness " + std::to_string(strictness) + " is neither BEST_EFFORT (1) nor STRICT (2)";
  const double t = plugin_.world->time();
  std::string problems;
  auto problem = [&](const std::string& p) { problems += (problems.empty() ? "" : "; ") + p; };
  std::vector<Entry*> to_stop, to_start;
  for (const auto& n : stop)
  {
    Entry* e = find(n);
    if (!e)
      problem("cannot stop '" + n + "': not loaded");
    else if (e->state != State::RUNNING)
      problem("cannot stop '" + n + "': not running");
    else
      to_stop.push_back(e);
  }
  // A joint may be commanded by one running controller at a time.
  std::map<std::string, std::string> owner;
  for (auto& e : entries_)
    if (e.state == State::RUNNING && std::find(to_stop.begin(), to_stop.end(), &e) == to_stop.end())
      for (const auto& r : resources(*e.controller))
        owner[r] = e.name;
  for (const auto& n : start)
  {
    Entry* e = find(n);
    if (!e)
    {
      problem("cannot start '" + n + "': not loaded");
      continue;
    }
    if (e->state == State::RUNNING && std::find(to_stop.begin(), to_stop.end(), e) == to_stop.end())
    {
      problem("cannot start '" + n + "': already running");
      continue;
    }
    std::string conflict;
    for (const auto& r : resources(*e->controller))
      if (owner.count(r))
        conflict = "joint '" + r + "' is commanded by '" + owner[r] + "'";
    if (!conflict.empty())
    {
      problem("cannot start '" + n + "': " + conflict);
      continue;
    }
    for (const auto& r : resources(*e->controller))
      owner[r] = n;
    to_start.push_back(e);
  }
  if (!problems.empty() && strictness == kStrict)
    return problems + " (STRICT: nothing switched)";
  for (Entry* e : to_stop)
  {
    if (!e->start_pending)  // one that never started has nothing to stop
      e->controller->stopping(t);
    e->state = State::STOPPED;
    e->start_pending = false;
  }
  const bool paused = plugin_.paused && *plugin_.paused;
  if (!to_start.empty() && !paused)
    hw_.read(*plugin_.robot);  // the joints now, not at the last control period
  for (Entry* e : to_start)
  {
    e->state = State::RUNNING;
    e->start_pending = paused;
    if (!paused)
      e->controller->starting(t);
  }
  if (!problems.empty())
    ROS_WARN("%s: %s (BEST_EFFORT)", service("switch_controller").c_str(), problems.c_str());
  return "";
}

bool ControllerManager::onLoad(cmm::LoadController::Request& req, cmm::LoadController::Response& res)
{
  // controller_manager_msgs' replies carry only `ok`; why a call failed goes to the log, as
  // upstream's controller manager reports it, after the service's full name (the spawner reads it
  // from /rosout_agg).
  const std::string why = load(req.name);
  res.ok = why.empty();
  if (res.ok)
    ROS_INFO("%s: loaded '%s' (%s)", service("load_controller").c_str(), req.name.c_str(),
             find(req.name)->type.c_str());
  else
    ROS_ERROR("%s: %s", service("load_controller").c_str(), why.c_str());
  return true;
}

bool ControllerManager::onUnload(cmm::UnloadController::Request& req, cmm::UnloadController::Response& res)
{
  const std::string why = unload(req.name);
  res.ok = why.empty();
  if (!res.ok)
    ROS_ERROR("%s: %s", service("unload_controller").c_str(), why.c_str());
  return true;
}

bool ControllerManager::onSwitch(cmm::SwitchController::Request& req, cmm::SwitchController::Response& res)
{
  const std::string why = switchControllers(req.start_controllers, req.stop_controllers, req.strictness);
  res.ok = why.empty();
  if (!res.ok)
    ROS_ERROR("%s: %s", service("switch_controller").c_str(), why.c_str());
  return true;
}

bool ControllerManager::onList(cmm::ListControllers::Request&, cmm::ListControllers::Response& res)
{
  for (const auto& e : entries_)
  {
    cmm::ControllerState s;
    s.name = e.name;
    s.type = e.type;
    s.state = e.state == State::RUNNING ? "running" : e.state == State::STOPPED ? "stopped" : "initialized";
    for (const auto& [iface, joints] : e.controller->claimed())
    {
      cmm::HardwareInterfaceResources r;
      r.hardware_interface = iface;
      r.resources = joints;
      s.claimed_resources.push_back(r);
    }
    res.controller.push_back(s);
  }
  return true;
}

bool ControllerManager::onListTypes(cmm::ListControllerTypes::Request&, cmm::ListControllerTypes::Response& res)
{
  for (const auto& [type, f] : controllerTypes())
  {
    res.types.push_back(type);
    res.base_classes.push_back("controller_interface::ControllerBase");
  }
  return true;
}

bool ControllerManager::onReload(cmm::ReloadControllerLibraries::Request& req,
                                 cmm::ReloadControllerLibraries::Response& res)
{
  // The controllers are built in: nothing to reload. As upstream, loaded controllers block it
  // unless force_kill, which stops and unloads them.
  if (!entries_.empty() && !req.force_kill)
  {
    res.ok = false;
    ROS_ERROR("%s: %zu controllers are loaded; unload them or call with force_kill",
              service("reload_controller_libraries").c_str(), entries_.size());
    return true;
  }
  const double t = plugin_.world->time();
  for (auto& e : entries_)
    if (e.state == State::RUNNING && !e.start_pending)
      e.controller->stopping(t);
  entries_.clear();
  res.ok = true;
  return true;
}

}  // namespace mybot_ros_control
