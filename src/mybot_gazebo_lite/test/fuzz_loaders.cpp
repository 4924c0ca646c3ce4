// Mutation fuzzing of the model loaders and of the physics they build (scripts/fuzz runs it,
// built with AddressSanitizer and UBSan; not a gate test: what it finds depends on its seed and
// its time, and what it found becomes a gtest in test_loaders.cpp or test_physics.cpp).
//
//   fuzz_loaders KIND SECONDS SEED OUT_DIR INPUT...
//   KIND: urdf | world | sdf_model | image_world (a map_server YAML naming its image by an absolute
//   path) | pgm (an image, loaded through a fixed YAML)
//   (SECONDS 0: each input once, unmutated: the kept findings' replay)
//
// Each round takes one of the inputs, mutates it one to four times where a hand edit or a broken
// generator would (a number becomes nan, -1, 0 or 1e308; an attribute takes another one's value;
// a line is lost, doubled or moved; the file is cut short; a byte flips), writes it to
// OUT_DIR/current.KIND, loads it and, when the loader takes it, builds it in a PhysicsWorld and
// steps it for 0.2 s. What it checks:
//  - no crash, no sanitizer report, no hang (20 s a round): the process dies, current.KIND stays
//    for scripts/fuzz to keep;
//  - a refusal is a std::exception (replayed, its message is printed);
//  - a model the loader took stays finite in the simulation: otherwise OUT_DIR/nonfinite-N.KIND.
// Structured mutations find more than byte flips: the loaders reject most non-XML at once.
#include "mybot_gazebo_lite/parsing.h"
#include "mybot_gazebo_lite/physics.h"
#include "mybot_common/fuzz.h"

#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

using namespace mybot_gazebo_lite;

using mybot_common::fuzz::spit;

namespace
{
bool finite(const btTransform& tf)
{
  const btVector3& p = tf.getOrigin();
  const btQuaternion q = tf.getRotation();
  return std::isfinite(p.x()) && std::isfinite(p.y()) && std::isfinite(p.z()) && std::isfinite(q.w()) &&
         std::isfinite(q.x()) && std::isfinite(q.y()) && std::isfinite(q.z());
}

// Steps the world for 0.2 s and tells whether every link and model stayed finite.
bool simulatesFinitely(PhysicsWorld& world)
{
  for (int i = 0; i < 200; ++i)
    world.step();
  for (const auto& [name, pose] : world.linkStates())
    if (!finite(pose.tf) || !std::isfinite(pose.linear.length2()) || !std::isfinite(pose.angular.length2()))
    {
      std::fprintf(stderr, "  link %s is not finite after 0.2 s\n", name.c_str());
      return false;
    }
  return true;
}

WorldSpec ground()
{
  WorldSpec w;
  w.ground_plane = true;
  return w;
}

// Loads one input as KIND; returns whether the simulation stayed finite (true for a refusal, whose
// message goes to `refusal`).
bool run(const std::string& kind, const std::string& text, const std::string& base_dir, std::string* refusal = nullptr)
{
  const std::string source = "fuzz." + kind;
  try
  {
    if (kind == "urdf")
    {
      auto spec = std::make_shared<RobotSpec>(parseUrdf(text, source));
      PhysicsWorld world(ground(), {});
      world.addRobot(spec, "bot", "", btTransform(btQuaternion::getIdentity(), btVector3(0, 0, 0.05)));
      return simulatesFinitely(world);
    }
    if (kind == "world")
    {
      PhysicsWorld world(parseSdfWorld(text, source, base_dir), {});
      return simulatesFinitely(world);
    }
    if (kind == "image_world" || kind == "pgm")
    {
      // image_world: a map_server YAML, its image's path made absolute in the seed; pgm: an image,
      // read through a fixed YAML. Both as the simulator loads a floor plan, header check first.
      const std::string yaml = base_dir + "/current." + kind + ".yaml";
      if (kind == "image_world")
        spit(yaml, text);
      else
      {
        spit(base_dir + "/current.pgm", text);
        spit(yaml,
             "image: current.pgm\nresolution: 0.05\norigin: [0.0, 0.0, 0.0]\nnegate: 0\n"
             "occupied_thresh: 0.65\nfree_thresh: 0.196\n");
      }
      PhysicsWorld world(loadWorldFile(yaml), {});
      return simulatesFinitely(world);
    }
    SdfSpawn spawn = parseSdfSpawn(text, source, base_dir);
    PhysicsWorld world(ground(), {});
    if (spawn.robot)
      world.addRobot(spawn.robot, "m", "", spawn.root_in_model);
    else
      world.addModel(spawn.model);
    return simulatesFinitely(world);
  }
  catch (const std::exception& e)
  {
    if (refusal)
      *refusal = e.what();
    return true;
  }
}

}  // namespace

int main(int argc, char** argv)
{
  if (argc < 6)
  {
    std::fprintf(stderr, "usage: fuzz_loaders urdf|world|sdf_model|image_world|pgm SECONDS SEED OUT_DIR INPUT...\n");
    return 2;
  }
  const std::string kind = argv[1], out = argv[4];
  if (kind != "urdf" && kind != "world" && kind != "sdf_model" && kind != "image_world" && kind != "pgm")
  {
    std::fprintf(stderr, "fuzz_loaders: KIND is urdf, world, sdf_model, image_world or pgm, not '%s'\n", kind.c_str());
    return 2;
  }
  const bool image = kind == "image_world" || kind == "pgm";  // loaded from files written to OUT_DIR
  return mybot_common::fuzz::drive(kind, std::atof(argv[2]), static_cast<unsigned>(std::atol(argv[3])), out,
                                   mybot_common::fuzz::readInputs(argc, argv, 5, image ? out : ""),
                                   [&](const std::string& text, const std::string& dir)
                                   {
                                     mybot_common::fuzz::Outcome o;
                                     o.finite = run(kind, text, dir, &o.what);
                                     o.taken = o.what.empty();
                                     if (o.taken)
                                       o.what = "simulated";
                                     return o;
                                   });
}
