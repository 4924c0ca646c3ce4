// Mutation fuzzing of the emulated plugins' parameters (scripts/fuzz --only plugin runs it, built
// with AddressSanitizer and UBSan, beside a ROS master of its own; not a gate test: what it finds
// depends on its seed and its time, and what it found becomes a test of the plugin).
//
//   fuzz_plugins plugin SECONDS SEED OUT_DIR INPUT...
//   INPUT: a URDF or an SDF model that has <plugin>s (SECONDS 0: each input once, unmutated)
//
// fuzz_loaders mutates whole files, so its mutations rarely land in a <plugin> or <sensor> block,
// and it builds no plugin: it has no ROS. Here each round mutates one or two of the input's
// <gazebo> blocks (a URDF) or <plugin> / <sensor> blocks (an SDF model) as fuzz_loaders mutates
// files, loads the robot into a world with a ground plane and a wall in front of it, makes every
// plugin as the simulator does (createPlugin: parameters read, publishers advertised) and steps
// the world 0.2 s with the plugins around each step, time sent back to 0 halfway (reset_simulation). What it checks:
//  - no crash, no sanitizer report (an absurd count turned into an int, an allocation of
//    terabytes), no hang (20 s a round): the process dies, current.plugin stays for scripts/fuzz;
//  - a refusal is a std::exception, as the simulator reports it (replayed, its message is printed);
//  - a robot whose plugins were all made stays finite: otherwise OUT_DIR/nonfinite-N.plugin.
#include "mybot_gazebo_lite/parsing.h"
#include "mybot_gazebo_lite/physics.h"
#include "mybot_gazebo_lite/ros/sim_plugin.h"
#include "mybot_common/fuzz.h"

#include <ros/ros.h>

#include <cmath>
#include <cstdio>
#include <random>
#include <string>
#include <vector>

using namespace mybot_gazebo_lite;

using mybot_common::fuzz::Mutator;

namespace
{
// What the sensors see: a wall 1.5 m ahead, across the robot's way, on a ground plane.
const char* const kWorld = R"(<sdf version="1.6"><world name="fuzz">
  <model name="wall"><static>true</static><pose>1.5 0 0.5 0 0 0</pose>
    <link name="l"><collision name="c"><geometry><box><size>0.2 4 1</size></box></geometry></collision></link>
  </model></world></sdf>)";

bool finite(const Pose& s)
{
  const btVector3& p = s.tf.getOrigin();
  const btQuaternion q = s.tf.getRotation();
  return std::isfinite(p.length2()) && std::isfinite(q.length2()) && std::isfinite(s.linear.length2()) &&
         std::isfinite(s.angular.length2());
}

// The blocks a plugin reads its parameters from: a URDF's <gazebo> blocks, an SDF model's
// <plugin> and <sensor> blocks, as (position, length).
std::vector<std::pair<size_t, size_t>> pluginBlocks(const std::string& text)
{
  const bool sdf = text.find("<sdf") != std::string::npos;
  std::vector<std::pair<size_t, size_t>> out;
  for (const char* tag : sdf ? std::vector<const char*>{"plugin", "sensor"} : std::vector<const char*>{"gazebo"})
  {
    const std::string open = std::string("<") + tag, close = std::string("</") + tag + ">";
    for (size_t at = text.find(open); at != std::string::npos; at = text.find(open, at + 1))
    {
      const size_t end = text.find(close, at);
      if (end != std::string::npos)
        out.emplace_back(at, end + close.size() - at);
    }
  }
  return out;
}

// `text` with one or two of its plugin blocks mutated (the whole text when it has none).
std::string mutatePlugins(const std::string& text, Mutator& mutator, std::mt19937& pick)
{
  const auto blocks = pluginBlocks(text);
  if (blocks.empty())
    return mutator.mutate(text);
  const auto [at, len] = blocks[std::uniform_int_distribution<size_t>(0, blocks.size() - 1)(pick)];
  std::string block = mutator.mutate(text.substr(at, len));
  if (std::uniform_int_distribution<int>(0, 3)(pick) == 0)  // now and then a second pass on it
    block = mutator.mutate(block);
  return text.substr(0, at) + block + text.substr(at + len);
}

class Harness
{
public:
  Harness()
  {
    world_spec_ = parseSdfWorld(kWorld, "fuzz world", ".");
    world_spec_.ground_plane = true;
  }

  // Loads one input, makes its plugins and steps 0.2 s; returns whether it stayed finite (true for
  // a refusal, whose message goes to `refusal`).
  bool run(const std::string& text, const std::string& base_dir, std::string* refusal)
  {
    try
    {
      std::shared_ptr<RobotSpec> spec;
      btTransform pose(btQuaternion::getIdentity(), btVector3(0, 0, 0.05));
      if (text.find("<sdf") != std::string::npos)
      {
        SdfSpawn spawn = parseSdfSpawn(text, "fuzz.plugin", base_dir);
        if (!spawn.robot)
          return true;  // a rigid model: no plugins run
        spec = spawn.robot;
        pose = pose * spawn.model.pose * spawn.root_in_model;
      }
      else
        spec = std::make_shared<RobotSpec>(parseUrdf(text, "fuzz.plugin"));
      PhysicsWorld world(world_spec_, {});
      StaticSliceCache slices(world.worldSpec());
      Robot& robot = world.addRobot(spec, "bot", "", pose);
      const bool paused = false;
      std::vector<std::mt19937> rngs(spec->plugins.size());
      std::vector<std::unique_ptr<SimPlugin>> plugins;
      for (size_t i = 0; i < spec->plugins.size(); ++i)
      {
        PluginContext ctx;  // as the simulator makes it, without lockstep
        ctx.world = &world;
        ctx.robot = &robot;
        ctx.spec = &spec->plugins[i];
        if (const XmlNode* rn = ctx.spec->xml.child("robotNamespace"))
          ctx.ns = rn->text;
        ctx.tf = &tf_;
        ctx.slices = &slices;
        ctx.rng = &rngs[i];
        ctx.paused = &paused;
        if (auto plugin = createPlugin(ctx))
          plugins.push_back(std::move(plugin));
      }
      for (int i = 0; i < 200; ++i)
      {
        if (i == 100)  // reset_simulation halfway: time jumps back to 0, as the simulator's service does it
        {
          world.resetTime();
          world.resetWorld();
          for (auto& p : plugins)
            p->reset();
        }
        for (auto& p : plugins)
          p->preStep(world.time());
        world.step();
        for (auto& p : plugins)
          p->update(world.time());
      }
      for (const auto& [name, state] : world.linkStates())
        if (!finite(state))
        {
          std::fprintf(stderr, "  link %s is not finite after 0.2 s\n", name.c_str());
          return false;
        }
      return true;
    }
    catch (const std::exception& e)
    {
      if (refusal)
        *refusal = e.what();
      return true;
    }
  }

private:
  WorldSpec world_spec_;
  tf2_ros::TransformBroadcaster tf_;
};

}  // namespace

int main(int argc, char** argv)
{
  ros::init(argc, argv, "fuzz_plugins", ros::init_options::AnonymousName | ros::init_options::NoRosout);
  if (argc < 6 || std::string(argv[1]) != "plugin")
  {
    std::fprintf(stderr, "usage: fuzz_plugins plugin SECONDS SEED OUT_DIR INPUT...\n");
    return 2;
  }
  if (!ros::master::check())
  {
    std::fprintf(stderr, "fuzz_plugins: no ROS master at %s (scripts/fuzz starts one)\n",
                 ros::master::getURI().c_str());
    return 2;
  }
  ros::console::set_logger_level(ROSCONSOLE_DEFAULT_NAME, ros::console::levels::Error);  // no per-round warnings
  ros::console::notifyLoggerLevelsChanged();
  Harness harness;
  return mybot_common::fuzz::drive(
      "plugin", std::atof(argv[2]), static_cast<unsigned>(std::atol(argv[3])), argv[4],
      mybot_common::fuzz::readInputs(argc, argv, 5),
      [&](const std::string& text, const std::string& dir)
      {
        mybot_common::fuzz::Outcome o;
        o.finite = harness.run(text, dir, &o.what);
        o.taken = o.what.empty();
        if (o.taken)
          o.what = "simulated";
        return o;
      },
      mutatePlugins);
}
