#include "mybot_gazebo_lite/camera_model.h"
#include "mybot_gazebo_lite/parsing.h"
#include "mybot_gazebo_lite/physics.h"

#include <BulletDynamics/Featherstone/btMultiBody.h>
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <functional>
#include <map>
#include <sstream>
#include <tuple>

using namespace mybot_gazebo_lite;

namespace
{
std::string fixture(const std::string& name)
{
  std::ifstream f(std::string(FIXTURE_DIR) + "/" + name);
  std::stringstream ss;
  ss << f.rdbuf();
  return ss.str();
}

WorldSpec flatWorld()
{
  WorldSpec w;
  w.ground_plane = true;
  return w;
}

// A model of one box link centred at `center`.
WorldModel boxModel(const std::string& name, const btVector3& center, const btVector3& size, bool is_static)
{
  WorldModel m;
  m.name = name;
  m.is_static = is_static;
  m.pose.setOrigin(center);
  WorldLink l;
  l.name = "link";
  Shape box;
  box.size = size;
  l.shapes.push_back(box);
  m.links.push_back(l);
  return m;
}

// An arm: a 4 kg base and a 0.5 m, 1 kg link on a shoulder about y, 0.1 m above the base. `shoulder`
// is the shoulder's type and what follows its axis; `rooted`: fixed 1 m above the world by a
// `world` link, as UR's and most arms' descriptions are.
std::string armUrdf(bool rooted, const std::string& shoulder)
{
  const std::string world = R"(<link name="world"/>
    <joint name="world_joint" type="fixed"><parent link="world"/><child link="base_link"/>
      <origin xyz="0 0 1.0"/></joint>)";
  return "<robot name='arm'>" + (rooted ? world : std::string()) + R"(<link name="base_link">
      <collision><geometry><box size="0.2 0.2 0.1"/></geometry></collision>
      <inertial><mass value="4"/><inertia ixx="0.02" ixy="0" ixz="0" iyy="0.02" iyz="0" izz="0.03"/></inertial>
    </link>
    <link name="arm_link">
      <collision><origin xyz="0.25 0 0"/><geometry><box size="0.5 0.05 0.05"/></geometry></collision>
      <inertial><origin xyz="0.25 0 0"/><mass value="1"/>
        <inertia ixx="0.0004" ixy="0" ixz="0" iyy="0.021" iyz="0" izz="0.021"/></inertial>
    </link>
    <joint name="shoulder" type=")" +
         shoulder + R"(</joint></robot>)";
}

// armUrdf rooted, its shoulder a revolute about y with limits [-2, 2] rad: horizontal at 0, gravity
// pitches it down (+). `dynamics`: a <dynamics> element, or nothing.
std::shared_ptr<RobotSpec> pitchingArm(const std::string& dynamics = "")
{
  return std::make_shared<RobotSpec>(
      parseUrdf(armUrdf(true, R"(revolute"><parent link="base_link"/><child link="arm_link"/>
      <origin xyz="0 0 0.1"/><axis xyz="0 1 0"/><limit lower="-2" upper="2" effort="50" velocity="5"/>)" +
                                  dynamics),
                "arm.urdf"));
}

void run(PhysicsWorld& w, double seconds)
{
  int n = static_cast<int>(std::lround(seconds / w.stepSize()));
  for (int i = 0; i < n; ++i)
    w.step();
}
}  // namespace

TEST(Physics, LumpsFixedJointsAndKeepsMovableOnes)
{
  auto spec = std::make_shared<RobotSpec>(parseUrdf(fixture("diffbot.urdf"), "diffbot.urdf"));
  PhysicsWorld w(flatWorld(), {});
  Robot& r = w.addRobot(spec, "bot", "", btTransform::getIdentity());
  EXPECT_EQ(r.multibody()->getNumLinks(), 2);
  EXPECT_TRUE(r.hasJoint("left_wheel_hinge"));
  EXPECT_FALSE(r.hasJoint("caster_front_joint"));
  // base_link is 0.1 m above the footprint.
  EXPECT_NEAR(r.linkState("base_link").tf.getOrigin().z(), 0.1, 1e-9);
  EXPECT_NEAR(r.linkState("left_wheel").tf.getOrigin().y(), 0.15, 1e-9);
}

TEST(Physics, RestsWithoutDrift)
{
  auto spec = std::make_shared<RobotSpec>(parseUrdf(fixture("diffbot.urdf"), "diffbot.urdf"));
  PhysicsWorld w(flatWorld(), {});
  Robot& r = w.addRobot(spec, "bot", "", btTransform(btQuaternion::getIdentity(), btVector3(0, 0, 0.005)));
  r.commandVelocity("left_wheel_hinge", 0, 5);
  r.commandVelocity("right_wheel_hinge", 0, 5);
  run(w, 3.0);
  btVector3 p0 = r.linkState("base_footprint").tf.getOrigin();
  EXPECT_NEAR(p0.z(), 0.0, 0.003);
  run(w, 120.0);
  btVector3 p1 = r.linkState("base_footprint").tf.getOrigin();
  EXPECT_LT((p1 - p0).length(), 1e-4);
}

TEST(Physics, DrivesStraightAtWheelSpeed)
{
  auto spec = std::make_shared<RobotSpec>(parseUrdf(fixture("diffbot.urdf"), "diffbot.urdf"));
  PhysicsWorld w(flatWorld(), {});
  Robot& r = w.addRobot(spec, "bot", "", btTransform::getIdentity());
  run(w, 1.0);
  btVector3 p0 = r.linkState("base_footprint").tf.getOrigin();
  r.commandVelocity("left_wheel_hinge", 5.0, 20);
  r.commandVelocity("right_wheel_hinge", 5.0, 20);
  run(w, 4.0);
  btVector3 p1 = r.linkState("base_footprint").tf.getOrigin();
  EXPECT_NEAR(p1.x() - p0.x(), 2.0, 0.04);
  EXPECT_NEAR(p1.y() - p0.y(), 0.0, 0.02);
  EXPECT_NEAR(r.jointVelocity("left_wheel_hinge"), 5.0, 0.05);
}

TEST(Physics, PositionCommandReachesTarget)
{
  auto spec = std::make_shared<RobotSpec>(parseUrdf(fixture("diffbot.urdf"), "diffbot.urdf"));
  PhysicsWorld w(flatWorld(), {});
  Robot& r = w.addRobot(spec, "bot", "", btTransform(btQuaternion::getIdentity(), btVector3(0, 0, 1.0)));
  // In the air: the wheel is free to turn.
  r.commandPosition("left_wheel_hinge", 1.0, 5);
  run(w, 0.3);
  EXPECT_NEAR(r.jointPosition("left_wheel_hinge"), 1.0, 0.01);
}

TEST(Physics, CountsContactsWithObstaclesNotTheGround)
{
  auto spec = std::make_shared<RobotSpec>(parseUrdf(fixture("diffbot.urdf"), "diffbot.urdf"));
  WorldSpec world = flatWorld();
  world.models.push_back(boxModel("wall", btVector3(1.5, 0, 0.25), btVector3(0.2, 2.0, 0.5), true));
  PhysicsWorld w(world, {});
  Robot& r = w.addRobot(spec, "bot", "", btTransform::getIdentity());
  run(w, 1.0);  // settled on the ground plane: no contact
  EXPECT_EQ(r.contacts().steps, 0u);
  EXPECT_TRUE(r.contacts().now.empty());
  r.commandVelocity("left_wheel_hinge", 5.0, 20);
  r.commandVelocity("right_wheel_hinge", 5.0, 20);
  run(w, 3.0);  // 0.5 m/s: reaches the wall's face (x = 1.4) within 3 s and pushes
  EXPECT_GT(r.contacts().steps, 100u);
  EXPECT_EQ(r.contacts().first_model, "wall");
  EXPECT_GT(r.contacts().first_time, 1.0);
  EXPECT_GT(r.contacts().max_depth, 0.0);
  ASSERT_EQ(r.contacts().now.size(), 1u);
  EXPECT_EQ(r.contacts().now[0], "wall");
  w.resetWorld();
  EXPECT_EQ(r.contacts().steps, 0u);
  EXPECT_LT(r.contacts().first_time, 0.0);
}

// What a camera draws besides the static world: every other robot's and every dynamic body's
// shapes where they stand at this frame, never the camera's own robot.
TEST(Physics, CamerasSeeOtherRobotsAndDynamicBodiesWhereTheyStand)
{
  auto spec = std::make_shared<RobotSpec>(parseUrdf(fixture("diffbot.urdf"), "diffbot.urdf"));
  WorldSpec world = flatWorld();
  // A dynamic green 0.3 m cube at (0, 2).
  WorldModel crate = boxModel("crate", btVector3(0, 2, 0.15), btVector3(0.3, 0.3, 0.3), false);
  crate.links[0].has_color = true;
  crate.links[0].color[0] = 0.0f;
  crate.links[0].color[1] = 1.0f;
  crate.links[0].color[2] = 0.0f;
  world.models.push_back(crate);
  PhysicsWorld w(world, {});
  Robot& me = w.addRobot(spec, "me", "", btTransform::getIdentity());
  Robot& other = w.addRobot(spec, "other", "", makeTransform(btVector3(2, 0, 0), btVector3(0, 0, 0)));
  run(w, 0.5);

  // The other robot's six collisions (chassis, two casters, two wheels, the laser's box) and the
  // crate; none of mine.
  const std::vector<PlacedShape> seen = w.movingShapes(&me);
  ASSERT_EQ(seen.size(), 7u);
  EXPECT_EQ(w.movingShapes(nullptr).size(), 13u);
  EXPECT_EQ(w.movingShapes(&other).size(), 7u);
  const btVector3 chassis = other.linkPose("chassis").getOrigin();
  EXPECT_NEAR(seen[0].tf.getOrigin().x(), chassis.x(), 1e-9);
  EXPECT_NEAR(chassis.x(), 2.0, 0.01);

  // My camera, level 0.2 m ahead of my base at the chassis's height, looking along +x: the other
  // robot's chassis's back face at x = 1.8 fills the centre of the image.
  const CameraIntrinsics k = gazeboIntrinsics(81, 61, 1.0);
  RenderSettings settings;
  std::vector<float> depth(81 * 61);
  std::vector<uint8_t> rgb(81 * 61 * 3);
  const PrismScene empty_world(world);  // its static part: nothing but the ground
  const double z = chassis.z();
  PrismScene moving(seen);
  renderCamera(empty_world, &moving, k, CameraPose{0.2, 0, z, 0}, settings, rgb.data(), depth.data());
  EXPECT_NEAR(depth[30 * 81 + 40], 1.6, 0.01);
  // Turned to the crate at (0, 2): its face at y = 1.85, in its own colour.
  renderCamera(empty_world, &moving, k, CameraPose{0, 0, 0.15, M_PI / 2}, settings, rgb.data(), depth.data());
  EXPECT_NEAR(depth[30 * 81 + 40], 1.85, 0.01);
  const uint8_t* px = &rgb[(30 * 81 + 40) * 3];
  EXPECT_EQ(px[0], 0);
  EXPECT_GT(px[1], 200);
  EXPECT_EQ(px[2], 0);

  // Moved, the other robot is drawn where it stands now, one metre farther.
  w.setModelState("other", makeTransform(btVector3(3, 0, 0), btVector3(0, 0, 0)), btVector3(0, 0, 0),
                  btVector3(0, 0, 0));
  run(w, 0.2);
  moving = PrismScene(w.movingShapes(&me));
  renderCamera(empty_world, &moving, k, CameraPose{0.2, 0, other.linkPose("chassis").getOrigin().z(), 0}, settings,
               nullptr, depth.data());
  EXPECT_NEAR(depth[30 * 81 + 40], 2.6, 0.01);
  // Without the moving scene, as before, the cameras see only the static world: the floor.
  renderCamera(empty_world, k, CameraPose{0.2, 0, z, 0}, settings, nullptr, depth.data());
  EXPECT_GT(depth[30 * 81 + 40], 1e6);
}

// /gazebo/model_states and /gazebo/link_states: every model in the order it came into the world; a
// model's pose is its own frame, not its link's; links are named "model::link".
TEST(Physics, ListsEveryModelAndLinkInGazebosOrder)
{
  auto spec = std::make_shared<RobotSpec>(parseUrdf(fixture("diffbot.urdf"), "diffbot.urdf"));
  WorldSpec world = flatWorld();
  world.models.push_back(boxModel("wall", btVector3(3, 0, 0.5), btVector3(0.1, 2, 1), true));
  // A dynamic crate whose link sits 0.5 m along the model's x, the model turned 90 degrees.
  WorldModel crate = boxModel("crate", btVector3(0, 2, 0.15), btVector3(0.3, 0.3, 0.3), false);
  crate.pose.setRotation(btQuaternion(btVector3(0, 0, 1), M_PI / 2));
  crate.links[0].pose.setOrigin(btVector3(0.5, 0, 0));
  world.models.push_back(crate);
  PhysicsWorld w(world, {});
  w.addRobot(spec, "second", "", makeTransform(btVector3(-2, 0, 0), btVector3(0, 0, 0)));
  w.addRobot(spec, "first", "", btTransform::getIdentity());
  w.addModel(boxModel("late", btVector3(0, -3, 0.5), btVector3(0.2, 0.2, 1), true));  // spawned after them
  run(w, 0.2);

  const auto models = w.modelStates();
  std::vector<std::string> names;
  for (const auto& [name, state] : models)
    names.push_back(name);
  EXPECT_EQ(names, (std::vector<std::string>{"ground_plane", "wall", "crate", "second", "first", "late"}));
  for (const auto& [name, state] : models)
  {
    Pose one;
    ASSERT_TRUE(w.getModelState(name, one)) << name;
    EXPECT_EQ(one.tf.getOrigin(), state.tf.getOrigin()) << name;
  }
  // The crate's model frame stays where the world put it; its link is 0.5 m along the turned x.
  EXPECT_NEAR(models[2].second.tf.getOrigin().x(), 0.0, 1e-3);
  EXPECT_NEAR(models[2].second.tf.getOrigin().y(), 2.0, 1e-3);
  EXPECT_NEAR(models[3].second.tf.getOrigin().x(), -2.0, 0.01);

  const auto links = w.linkStates();
  std::map<std::string, btVector3> at;
  for (const auto& [name, state] : links)
    at[name] = state.tf.getOrigin();
  EXPECT_EQ(links.front().first, "ground_plane::link");
  ASSERT_TRUE(at.count("crate::link"));
  EXPECT_NEAR(at["crate::link"].x(), 0.0, 1e-3);
  EXPECT_NEAR(at["crate::link"].y(), 2.5, 1e-3);
  // Every URDF link of each robot, lumped ones included, where the robot's own query puts it.
  for (const auto& l : spec->links)
  {
    ASSERT_TRUE(at.count("first::" + l.name)) << l.name;
    EXPECT_EQ(at["first::" + l.name], w.robots().back()->linkState(l.name).tf.getOrigin()) << l.name;
  }
}

// The links a vacuum gripper may take: of moving models only, within the radius, none of the asker's,
// each with the state linkStates() gives it.
TEST(Physics, FindsTheMovingLinksNearAPoint)
{
  auto spec = std::make_shared<RobotSpec>(parseUrdf(fixture("diffbot.urdf"), "diffbot.urdf"));
  WorldSpec world = flatWorld();
  world.models.push_back(boxModel("pillar", btVector3(0.5, 0.5, 0.5), btVector3(0.1, 0.1, 1), true));
  world.models.push_back(boxModel("crate", btVector3(0.6, 0.4, 0.15), btVector3(0.1, 0.1, 0.1), false));
  PhysicsWorld w(world, {});
  w.addRobot(spec, "near", "", btTransform::getIdentity());
  w.addRobot(spec, "asker", "", makeTransform(btVector3(0.3, 0.3, 0), btVector3(0, 0, 0)));
  w.addRobot(spec, "far", "", makeTransform(btVector3(-5, 0, 0), btVector3(0, 0, 0)));
  run(w, 0.2);
  w.setRobotVelocity(*w.robot("near"), btVector3(0.2, 0, 0), btVector3(0, 0, 0.5));  // velocities to compare

  const auto all = w.linkStates();
  for (const double radius : {0.05, 0.3, 0.6, 1.0})
  {
    const btVector3 centre(0.5, 0.4, 0.1);
    std::vector<std::pair<std::string, Pose>> expected;
    for (const auto& [name, state] : all)
    {
      const std::string model = name.substr(0, name.find("::"));
      if (model != "asker" && model != "pillar" && model != "ground_plane" &&
          (state.tf.getOrigin() - centre).length() < radius)
        expected.emplace_back(name, state);
    }
    const auto near = w.movingLinksNear(centre, radius, "asker");
    ASSERT_EQ(near.size(), expected.size()) << radius;
    for (size_t i = 0; i < near.size(); ++i)
    {
      EXPECT_EQ(near[i].first, expected[i].first);
      EXPECT_EQ(near[i].second.tf.getOrigin(), expected[i].second.tf.getOrigin()) << near[i].first;
      EXPECT_EQ(near[i].second.linear, expected[i].second.linear) << near[i].first;
      EXPECT_EQ(near[i].second.angular, expected[i].second.angular) << near[i].first;
    }
    if (radius == 1.0)  // the scene holds what the test means to tell apart
    {
      EXPECT_TRUE(std::any_of(near.begin(), near.end(), [](const auto& n) { return n.first == "crate::link"; }));
      EXPECT_TRUE(std::any_of(near.begin(), near.end(), [](const auto& n) { return n.first.rfind("near::", 0) == 0; }));
      for (const std::string left_out : {"asker::", "pillar::"})  // near, and not listed
        EXPECT_TRUE(std::any_of(all.begin(), all.end(),
                                [&](const auto& n) {
                                  return n.first.rfind(left_out, 0) == 0 &&
                                         (n.second.tf.getOrigin() - centre).length() < 1.0;
                                }))
            << left_out;
    }
  }
}

// gazebo_ros's spawn_sdf_model and delete_model on world models, while the world runs.
TEST(Physics, SpawnsAndDeletesSdfModelsWhileRunning)
{
  PhysicsWorld w(flatWorld(), {});
  const std::string crate = R"(<sdf version="1.6"><model name="from_file">
      <pose>0 0 1 0 0 0</pose>
      <link name="body"><inertial><mass>2</mass></inertial>
        <collision name="c"><geometry><box><size>0.2 0.2 0.2</size></box></geometry></collision></link>
    </model></sdf>)";
  WorldModel m = parseSdfModel(crate, "crate.sdf", ".");
  m.name = "crate";  // the service's model_name wins over the file's
  m.pose = makeTransform(btVector3(2, 0, 0), btVector3(0, 0, 0)) * m.pose;
  w.addModel(m);
  run(w, 1.0);
  Pose p;
  ASSERT_TRUE(w.getModelState("crate", p));
  EXPECT_NEAR(p.tf.getOrigin().x(), 2.0, 1e-3);
  EXPECT_NEAR(p.tf.getOrigin().z(), 0.1, 0.01);  // fell from 1 m onto the ground
  // The ray from the origin along x meets its near face at 1.9 m.
  EXPECT_NEAR(w.rayTest(btVector3(0, 0, 0.1), btVector3(5, 0, 0.1), nullptr), 1.9, 0.01);

  EXPECT_THROW(w.addModel(m), LoadError);  // its name is taken
  WorldModel wall = boxModel("wall", btVector3(-2, 0, 0.5), btVector3(0.1, 2, 1), true);
  w.addModel(wall);
  EXPECT_EQ(w.worldSpec().models.size(), 2u);  // the static world's caches are built from it
  WorldModel empty;
  empty.name = "marker";
  empty.links.emplace_back();
  EXPECT_THROW(w.addModel(empty), LoadError);  // nothing to collide with

  // A static model moves too (set_model_state), the spec the static caches read with it, and
  // reset_world puts it back.
  bool moved_static = false;
  EXPECT_TRUE(w.setModelState("wall", makeTransform(btVector3(-3, 0, 0.5), btVector3(0, 0, 0)), btVector3(),
                              btVector3(), &moved_static));
  EXPECT_TRUE(moved_static);
  EXPECT_NEAR(w.worldSpec().models[1].pose.getOrigin().x(), -3.0, 1e-12);
  EXPECT_NEAR(w.rayTest(btVector3(0, 0, 0.5), btVector3(-5, 0, 0.5), nullptr), 2.95, 1e-3);
  EXPECT_TRUE(w.resetWorld());
  EXPECT_NEAR(w.worldSpec().models[1].pose.getOrigin().x(), -2.0, 1e-12);
  EXPECT_NEAR(w.rayTest(btVector3(0, 0, 0.5), btVector3(-5, 0, 0.5), nullptr), 1.95, 1e-3);
  EXPECT_FALSE(w.resetWorld());  // nothing static moved since

  bool was_static = true;
  EXPECT_TRUE(w.removeModel("crate", &was_static));
  EXPECT_FALSE(was_static);
  EXPECT_FALSE(w.getModelState("crate", p));
  EXPECT_LT(w.rayTest(btVector3(0, 0, 0.1), btVector3(5, 0, 0.1), nullptr), 0);  // nothing there now
  EXPECT_TRUE(w.removeModel("wall", &was_static));
  EXPECT_TRUE(was_static);
  EXPECT_TRUE(w.worldSpec().models.empty());
  EXPECT_FALSE(w.removeModel("wall"));
  run(w, 0.1);  // the world steps on without them

  EXPECT_THROW(parseSdfModel("<sdf><world name='w'/></sdf>", "w.sdf", "."), LoadError);  // no model in it
  EXPECT_EQ(
      parseSdfModel("<sdf><world name='w'><model name='one'><link name='l'/></model></world></sdf>", "w.sdf", ".").name,
      "one");
  EXPECT_THROW(parseSdfModel("<robot name='r'/>", "r.urdf", "."), LoadError);
}

// get_model_state / get_link_state relative to another entity, as gazebo_ros computes it.
TEST(Physics, StatesRelativeToAnotherEntity)
{
  Pose frame;  // at (1, 0, 0), turned 90 degrees left, moving along +x at 1 m/s
  frame.tf = makeTransform(btVector3(1, 0, 0), btVector3(0, 0, M_PI / 2));
  frame.linear = btVector3(1, 0, 0);
  Pose s;  // at (1, 2, 0), moving along +y at 1 m/s
  s.tf = makeTransform(btVector3(1, 2, 0), btVector3(0, 0, 0));
  s.linear = btVector3(0, 1, 0);
  const Pose r = relativeTo(s, frame);
  // 2 m ahead along the frame's x (world +y); turned -90 degrees in it.
  EXPECT_NEAR(r.tf.getOrigin().x(), 2.0, 1e-12);
  EXPECT_NEAR(r.tf.getOrigin().y(), 0.0, 1e-12);
  EXPECT_NEAR(r.tf.getRotation().getAngle() * r.tf.getRotation().getAxis().z(), -M_PI / 2, 1e-12);
  // The velocity difference (-1, 1, 0) in the frame's axes: (1, 1, 0).
  EXPECT_NEAR(r.linear.x(), 1.0, 1e-12);
  EXPECT_NEAR(r.linear.y(), 1.0, 1e-12);

  auto spec = std::make_shared<RobotSpec>(parseUrdf(fixture("diffbot.urdf"), "diffbot.urdf"));
  PhysicsWorld w(flatWorld(), {});
  w.addRobot(spec, "bot", "", makeTransform(btVector3(1, 2, 0), btVector3(0, 0, 1)));
  Pose model, root, ground;
  ASSERT_TRUE(w.entityState("bot", model));
  ASSERT_TRUE(w.entityState("bot::" + spec->root, root));
  ASSERT_TRUE(w.entityState("ground_plane::link", ground));
  EXPECT_EQ(model.tf.getOrigin(), root.tf.getOrigin());
  EXPECT_NEAR(relativeTo(model, root).tf.getOrigin().length(), 0.0, 1e-12);
  EXPECT_FALSE(w.entityState("bot::no_such_link", model));
  EXPECT_FALSE(w.entityState("nobody", model));
}

// gazebo_ros's apply_body_wrench / clear_body_wrenches.
TEST(Physics, BodyWrenchesPushForTheirDurationThenStop)
{
  // A wrench given in a frame turned 90 degrees left at (1, 0, 0), acting at that frame's origin,
  // on a body whose centre of mass is at the world's origin.
  const btTransform frame = makeTransform(btVector3(1, 0, 0), btVector3(0, 0, M_PI / 2));
  btVector3 f, t;
  worldWrench(btVector3(1, 0, 0), btVector3(0, 0, 0), btVector3(0, 0, 0), &frame, btVector3(0, 0, 0), f, t);
  EXPECT_NEAR((f - btVector3(0, 1, 0)).length(), 0.0, 1e-12);
  EXPECT_NEAR((t - btVector3(0, 0, 1)).length(), 0.0, 1e-12);  // (1, 0, 0) x (0, 1, 0)
  // Without a frame, world axes and a lever arm from the centre of mass (as upstream).
  worldWrench(btVector3(0, 2, 0), btVector3(0, 0, 0.5), btVector3(1, 0, 0), nullptr, btVector3(5, 5, 5), f, t);
  EXPECT_EQ(f, btVector3(0, 2, 0));
  EXPECT_NEAR((t - btVector3(0, 0, 2.5)).length(), 0.0, 1e-12);

  WorldSpec world = flatWorld();
  world.models.push_back(boxModel("crate", btVector3(0, 0, 0.1), btVector3(0.2, 0.2, 0.2), false));  // 1 kg
  PhysicsWorld w(world, {});
  run(w, 0.2);  // at rest on the ground
  const double g = 9.8;
  // Twice its weight upwards for 0.5 s: it rises with g, then flies on with what it gained.
  ASSERT_TRUE(w.applyBodyWrench("crate::link", btVector3(0, 0, 2 * g), btVector3(0, 0, 0), w.time(), 0.5));
  run(w, 0.5);
  Pose p;
  ASSERT_TRUE(w.getModelState("crate", p));
  EXPECT_NEAR(p.linear.z(), g * 0.5, 0.05);
  run(w, 0.2);
  ASSERT_TRUE(w.getModelState("crate", p));
  EXPECT_NEAR(p.linear.z(), g * 0.5 - g * 0.2, 0.05);  // the push is over: gravity alone

  // Until cleared: a steady sideways push in the air; once cleared, the velocity it gave stays.
  ASSERT_TRUE(w.applyBodyWrench("crate::link", btVector3(1, 0, 0), btVector3(0, 0, 0), w.time(), -1));
  run(w, 0.1);
  w.clearBodyWrenches("crate::link");
  run(w, 0.1);
  ASSERT_TRUE(w.getModelState("crate", p));
  EXPECT_NEAR(p.linear.x(), 0.1, 0.005);
  EXPECT_FALSE(w.applyBodyWrench("crate::nolink", btVector3(), btVector3(), 0, 1));
  EXPECT_FALSE(w.applyBodyWrench("ground_plane::link", btVector3(), btVector3(), 0, 1));  // static: nothing to push

  // A robot's link: lifted off the ground by three times its weight on its root link.
  auto spec = std::make_shared<RobotSpec>(parseUrdf(fixture("diffbot.urdf"), "diffbot.urdf"));
  double mass = 0;
  for (const auto& l : spec->links)
    mass += l.has_inertial ? l.inertial.mass : 0.0;
  Robot& bot = w.addRobot(spec, "bot", "", makeTransform(btVector3(3, 0, 0), btVector3(0, 0, 0)));
  run(w, 0.5);
  const double z0 = bot.linkState(spec->root).tf.getOrigin().z();
  ASSERT_TRUE(w.applyBodyWrench("bot::" + spec->root, btVector3(0, 0, 3 * mass * g), btVector3(), w.time(), 0.3));
  run(w, 0.3);
  EXPECT_GT(bot.linkState(spec->root).tf.getOrigin().z() - z0, 0.5 * 2 * g * 0.3 * 0.3 * 0.8);
}

// gazebo_ros's apply_joint_effort / clear_joint_forces.
TEST(Physics, JointEffortsTurnAJointForTheirDuration)
{
  auto spec = std::make_shared<RobotSpec>(parseUrdf(fixture("diffbot.urdf"), "diffbot.urdf"));
  PhysicsWorld w(flatWorld(), {});
  // High in the air: the wheels turn freely while it falls.
  Robot& r = w.addRobot(spec, "bot", "", makeTransform(btVector3(0, 0, 20), btVector3(0, 0, 0)));
  EXPECT_EQ(w.applyJointEffort("left_wheel_hinge", 0.05, w.time(), 0.2), "");  // one robot has it
  run(w, 0.2);
  const double spun = r.jointVelocity("left_wheel_hinge");
  EXPECT_GT(spun, 0.5);
  run(w, 0.1);  // over: it turns on at what it gained
  EXPECT_NEAR(r.jointVelocity("left_wheel_hinge"), spun, 0.1 * spun);
  // The other wheel was not pushed: it turns only relative to the chassis, which the reaction
  // torque turned the other way.
  EXPECT_LT(std::fabs(r.jointVelocity("right_wheel_hinge")), 0.3 * spun);

  EXPECT_EQ(w.applyJointEffort("bot::right_wheel_hinge", -0.05, w.time(), -1), "");  // until cleared
  run(w, 0.1);
  w.clearJointForces("bot::right_wheel_hinge");
  const double held = r.jointVelocity("right_wheel_hinge");
  EXPECT_LT(held, -0.2);
  run(w, 0.1);
  EXPECT_NEAR(r.jointVelocity("right_wheel_hinge"), held, 0.1 * std::fabs(held));

  w.addRobot(spec, "twin", "", makeTransform(btVector3(5, 0, 20), btVector3(0, 0, 0)));
  EXPECT_NE(w.applyJointEffort("left_wheel_hinge", 1, w.time(), 1).find("name it model::joint"), std::string::npos);
  // A URDF fixed joint: Gazebo lumps it away, and the refusal says how it would be kept.
  EXPECT_NE(w.applyJointEffort("bot::base_joint", 1, w.time(), 1).find("is fixed, and Gazebo lumps it away"),
            std::string::npos);
  EXPECT_NE(w.applyJointEffort("bot::base_joint", 1, w.time(), 1).find("<preserveFixedJoint>"), std::string::npos);
  EXPECT_NE(w.applyJointEffort("bot::no_joint", 1, w.time(), 1).find("no movable joint named 'bot::no_joint'"),
            std::string::npos);
  EXPECT_NE(w.applyJointEffort("nobody::left_wheel_hinge", 1, w.time(), 1), "");
}

// get_model_properties names what Gazebo's URDF conversion makes of a robot: a link per moving
// body (fixed children lumped into it, their collisions renamed and counted across the body).
TEST(Physics, ModelPropertiesAsGazeboBuildsTheModel)
{
  auto spec = std::make_shared<RobotSpec>(parseUrdf(fixture("diffbot.urdf"), "diffbot.urdf"));
  PhysicsWorld w(flatWorld(), {});
  w.addRobot(spec, "bot", "", makeTransform(btVector3(0, 0, 0.1), btVector3(0, 0, 0)));
  ModelProperties p;
  ASSERT_TRUE(w.modelProperties("bot", p));
  EXPECT_EQ(p.links, (std::vector<std::string>{"base_footprint", "left_wheel", "right_wheel"}));
  EXPECT_EQ(p.canonical_link, "base_footprint");
  EXPECT_EQ(p.collisions, (std::vector<std::string>{"base_footprint_fixed_joint_lump__chassis_collision",
                                                    "base_footprint_fixed_joint_lump__caster_front_collision_1",
                                                    "base_footprint_fixed_joint_lump__caster_back_collision_2",
                                                    "base_footprint_fixed_joint_lump__hokuyo_collision_3",
                                                    "left_wheel_collision", "right_wheel_collision"}));
  EXPECT_EQ(p.joints, (std::vector<std::string>{"left_wheel_hinge", "right_wheel_hinge"}));
  EXPECT_FALSE(p.is_static);

  WorldModel crate = boxModel("crate", btVector3(2, 0, 0.5), btVector3(0.2, 0.2, 0.2), false);
  crate.links[0].shapes[0].name = "crate_collision";
  w.addModel(crate);
  ASSERT_TRUE(w.modelProperties("crate", p));
  EXPECT_EQ(p.links, std::vector<std::string>{"link"});
  EXPECT_EQ(p.collisions, std::vector<std::string>{"crate_collision"});
  EXPECT_TRUE(p.joints.empty());
  EXPECT_FALSE(p.is_static);
  ASSERT_TRUE(w.modelProperties("ground_plane", p));
  EXPECT_TRUE(p.is_static);
  EXPECT_FALSE(w.modelProperties("nobody", p));
}

// set_model_configuration puts joints where asked, at rest, the body they hang from unmoved; a
// joint it does not know, a position past the limits or lists of different lengths change nothing.
TEST(Physics, ModelConfigurationSetsJointsAtOnce)
{
  auto spec = pitchingArm(R"(<dynamics damping="0.7"/>)");
  PhysicsWorld w(flatWorld(), {});
  Robot& r = w.addRobot(spec, "arm", "", makeTransform(btVector3(0, 0, 0), btVector3(0, 0, 0)));
  ModelProperties mp;
  ASSERT_TRUE(w.modelProperties("arm", mp));
  EXPECT_EQ(mp.links, (std::vector<std::string>{"base_link", "arm_link"}));  // "world" is the world's

  // Pitched down by 1 rad about +y: the arm's far end goes down, x = 0.5 cos 1, z = 1.1 - 0.5 sin 1.
  EXPECT_EQ(w.setJointPositions("arm", {"shoulder"}, {1.0}), "");
  EXPECT_NEAR(r.jointPosition("shoulder"), 1.0, 1e-12);
  EXPECT_EQ(r.jointVelocity("shoulder"), 0.0);
  const btVector3 tip = r.linkPose("arm_link") * btVector3(0.5, 0, 0);
  EXPECT_NEAR(tip.x(), 0.5 * std::cos(1.0), 1e-9);
  EXPECT_NEAR(tip.z(), 1.1 - 0.5 * std::sin(1.0), 1e-9);
  EXPECT_NEAR(r.linkPose("base_link").getOrigin().z(), 1.0, 1e-9);
  JointProperties jp;
  EXPECT_EQ(w.jointProperties("shoulder", jp), "");
  EXPECT_EQ(jp.type, JointSpec::REVOLUTE);
  EXPECT_EQ(jp.damping, 0.7);
  EXPECT_NEAR(jp.position, 1.0, 1e-12);
  run(w, 0.1);  // gravity swings it on from there
  EXPECT_EQ(w.jointProperties("arm::shoulder", jp), "");
  EXPECT_GT(jp.rate, 0.1);

  for (const auto& [names, positions, says] :
       std::vector<std::tuple<std::vector<std::string>, std::vector<double>, std::string>>{
           {{"elbow"}, {0.1}, "no movable joint named 'arm::elbow'"},
           {{"world_joint"}, {0.1}, "joint 'arm::world_joint' is fixed, and Gazebo lumps it away"},
           {{"shoulder"}, {2.5}, "2.5 is beyond the limits [-2, 2] of joint 'shoulder'"},
           {{"shoulder"}, {std::nan("")}, "not a number"},
           {{"shoulder"}, {}, "different lengths"}})
  {
    const double before = r.jointPosition("shoulder");
    const std::string why = w.setJointPositions("arm", names, positions);
    EXPECT_NE(why.find(says), std::string::npos) << why;
    EXPECT_EQ(r.jointPosition("shoulder"), before);
  }
  EXPECT_NE(w.setJointPositions("nobody", {}, {}).find("no model named 'nobody'"), std::string::npos);
  EXPECT_NE(w.jointProperties("elbow", jp), "");
}

// get_link_properties reports a body as Gazebo does: its centre of mass in the link frame and its
// inertia in the link frame's axes (a tensor with products comes back as the URDF gives it, though
// Bullet holds it along its principal axes); a link lumped into another is not one.
TEST(Physics, LinkPropertiesAsGazeboReportsThem)
{
  auto spec = pitchingArm();
  PhysicsWorld w(flatWorld(), {});
  w.addRobot(spec, "arm", "", btTransform::getIdentity());
  LinkProperties p;
  ASSERT_EQ(w.linkProperties("arm::arm_link", p), "");
  EXPECT_NEAR((p.com - btVector3(0.25, 0, 0)).length(), 0, 1e-9);
  EXPECT_NEAR(p.mass, 1.0, 1e-9);
  const double want[3][3] = {{0.0004, 0, 0}, {0, 0.021, 0}, {0, 0, 0.021}};
  for (int i = 0; i < 3; ++i)
    for (int k = 0; k < 3; ++k)
      EXPECT_NEAR(p.inertia[i][k], want[i][k], 1e-9) << i << k;
  EXPECT_TRUE(p.gravity_mode);
  ASSERT_EQ(w.linkProperties("base_link", p), "");  // one model alone has it
  EXPECT_NEAR(p.mass, 4.0, 1e-9);
  EXPECT_NE(w.linkProperties("arm::world", p), "");  // the world is no link

  // A tensor with products, off its link frame's origin.
  const std::string tilted = R"(<robot name="tilted"><link name="body">
      <collision><geometry><box size="0.4 0.2 0.1"/></geometry></collision>
      <inertial><origin xyz="0.05 -0.02 0.01"/><mass value="2"/>
        <inertia ixx="0.03" ixy="0.01" ixz="-0.004" iyy="0.02" iyz="0.002" izz="0.04"/></inertial></link></robot>)";
  w.addRobot(std::make_shared<RobotSpec>(parseUrdf(tilted, "tilted.urdf")), "tilted", "",
             makeTransform(btVector3(3, 0, 1), btVector3(0, 0, 0)));
  ASSERT_EQ(w.linkProperties("tilted::body", p), "");
  EXPECT_NEAR((p.com - btVector3(0.05, -0.02, 0.01)).length(), 0, 1e-9);
  const double full[3][3] = {{0.03, 0.01, -0.004}, {0.01, 0.02, 0.002}, {-0.004, 0.002, 0.04}};
  for (int i = 0; i < 3; ++i)
    for (int k = 0; k < 3; ++k)
      EXPECT_NEAR(p.inertia[i][k], full[i][k], 1e-6) << i << k;  // Bullet's single-precision floats

  auto bot = std::make_shared<RobotSpec>(parseUrdf(fixture("diffbot.urdf"), "diffbot.urdf"));
  w.addRobot(bot, "bot", "", makeTransform(btVector3(-3, 0, 0.1), btVector3(0, 0, 0)));
  const std::string lumped = w.linkProperties("bot::hokuyo", p);
  EXPECT_NE(lumped.find("lumped into 'bot::base_footprint'"), std::string::npos) << lumped;
  w.addModel(boxModel("crate", btVector3(2, 3, 0.1), btVector3(0.2, 0.2, 0.2), false));
  w.addModel(boxModel("wall", btVector3(-2, 3, 0.5), btVector3(0.1, 2, 1), true));
  ASSERT_EQ(w.linkProperties("crate::link", p), "");
  EXPECT_NEAR(p.mass, 1.0, 1e-6);
  EXPECT_NEAR(p.inertia[0][0], 1.0 / 12 * (0.04 + 0.04), 1e-6);  // a 0.2 m cube's
  ASSERT_EQ(w.linkProperties("wall::link", p), "");
  EXPECT_NEAR(p.mass, 1.0, 1e-9);
  EXPECT_EQ(p.inertia[0][0], 0.0);  // static: not simulated
  const std::string two = w.linkProperties("link", p);
  EXPECT_NE(two.find("is in 3 models (ground_plane, crate, ..."), std::string::npos) << two;
  EXPECT_NE(w.linkProperties("arm::nothing", p).find("no link named 'arm::nothing'"), std::string::npos);
}

// set_link_properties: a new mass and inertia change how a torque turns a link, gravity_mode false
// takes its weight away; a moved centre of mass, turned axes or an unphysical body change nothing.
TEST(Physics, LinkPropertiesChangeMassInertiaAndGravity)
{
  auto spec = pitchingArm();
  PhysicsWorld w(flatWorld(), {});
  Robot& r = w.addRobot(spec, "arm", "", btTransform::getIdentity());
  LinkProperties p;
  ASSERT_EQ(w.linkProperties("arm::arm_link", p), "");

  // Weightless, the horizontal arm stays where it is.
  p.gravity_mode = false;
  ASSERT_EQ(w.setLinkProperties("arm::arm_link", p), "");
  run(w, 0.5);
  EXPECT_NEAR(r.jointPosition("shoulder"), 0.0, 1e-6);
  LinkProperties q;
  ASSERT_EQ(w.linkProperties("arm::arm_link", q), "");
  EXPECT_FALSE(q.gravity_mode);

  // 1 N m for 0.1 s about the shoulder: omega = t / (iyy + m d^2), d = 0.25 m.
  const auto spin = [&]()
  {
    w.setJointPositions("arm", {"shoulder"}, {0.0});
    w.applyJointEffort("shoulder", 1.0, w.time(), 0.1);
    run(w, 0.1);
    return r.jointVelocity("shoulder");
  };
  EXPECT_NEAR(spin(), 0.1 / (0.021 + 0.0625), 0.01 * 0.1 / 0.0835);
  p.mass = 2;
  p.inertia = p.inertia * 2.0;
  ASSERT_EQ(w.setLinkProperties("arm::arm_link", p), "");
  EXPECT_NEAR(spin(), 0.1 / (0.042 + 0.125), 0.01 * 0.1 / 0.167);

  // Refused, and nothing changes.
  for (const auto& [change, says] :
       std::vector<std::pair<std::function<void(LinkProperties&)>, std::string>>{
           {[](LinkProperties& x) { x.com += btVector3(0.01, 0, 0); }, "is not where the link's centre of mass is"},
           {[](LinkProperties& x) { x.inertia[0][1] = x.inertia[1][0] = 0.005; }, "principal axes"},
           {[](LinkProperties& x) { x.mass = 0; }, "must be > 0"},
           {[](LinkProperties& x) { x.inertia = btMatrix3x3(1, 0, 0, 0, 0.1, 0, 0, 0, 0.1); }, "are not a body's"},
       })
  {
    LinkProperties bad = p;
    change(bad);
    const std::string why = w.setLinkProperties("arm::arm_link", bad);
    EXPECT_NE(why.find(says), std::string::npos) << why;
    ASSERT_EQ(w.linkProperties("arm::arm_link", q), "");
    EXPECT_EQ(q.mass, 2.0);
  }

  // A world model's body too; a static one is refused.
  w.addModel(boxModel("crate", btVector3(2, 0, 3), btVector3(0.2, 0.2, 0.2), false));
  w.addModel(boxModel("wall", btVector3(-2, 0, 0.5), btVector3(0.1, 2, 1), true));
  ASSERT_EQ(w.linkProperties("crate::link", q), "");
  q.gravity_mode = false;
  q.mass = 5;
  q.inertia = q.inertia * 5.0;
  ASSERT_EQ(w.setLinkProperties("crate::link", q), "");
  run(w, 0.5);
  Pose crate;
  ASSERT_TRUE(w.entityState("crate::link", crate));
  EXPECT_NEAR(crate.tf.getOrigin().z(), 3.0, 1e-6);
  ASSERT_EQ(w.linkProperties("crate::link", q), "");
  EXPECT_NEAR(q.mass, 5.0, 1e-6);
  ASSERT_EQ(w.linkProperties("wall::link", q), "");
  EXPECT_NE(w.setLinkProperties("wall::link", q).find("is static"), std::string::npos);
}

// set_joint_properties: damping, stops, and ODE's joint motor (vel at up to fmax); a list with a
// value per axis past the first, stops the wrong way round or vel with no motor change nothing.
TEST(Physics, JointPropertiesSetDampingStopsAndMotor)
{
  auto spec = pitchingArm(R"(<dynamics damping="0.7"/>)");
  PhysicsWorld w(flatWorld(), {});
  Robot& r = w.addRobot(spec, "arm", "", btTransform::getIdentity());
  JointProperties jp;

  JointSettings s;
  s.damping = {0.0};
  s.lower = {-0.3};
  s.upper = {0.3};
  ASSERT_EQ(w.setJointProperties("shoulder", s), "");
  ASSERT_EQ(w.jointProperties("shoulder", jp), "");
  EXPECT_EQ(jp.damping, 0.0);
  run(w, 1.0);  // gravity swings the arm down (+y pitch) onto the new stop
  EXPECT_NEAR(r.jointPosition("shoulder"), 0.3, 0.02);
  EXPECT_NE(w.setJointPositions("arm", {"shoulder"}, {1.0}).find("beyond the limits [-0.3, 0.3]"), std::string::npos);

  // The motor: 1 rad/s against gravity's 2.45 N m at most, within stops wide apart.
  s = JointSettings();
  s.lower = {-100};
  s.upper = {100};
  s.fmax = {10};
  s.vel = {-1};
  ASSERT_EQ(w.setJointProperties("arm::shoulder", s), "");
  run(w, 0.5);
  EXPECT_NEAR(r.jointVelocity("shoulder"), -1.0, 0.02);
  s = JointSettings();
  s.vel = {0.5};  // the motor runs: a new velocity alone
  ASSERT_EQ(w.setJointProperties("shoulder", s), "");
  run(w, 0.2);
  EXPECT_NEAR(r.jointVelocity("shoulder"), 0.5, 0.02);
  s = JointSettings();
  s.fmax = {0};  // off: the arm swings free
  ASSERT_EQ(w.setJointProperties("shoulder", s), "");

  for (const auto& [change, says] :
       std::vector<std::pair<std::function<void(JointSettings&)>, std::string>>{
           {[](JointSettings& x) {
              x.damping = {1, 2};
            },
            "has one axis: damping has 2 values"},
           {[](JointSettings& x) { x.upper = {std::nan("")}; }, "hiStop[0] is not a number"},
           {[](JointSettings& x) { x.lower = {0.5}, x.upper = {0.2}; }, "is above hiStop[0]"},
           {[](JointSettings& x) { x.damping = {-1}; }, "must be >= 0"},
           {[](JointSettings& x) { x.vel = {1}; }, "vel without fmax"},
       })
  {
    JointSettings bad;
    change(bad);
    const std::string why = w.setJointProperties("shoulder", bad);
    EXPECT_NE(why.find(says), std::string::npos) << why;
    ASSERT_EQ(w.jointProperties("shoulder", jp), "");
    EXPECT_EQ(jp.damping, 0.0);
  }
  EXPECT_NE(w.setJointProperties("elbow", s).find("no movable joint named 'elbow'"), std::string::npos);
  EXPECT_EQ(w.setJointPositions("arm", {"shoulder"}, {1.0}), "");  // the wide stops hold
}

// set_link_state moves a world model's link, or a robot by a link on its root body; a link that
// its joints place is refused.
TEST(Physics, LinkStateMovesFreeLinksAndRobotsByTheirRootBody)
{
  auto spec = std::make_shared<RobotSpec>(parseUrdf(fixture("diffbot.urdf"), "diffbot.urdf"));
  PhysicsWorld w(flatWorld(), {});
  Robot& r = w.addRobot(spec, "bot", "", makeTransform(btVector3(0, 0, 0.1), btVector3(0, 0, 0)));
  w.addModel(boxModel("crate", btVector3(2, 0, 0.1), btVector3(0.2, 0.2, 0.2), false));
  w.addModel(boxModel("wall", btVector3(-2, 0, 0.5), btVector3(0.1, 2, 1), true));
  run(w, 0.2);

  // The hokuyo is lumped into the root body: where it goes, the robot goes.
  const btTransform hokuyo_in_root = r.linkPose("base_footprint").inverse() * r.linkPose("hokuyo");
  const btTransform target = makeTransform(btVector3(1, 3, 0.4), btVector3(0, 0, 1.0));
  EXPECT_EQ(w.setLinkState("bot::hokuyo", target, btVector3(0.5, 0, 0), btVector3(0, 0, 0)), "");
  EXPECT_NEAR((r.linkPose("hokuyo").getOrigin() - target.getOrigin()).length(), 0, 1e-9);
  const btTransform root = r.linkPose("base_footprint");
  EXPECT_NEAR((root * hokuyo_in_root).getOrigin().distance(target.getOrigin()), 0, 1e-9);
  EXPECT_NEAR(r.linkState("base_footprint").linear.x(), 0.5, 1e-9);

  bool moved_static = false;
  EXPECT_EQ(w.setLinkState("wall::link", makeTransform(btVector3(-3, 0, 0.5), btVector3(0, 0, 0)), btVector3(0, 0, 0),
                           btVector3(0, 0, 0), &moved_static),
            "");
  EXPECT_TRUE(moved_static);
  EXPECT_NEAR(w.rayTest(btVector3(0, 0, 0.5), btVector3(-5, 0, 0.5), nullptr), 2.95, 0.01);
  EXPECT_EQ(w.setLinkState("crate::link", makeTransform(btVector3(2, 0, 2), btVector3(0, 0, 0)), btVector3(0, 0, 0),
                           btVector3(0, 0, 0)),
            "");
  Pose crate;
  ASSERT_TRUE(w.entityState("crate::link", crate));
  EXPECT_NEAR(crate.tf.getOrigin().z(), 2.0, 1e-9);
  run(w, 0.3);  // and falls from there
  ASSERT_TRUE(w.entityState("crate::link", crate));
  EXPECT_LT(crate.tf.getOrigin().z(), 1.7);

  const btTransform wheel = r.linkPose("left_wheel");
  EXPECT_NE(
      w.setLinkState("bot::left_wheel", target, btVector3(0, 0, 0), btVector3(0, 0, 0)).find("placed by its joints"),
      std::string::npos);
  EXPECT_EQ(r.linkPose("left_wheel").getOrigin(), wheel.getOrigin());
  EXPECT_NE(w.setLinkState("bot::nothing", target, btVector3(0, 0, 0), btVector3(0, 0, 0)), "");
  EXPECT_NE(w.setLinkState("crate", target, btVector3(0, 0, 0), btVector3(0, 0, 0)), "");
}

// set_physics_properties: a new step size goes on from the time reached (no jump), and new gravity
// pulls from the next step.
TEST(Physics, StepSizeAndGravityChangeWhileRunning)
{
  PhysicsWorld w(flatWorld(), {});
  w.addModel(boxModel("ball", btVector3(0, 0, 50), btVector3(0.2, 0.2, 0.2), false));
  run(w, 0.5);
  EXPECT_NEAR(w.time(), 0.5, 1e-12);
  w.setStepSize(0.004);
  w.step();
  EXPECT_NEAR(w.time(), 0.504, 1e-12);
  run(w, 0.496);
  EXPECT_NEAR(w.time(), 1.0, 1e-12);

  Pose p;
  ASSERT_TRUE(w.entityState("ball", p));
  EXPECT_NEAR(p.linear.z(), -9.8, 0.05);  // 1 s of fall
  w.setGravity(btVector3(0, 0, 1.62));    // pointing up now
  run(w, 1.0);
  ASSERT_TRUE(w.entityState("ball", p));
  EXPECT_NEAR(p.linear.z(), -9.8 + 1.62, 0.05);
  EXPECT_EQ(w.gravity(), btVector3(0, 0, 1.62));
  w.setSolverIterations(30);
  EXPECT_EQ(w.solverIterations(), 30);
  w.resetTime();
  w.step();
  EXPECT_NEAR(w.time(), 0.004, 1e-12);
}

// An SDF model with joints is simulated as Gazebo simulates it, a robot: a door anchored to the
// world, hinged at its edge (the joint's <pose> in the door's frame), swings about that edge.
TEST(Physics, SdfModelWithJointsSwingsAboutItsHinge)
{
  const std::string door = R"(<sdf version="1.6"><model name="door"><pose>1 2 0 0 0 0</pose>
      <link name="frame"><pose>0 0 1 0 0 0</pose>
        <collision name="post"><geometry><box><size>0.1 0.1 2</size></box></geometry></collision></link>
      <link name="leaf"><pose>0.55 0 1 0 0 0</pose>
        <inertial><mass>10</mass><inertia><ixx>3.4</ixx><iyy>4.2</iyy><izz>0.85</izz></inertia></inertial>
        <collision name="panel"><geometry><box><size>1 0.04 1.9</size></box></geometry></collision></link>
      <joint name="anchor" type="fixed"><parent>world</parent><child>frame</child></joint>
      <joint name="hinge" type="revolute"><pose>-0.5 0 0 0 0 0</pose><parent>frame</parent><child>leaf</child>
        <axis><xyz>0 0 1</xyz><limit><lower>-2</lower><upper>2</upper></limit><dynamics><damping>1</damping></dynamics>
        </axis></joint></model></sdf>)";
  SdfSpawn sdf = parseSdfSpawn(door, "door.sdf", ".");
  ASSERT_TRUE(sdf.robot);
  EXPECT_EQ(sdf.robot->root, "world");
  EXPECT_EQ(sdf.robot->name, "door");
  PhysicsWorld w(flatWorld(), {});
  Robot& r = w.addRobot(sdf.robot, "door", "", sdf.model.pose * sdf.root_in_model);
  EXPECT_NEAR(r.linkPose("leaf").getOrigin().distance(btVector3(1.55, 2, 1)), 0, 1e-9);
  EXPECT_EQ(w.applyJointEffort("door::hinge", 20, w.time(), 0.5), "");
  run(w, 1.0);
  const double a = r.jointPosition("hinge");
  EXPECT_GT(a, 0.2);
  // The hinge, at (1.05, 2), stays where it is: the leaf's centre is 0.5 m from it, at the angle turned.
  const btVector3 c = r.linkPose("leaf").getOrigin();
  EXPECT_NEAR(c.distance(btVector3(1.05, 2, 1)), 0.5, 1e-6);
  EXPECT_NEAR(std::atan2(c.y() - 2, c.x() - 1.05), a, 1e-6);
  EXPECT_NEAR(r.linkPose("frame").getOrigin().distance(btVector3(1, 2, 1)), 0, 1e-6);  // anchored

  // A static model, or one without joints or plugins, stays a world model.
  EXPECT_FALSE(parseSdfSpawn(R"(<model name="crate"><link name="l"><collision name="c"><geometry><box>
      <size>0.2 0.2 0.2</size></box></geometry></collision></link></model>)",
                             "crate.sdf", ".")
                   .robot);
  // What it cannot simulate, named.
  for (const auto& [xml, says] : std::vector<std::pair<std::string, std::string>>{
           {R"(<model name="m"><link name="a"/><link name="b"/><joint name="j" type="universal"><parent>a</parent>
               <child>b</child></joint></model>)",
            "<joint name='j'>: type 'universal' is not simulated"},
           {R"(<model name="m"><link name="a"/><link name="b"/><link name="c"/><joint name="j" type="revolute">
               <parent>a</parent><child>b</child></joint></model>)",
            "links 'a' and 'c' are not joined"},
           {R"(<model name="m"><link name="a"/><joint name="j" type="revolute"><parent>a</parent>
               <child>nothing</child></joint></model>)",
            "no link named 'nothing'"}})
  {
    try
    {
      parseSdfSpawn(xml, "m.sdf", ".");
      ADD_FAILURE() << "accepted: " << xml;
    }
    catch (const LoadError& e)
    {
      EXPECT_NE(std::string(e.what()).find(says), std::string::npos) << e.what();
    }
  }
}

// An SDF ball joint (how SDF robots often mount a caster) leaves its link free to turn every
// way about the pivot: a bob let go level with its pivot swings down on a rod of constant length,
// its damping brings it to rest hanging below, and a world reset puts it back where it started.
TEST(Physics, ABallJointSwingsFreelyAboutItsPivot)
{
  const std::string pendulum = R"(<sdf version="1.6"><model name="pendulum">
      <link name="post"><pose>0 0 1 0 0 0</pose>
        <collision name="c"><geometry><box><size>0.05 0.05 0.05</size></box></geometry></collision></link>
      <link name="bob"><pose>0.3 0.4 1 0 0 0</pose>
        <inertial><mass>1</mass><inertia><ixx>0.001</ixx><iyy>0.001</iyy><izz>0.001</izz></inertia></inertial>
        <collision name="c"><geometry><sphere><radius>0.05</radius></sphere></geometry></collision></link>
      <joint name="anchor" type="fixed"><parent>world</parent><child>post</child></joint>
      <joint name="swivel" type="ball"><pose>-0.3 -0.4 0 0 0 0</pose><parent>post</parent><child>bob</child>
        <axis><xyz>0 0 1</xyz><dynamics><damping>0.1</damping></dynamics></axis></joint></model></sdf>)";
  SdfSpawn sdf = parseSdfSpawn(pendulum, "pendulum.sdf", ".");
  ASSERT_TRUE(sdf.robot);
  PhysicsWorld w(flatWorld(), {});
  Robot& r = w.addRobot(sdf.robot, "pendulum", "", sdf.model.pose * sdf.root_in_model);
  EXPECT_TRUE(r.movableJoints().empty());  // nothing to command or report
  const btVector3 pivot(0, 0, 1);
  run(w, 0.3);
  btVector3 bob = r.linkPose("bob").getOrigin();
  EXPECT_NEAR(bob.distance(pivot), 0.5, 1e-6);
  EXPECT_LT(bob.z(), 0.8);                                                // falling
  EXPECT_NEAR(std::atan2(bob.y(), bob.x()), std::atan2(0.4, 0.3), 1e-6);  // in its plane: nothing pushes it out
  run(w, 60.0);
  bob = r.linkPose("bob").getOrigin();
  EXPECT_NEAR(bob.distance(btVector3(0, 0, 0.5)), 0, 0.005);  // at rest below the pivot
  EXPECT_FALSE(w.resetWorld());                               // no static model moved
  EXPECT_NEAR(r.linkPose("bob").getOrigin().distance(btVector3(0.3, 0.4, 1)), 0, 1e-9);
}

// Gazebo's "Make a mobile robot" tutorial builds its robot in SDF and attaches a laser model
// from the model path with <include> and a fixed joint to "hokuyo::link". Nested and included
// models are flattened into the robot under their scoped names, their own joints too: the laser
// rides the chassis where the include put it, and a nested mast pans on its own joint.
TEST(Physics, AnSdfRobotWithAnIncludedLaserAndANestedMast)
{
  const std::string wheel = R"(<inertial><mass>0.5</mass><inertia><ixx>0.002</ixx><iyy>0.002</iyy><izz>0.002</izz>
      </inertia></inertial><collision name="c"><pose>0 0 0 1.5707963267948966 0 0</pose><geometry><cylinder>
      <radius>0.1</radius><length>0.05</length></cylinder></geometry></collision>)";
  const std::string robot = R"(<sdf version="1.6"><model name="my_robot">
      <link name="chassis"><pose>0 0 0.1 0 0 0</pose>
        <inertial><mass>5</mass><inertia><ixx>0.02</ixx><iyy>0.07</iyy><izz>0.08</izz></inertia></inertial>
        <collision name="box"><geometry><box><size>0.4 0.2 0.1</size></box></geometry></collision>
        <collision name="caster"><pose>-0.15 0 -0.05 0 0 0</pose><geometry><sphere><radius>0.05</radius></sphere>
        </geometry></collision></link>
      <link name="left_wheel"><pose>0.1 0.13 0.1 0 0 0</pose>)" +
                            wheel + R"(</link>
      <link name="right_wheel"><pose>0.1 -0.13 0.1 0 0 0</pose>)" +
                            wheel + R"(</link>
      <joint name="left_wheel_hinge" type="revolute"><parent>chassis</parent><child>left_wheel</child>
        <axis><xyz>0 1 0</xyz></axis></joint>
      <joint name="right_wheel_hinge" type="revolute"><parent>chassis</parent><child>right_wheel</child>
        <axis><xyz>0 1 0</xyz></axis></joint>
      <include><uri>model://tutorial_laser</uri><pose>0.2 0 0.2 0 0 0</pose></include>
      <joint name="laser_joint" type="fixed"><child>tutorial_laser::link</child><parent>chassis</parent></joint>
      <model name="mast"><pose>-0.1 0 0.15 0 0 0</pose>
        <link name="base"><inertial><mass>0.2</mass><inertia><ixx>0.001</ixx><iyy>0.001</iyy><izz>0.001</izz>
          </inertia></inertial><collision name="c"><geometry><box><size>0.04 0.04 0.1</size></box></geometry>
          </collision></link>
        <link name="top"><pose>0 0 0.08 0 0 0</pose><inertial><mass>0.1</mass><inertia><ixx>0.0001</ixx>
          <iyy>0.0001</iyy><izz>0.0001</izz></inertia></inertial><collision name="c"><geometry><box>
          <size>0.1 0.02 0.02</size></box></geometry></collision></link>
        <joint name="pan" type="revolute"><parent>base</parent><child>top</child><axis><xyz>0 0 1</xyz>
          <dynamics><damping>0.001</damping></dynamics></axis></joint>
      </model>
      <joint name="mast_joint" type="fixed"><parent>chassis</parent><child>mast::base</child></joint>
      </model></sdf>)";
  const SdfSpawn sdf = parseSdfSpawn(robot, "my_robot.sdf", FIXTURE_DIR);
  ASSERT_TRUE(sdf.robot);
  std::vector<std::string> links, joints;
  for (const LinkSpec& l : sdf.robot->links)
    links.push_back(l.name);
  for (const JointSpec& j : sdf.robot->joints)
    joints.push_back(j.name + ": " + j.parent + " -> " + j.child);
  EXPECT_EQ(links, (std::vector<std::string>{"chassis", "left_wheel", "right_wheel", "tutorial_laser::link",
                                             "mast::base", "mast::top"}));
  EXPECT_EQ(joints, (std::vector<std::string>{
                        "left_wheel_hinge: chassis -> left_wheel", "right_wheel_hinge: chassis -> right_wheel",
                        "laser_joint: chassis -> tutorial_laser::link", "mast_joint: chassis -> mast::base",
                        "mast::pan: mast::base -> mast::top"}));
  EXPECT_EQ(sdf.robot->links[3].sensors.size(), 1u);  // the included model's laser, on its link
  EXPECT_EQ(sdf.model.links.size(), 6u);              // and the same links as rigid bodies

  PhysicsWorld w(flatWorld(), {});
  Robot& r = w.addRobot(sdf.robot, "my_robot", "", sdf.model.pose * sdf.root_in_model);
  run(w, 1.0);
  // Where the <include> put it, 0.1 m above and 0.2 m ahead of the chassis' frame, at rest.
  const btTransform chassis = r.linkPose("chassis");
  EXPECT_LT((chassis.inverse() * r.linkPose("tutorial_laser::link")).getOrigin().distance(btVector3(0.2, 0, 0.1)),
            1e-6);
  EXPECT_LT((chassis.inverse() * r.linkPose("mast::top")).getOrigin().distance(btVector3(-0.1, 0, 0.13)), 1e-6);
  EXPECT_EQ(w.applyJointEffort("my_robot::mast::pan", 0.01, w.time(), 0.2), "");
  run(w, 0.5);
  EXPECT_GT(r.jointPosition("mast::pan"), 0.1);  // its own joint turns it

  // Gazebo keeps an SDF model's fixed joints and their links, and so does gazebo_lite: the laser is
  // a link of its own, fixed to the chassis. Every service finds them by one lookup; those that
  // would move the joint say why they cannot.
  JointProperties jp;
  ASSERT_EQ(w.jointProperties("laser_joint", jp), "");  // the name one model alone has
  EXPECT_EQ(jp.type, JointSpec::FIXED);
  EXPECT_EQ(jp.position, 0.0);
  for (const std::string& why : {w.applyJointEffort("my_robot::laser_joint", 1, w.time(), 0.1),
                                 w.setJointProperties("my_robot::laser_joint", JointSettings{{0.1}, {}, {}, {}, {}}),
                                 w.setJointPositions("my_robot", {"laser_joint"}, {0.1})})
    EXPECT_NE(why.find("joint 'my_robot::laser_joint' is fixed: it does not move"), std::string::npos) << why;
  LinkProperties lp;
  ASSERT_EQ(w.linkProperties("my_robot::tutorial_laser::link", lp), "");
  const double m = sdf.robot->link("tutorial_laser::link")->inertial.mass;
  EXPECT_NEAR(lp.mass, m, 1e-12);  // its own, not the chassis'
  // Its joint carries its weight, as a force-torque sensor there would read it.
  ASSERT_TRUE(r.hasKeptFixedJoint("laser_joint"));
  r.watchJointWrench("laser_joint");
  run(w, 0.1);
  EXPECT_NEAR(r.jointWrench("laser_joint").first.length(), m * 9.8, 1e-6);
  // Its mass can be set apart from the chassis'.
  lp.mass = 2 * m;
  lp.inertia = lp.inertia * 2.0;
  ASSERT_EQ(w.setLinkProperties("my_robot::tutorial_laser::link", lp), "");
  ASSERT_EQ(w.linkProperties("my_robot::tutorial_laser::link", lp), "");
  EXPECT_NEAR(lp.mass, 2 * m, 1e-12);
  run(w, 0.1);
  EXPECT_NEAR(r.jointWrench("laser_joint").first.length(), 2 * m * 9.8, 1e-6);
}

int main(int argc, char** argv)
{
  testing::InitGoogleTest(&argc, argv);
  return RUN_ALL_TESTS();
}

// A robot whose root link is `world` (UR's and most arms' descriptions) is fixed where it is
// spawned, as Gazebo fixes it: its base stays in the air while its arm swings down under gravity.
// Without the `world` link the same robot falls.
TEST(Physics, ARobotRootedAtAWorldLinkIsFixedWhereItIsSpawned)
{
  for (bool rooted : {true, false})
  {
    const std::string urdf = armUrdf(rooted, R"(continuous"><parent link="base_link"/><child link="arm_link"/>
      <origin xyz="0 0 0.1"/><axis xyz="0 1 0"/>)");
    auto spec = std::make_shared<RobotSpec>(parseUrdf(urdf, "arm.urdf"));
    PhysicsWorld w(flatWorld(), {});
    Robot& r =
        w.addRobot(spec, "arm", "", btTransform(btQuaternion::getIdentity(), btVector3(0, 0, rooted ? 0.0 : 1.0)));
    const btVector3 before = r.linkPose("base_link").getOrigin();
    run(w, 1.0);
    const btVector3 after = r.linkPose("base_link").getOrigin();
    if (rooted)
    {
      EXPECT_NEAR(before.z(), 1.0, 1e-9);
      EXPECT_LT((after - before).length(), 1e-6) << "the anchored base moved";
      // The arm, free about y, has swung down (+pi/2 about y points the link at -z).
      EXPECT_GT(std::abs(r.jointPosition("shoulder")), 0.5);
    }
    else
      EXPECT_LT(after.z(), 0.5) << "the free robot did not fall";
  }
}

// A joint's wrench (what gazebo_ros_ft_sensor reports): the parent's push on the child, in the
// child's axes, about the joint, checked against statics and a pendulum's dynamics.
TEST(Physics, AJointsWrenchHoldsTheArmAgainstGravity)
{
  const double m = 1.0, g = 9.8, r_com = 0.25;  // the arm: 1 kg, its centre of mass 0.25 m out
  // A shoulder about y without stops: gravity pitches the arm down (+).
  auto spec = std::make_shared<RobotSpec>(
      parseUrdf(armUrdf(true, R"(continuous"><parent link="base_link"/><child link="arm_link"/>
      <origin xyz="0 0 0.1"/><axis xyz="0 1 0"/><limit effort="50" velocity="50"/>)"),
                "arm.urdf"));
  // The errors of the swing below, at a step size.
  struct Swing
  {
    double axis_torque = 0, force = 0, fastest = 0;
  };
  auto swing = [&](double step)
  {
    PhysicsWorld::Options o;
    o.step = step;
    PhysicsWorld w(flatWorld(), o);
    Robot& r = w.addRobot(spec, "arm", "", btTransform::getIdentity());
    r.watchJointWrench("shoulder");
    // Held at 0.4 rad below horizontal by the servo: the joint carries the arm's weight and the
    // servo's torque against gravity's, whatever the servo's steady-state error.
    r.commandPosition("shoulder", 0.4, 50);
    run(w, 2.0);
    const double q = r.jointPosition("shoulder");
    EXPECT_NEAR(q, 0.4, 0.01);
    auto [f, tau] = r.jointWrench("shoulder");
    // The weight's reaction, (0, 0, m g) in the world, in the child's axes (pitched by q about y).
    EXPECT_NEAR(f.x(), -m * g * std::sin(q), 1e-6);
    EXPECT_NEAR(f.y(), 0.0, 1e-6);
    EXPECT_NEAR(f.z(), m * g * std::cos(q), 1e-6);
    // The servo's torque about the axis: minus gravity's, m g r cos(q).
    EXPECT_NEAR(tau.y(), -m * g * r_com * std::cos(q), 1e-6);
    EXPECT_NEAR(tau.x(), 0.0, 1e-6);
    EXPECT_NEAR(tau.z(), 0.0, 1e-6);

    // Let go: the arm swings free from there. The joint transmits no torque about its axis, and
    // its pull is what the centre of mass's acceleration a needs beyond gravity, m (a - g): in
    // the child's axes a = (-w^2 r, 0, -alpha r) and g = (g sin(q), 0, -g cos(q)), with
    // alpha = m g r cos(q) / I about the pivot.
    r.commandNone("shoulder");
    const double I = 0.021 + m * r_com * r_com;
    Swing e;
    for (int i = 0; i < std::lround(1.5 / step); ++i)
    {
      // The step's forces act where it begins (Bullet moves the links last, at the new velocity).
      const double q0 = r.jointPosition("shoulder"), w0 = r.jointVelocity("shoulder");
      w.step();
      const double w1 = r.jointVelocity("shoulder");
      std::tie(f, tau) = r.jointWrench("shoulder");
      const double alpha = m * g * r_com * std::cos(q0) / I;
      const btVector3 expected(m * (-w0 * w1 * r_com - g * std::sin(q0)), 0, m * (-alpha * r_com + g * std::cos(q0)));
      e.axis_torque = std::max(e.axis_torque, std::abs(tau.y()));
      e.force = std::max(e.force, (f - expected).length());
      e.fastest = std::max(e.fastest, std::abs(w1));
    }
    return e;
  };
  const Swing coarse = swing(0.001), fine = swing(0.0005);
  EXPECT_GT(coarse.fastest, 5.0) << "the arm did not swing";
  // What is left is the step's discretisation, first order in the step: against gravity's
  // 2.4 N m and forces up to 18.8 N, below 0.01 N m and 0.05 N at 1 ms, and half of it at 0.5 ms.
  EXPECT_LT(coarse.axis_torque, 0.01);
  EXPECT_LT(coarse.force, 0.05);
  EXPECT_NEAR(fine.axis_torque / coarse.axis_torque, 0.5, 0.05);
  EXPECT_NEAR(fine.force / coarse.force, 0.5, 0.05);
}

// A servo's effort (ros_control's joint state) is what its motor exerts: the torque that holds the
// arm against gravity, in position and velocity mode alike, and no more than its effort limit.
TEST(Physics, AServosEffortIsTheTorqueThatHoldsTheArm)
{
  const double m = 1.0, g = 9.8, r_com = 0.25;
  auto spec = std::make_shared<RobotSpec>(
      parseUrdf(armUrdf(true, R"(continuous"><parent link="base_link"/><child link="arm_link"/>
      <origin xyz="0 0 0.1"/><axis xyz="0 1 0"/><limit effort="50" velocity="50"/>)"),
                "arm.urdf"));
  PhysicsWorld w(flatWorld(), {});
  Robot& r = w.addRobot(spec, "arm", "", btTransform::getIdentity());
  r.watchJointWrench("shoulder");
  EXPECT_EQ(r.jointEffort("shoulder"), 0.0);  // before any step: nothing commands it
  r.commandPosition("shoulder", 0.4, 50);
  run(w, 2.0);
  double q = r.jointPosition("shoulder");
  // Gravity pitches the arm down (+ about y) with m g r cos(q); the servo holds it with minus that.
  EXPECT_NEAR(r.jointEffort("shoulder"), -m * g * r_com * std::cos(q), 1e-6);
  EXPECT_NEAR(r.jointEffort("shoulder"), r.jointWrench("shoulder").second.y(), 1e-9);  // all the joint carries

  r.commandVelocity("shoulder", 0.0, 50);  // held still by a velocity motor
  run(w, 0.5);
  q = r.jointPosition("shoulder");
  EXPECT_NEAR(r.jointEffort("shoulder"), -m * g * r_com * std::cos(q), 1e-6);

  // A servo too weak for the arm gives all it has, and the arm sags.
  r.commandPosition("shoulder", 0.0, 1.0);
  run(w, 0.2);
  EXPECT_NEAR(r.jointEffort("shoulder"), -1.0, 1e-9);
  EXPECT_GT(r.jointPosition("shoulder"), q);

  r.commandEffort("shoulder", 0.7);  // a commanded effort is its command
  run(w, 0.01);
  EXPECT_EQ(r.jointEffort("shoulder"), 0.7);
  r.commandNone("shoulder");
  run(w, 0.01);
  EXPECT_EQ(r.jointEffort("shoulder"), 0.0);
}

// A free prismatic joint lets its child rest on the ground: no force along its axis. Left out,
// the ground's push would show as the joint holding the link's whole weight.
TEST(Physics, AJointsWrenchCountsTheGroundsPushOnItsChild)
{
  auto spec = std::make_shared<RobotSpec>(
      parseUrdf(armUrdf(true, R"(prismatic"><parent link="base_link"/><child link="arm_link"/>
      <origin xyz="0 0 -0.1"/><axis xyz="0 0 1"/><limit lower="-2" upper="2" effort="50" velocity="5"/>)"),
                "arm.urdf"));
  PhysicsWorld w(flatWorld(), {});
  Robot& r = w.addRobot(spec, "arm", "", btTransform::getIdentity());
  r.watchJointWrench("shoulder");
  run(w, 2.0);
  EXPECT_NEAR(r.jointPosition("shoulder"), -0.875, 0.005) << "the link did not come to rest on the ground";
  const auto [f, tau] = r.jointWrench("shoulder");
  EXPECT_NEAR(f.z(), 0.0, 0.05) << "of a 9.81 N weight";
  EXPECT_NEAR(f.x(), 0.0, 0.05);
  EXPECT_NEAR(f.y(), 0.0, 0.05);
}

// Friction on the child counts too: a sled pushed along a free prismatic joint slides against
// the ground's friction, and the joint carries nothing along its axis. (The sled hangs on a free
// vertical joint, so that the ground bears its whole weight: N, and its friction, are known.)
TEST(Physics, AJointsWrenchCountsTheGroundsFrictionOnItsChild)
{
  const std::string urdf = R"(<robot name="sled"><link name="world"/>
    <joint name="world_joint" type="fixed"><parent link="world"/><child link="base"/><origin xyz="0 0 1"/></joint>
    <link name="base"><collision><geometry><box size="0.1 0.1 0.1"/></geometry></collision>
      <inertial><mass value="4"/><inertia ixx="0.01" ixy="0" ixz="0" iyy="0.01" iyz="0" izz="0.01"/></inertial></link>
    <link name="slider"><inertial><mass value="0.1"/>
      <inertia ixx="0.0001" ixy="0" ixz="0" iyy="0.0001" iyz="0" izz="0.0001"/></inertial></link>
    <joint name="lift" type="prismatic"><parent link="base"/><child link="slider"/><origin xyz="0 0 -0.9"/>
      <axis xyz="0 0 1"/><limit lower="-1" upper="1" effort="100" velocity="10"/></joint>
    <link name="sled"><collision><geometry><box size="0.2 0.2 0.1"/></geometry></collision>
      <inertial><mass value="1"/><inertia ixx="0.004" ixy="0" ixz="0" iyy="0.004" iyz="0" izz="0.007"/></inertial></link>
    <joint name="slide" type="prismatic"><parent link="slider"/><child link="sled"/>
      <axis xyz="1 0 0"/><limit lower="-5" upper="5" effort="100" velocity="10"/></joint></robot>)";
  auto spec = std::make_shared<RobotSpec>(parseUrdf(urdf, "sled.urdf"));
  PhysicsWorld w(flatWorld(), {});
  Robot& r = w.addRobot(spec, "sled", "", btTransform::getIdentity());
  r.watchJointWrench("slide");
  r.commandNone("lift");
  r.commandNone("slide");
  run(w, 0.5);  // down onto the ground
  ASSERT_NEAR(r.linkPose("sled").getOrigin().z(), 0.05, 0.002);
  const double push = 15.0, v0 = r.jointVelocity("slide");
  double most = 0;
  const int steps = 500;
  for (int i = 0; i < steps; ++i)
  {
    r.addWrench("sled", btVector3(push, 0, 0), btVector3(0, 0, 0));
    w.step();
    most = std::max(most, std::abs(r.jointWrench("slide").first.x()));
  }
  // The sled's 1 kg accelerated by the push less the friction: mu N = 1 x 1.1 kg x 9.8 m/s^2.
  const double friction = push - 1.0 * (r.jointVelocity("slide") - v0) / (steps * w.stepSize());
  EXPECT_NEAR(friction, 1.1 * 9.8, 0.5) << "the ground's friction";
  EXPECT_LT(most, 0.05) << "of a " << push << " N push against " << friction << " N of friction";
}

// A fixed joint Gazebo keeps (<preserveFixedJoint>): a wrist's force-torque sensor reads what the
// hand below it weighs, and the hand stays where the wrist holds it.
TEST(Physics, AKeptFixedJointHoldsItsChildAndReadsItsWeight)
{
  const std::string urdf = armUrdf(true, R"(revolute"><parent link="base_link"/><child link="arm_link"/>
      <origin xyz="0 0 0.1"/><axis xyz="0 1 0"/><limit lower="-2" upper="2" effort="50" velocity="5"/>)");
  // A 0.5 kg hand on a fixed wrist at the arm's end, its centre of mass 0.1 m further out.
  const std::string hand = R"(<link name="hand">
      <collision><origin xyz="0.1 0 0"/><geometry><box size="0.1 0.05 0.05"/></geometry></collision>
      <inertial><origin xyz="0.1 0 0"/><mass value="0.5"/>
        <inertia ixx="0.0002" ixy="0" ixz="0" iyy="0.0005" iyz="0" izz="0.0005"/></inertial></link>
    <joint name="wrist" type="fixed"><parent link="arm_link"/><child link="hand"/><origin xyz="0.5 0 0"/></joint>
    <gazebo reference="wrist"><preserveFixedJoint>true</preserveFixedJoint></gazebo></robot>)";
  const std::string with_hand = urdf.substr(0, urdf.rfind("</robot>")) + hand;
  auto spec = std::make_shared<RobotSpec>(parseUrdf(with_hand, "arm.urdf"));
  ASSERT_TRUE(spec->joint("wrist")->keep_fixed);
  PhysicsWorld w(flatWorld(), {});
  Robot& r = w.addRobot(spec, "arm", "", btTransform::getIdentity());
  ASSERT_TRUE(r.hasKeptFixedJoint("wrist"));
  EXPECT_FALSE(r.hasJoint("wrist"));  // not movable: nothing commands it
  r.watchJointWrench("wrist");
  r.commandPosition("shoulder", 0.3, 50);
  run(w, 2.0);
  const double q = r.jointPosition("shoulder"), m = 0.5, g = 9.8;
  // The hand where the wrist holds it: 0.5 m out along the arm, turned with it.
  const btTransform rel = r.linkPose("arm_link").inverse() * r.linkPose("hand");
  EXPECT_LT((rel.getOrigin() - btVector3(0.5, 0, 0)).length(), 1e-6);
  EXPECT_LT(rel.getRotation().getAngle(), 1e-6);
  // Its weight's reaction in the hand's axes (pitched by q about y), and the torque about the
  // wrist that keeps it level: minus the weight's, m g 0.1 cos(q) about y.
  const auto [f, tau] = r.jointWrench("wrist");
  EXPECT_NEAR(f.x(), -m * g * std::sin(q), 1e-6);
  EXPECT_NEAR(f.y(), 0.0, 1e-6);
  EXPECT_NEAR(f.z(), m * g * std::cos(q), 1e-6);
  EXPECT_NEAR(tau.y(), -m * g * 0.1 * std::cos(q), 1e-6);
  EXPECT_NEAR(tau.x(), 0.0, 1e-6);
  EXPECT_NEAR(tau.z(), 0.0, 1e-6);
  // Gazebo's model has the hand and the wrist: a link with its own mass, a fixed joint.
  ModelProperties props;
  ASSERT_TRUE(w.modelProperties("arm", props));
  EXPECT_EQ(props.links, (std::vector<std::string>{"base_link", "arm_link", "hand"}));
  EXPECT_EQ(props.joints, (std::vector<std::string>{"shoulder", "wrist"}));
  JointProperties jp;
  ASSERT_EQ(w.jointProperties("arm::wrist", jp), "");
  EXPECT_EQ(jp.type, JointSpec::FIXED);
  LinkProperties lp;
  ASSERT_EQ(w.linkProperties("arm::hand", lp), "");
  EXPECT_NEAR(lp.mass, 0.5, 1e-12);
  const std::string why = w.applyJointEffort("wrist", 1, w.time(), 0.1);
  EXPECT_NE(why.find("joint 'wrist' is fixed: it does not move"), std::string::npos) << why;

  // Without the tag, Gazebo lumps the wrist away: no joint, and the hand is the arm's link.
  auto lumped = std::make_shared<RobotSpec>(
      parseUrdf(with_hand.substr(0, with_hand.find("<gazebo reference=\"wrist\">")) + "</robot>", "arm.urdf"));
  w.addRobot(lumped, "plain", "", makeTransform(btVector3(3, 0, 0), btVector3(0, 0, 0)));
  for (const std::string& why : {w.jointProperties("plain::wrist", jp), w.applyJointEffort("plain::wrist", 1, 0, 1)})
    EXPECT_NE(why.find("joint 'plain::wrist' is fixed, and Gazebo lumps it away"), std::string::npos) << why;
  EXPECT_NE(w.linkProperties("plain::hand", lp).find("is lumped into 'plain::arm_link'"), std::string::npos);
  // "wrist" alone is the kept one's: the lumped one is no joint in Gazebo to be confused with.
  ASSERT_EQ(w.jointProperties("wrist", jp), "");
  EXPECT_EQ(jp.type, JointSpec::FIXED);
}

// Joint damping holds whatever the ratio of damping to the link's inertia. A 10 g arm 5 cm long
// with damping 0.1 N m s/rad is over-damped a thousandfold: it creeps down at the rate where
// damping balances gravity's torque, w = m g r cos(q) / d. As the explicit torque -d w it was before
// (d dt / I = 12 at 1 ms), the arm swung ever wider: -0.34 rad and -1000 rad/s after 1 s; damping
// 1e308 (scripts/fuzz) made it NaN. Damping that large holds the arm where it is.
TEST(Physics, StiffJointDampingIsStable)
{
  auto spec = std::make_shared<RobotSpec>(parseUrdf(R"(<robot name="light">
    <link name="world"/>
    <joint name="world_joint" type="fixed"><parent link="world"/><child link="base_link"/>
      <origin xyz="0 0 1.0"/></joint>
    <link name="base_link">
      <collision><geometry><box size="0.1 0.1 0.1"/></geometry></collision>
      <inertial><mass value="1"/><inertia ixx="0.002" ixy="0" ixz="0" iyy="0.002" iyz="0" izz="0.002"/></inertial>
    </link>
    <link name="arm_link">
      <inertial><origin xyz="0.025 0 0"/><mass value="0.01"/>
        <inertia ixx="1e-7" ixy="0" ixz="0" iyy="2e-6" iyz="0" izz="2e-6"/></inertial>
    </link>
    <joint name="shoulder" type="continuous"><parent link="base_link"/><child link="arm_link"/>
      <origin xyz="0 0 0.1"/><axis xyz="0 1 0"/><dynamics damping="0.1"/></joint></robot>)",
                                                    "light.urdf"));
  PhysicsWorld w(WorldSpec{}, {});
  Robot& r = w.addRobot(spec, "light", "", btTransform::getIdentity());
  run(w, 1.0);
  const double creep = 0.01 * 9.8 * 0.025 / 0.1;  // rad/s at q = 0; cos(q) stays above 0.9997
  std::printf("damped arm: %.5f rad after 1 s (creep %.5f rad/s), rate %.5f rad/s\n", r.jointPosition("shoulder"),
              creep, r.jointVelocity("shoulder"));
  EXPECT_NEAR(r.jointVelocity("shoulder"), creep, 0.01 * creep);
  EXPECT_NEAR(r.jointPosition("shoulder"), creep, 0.01 * creep);

  JointSettings huge;
  huge.damping = {1e308};
  EXPECT_EQ(w.setJointProperties("shoulder", huge), "");
  const double held = r.jointPosition("shoulder");
  run(w, 1.0);
  EXPECT_NEAR(r.jointPosition("shoulder"), held, 1e-9);
  EXPECT_NEAR(r.jointVelocity("shoulder"), 0.0, 1e-9);
}

// The same for an SDF ball joint, damped about each of its axes: a 10 g bob 5 cm from its pivot,
// let go level with it, creeps down at m g r / d about the horizontal axis across its rod.
TEST(Physics, StiffBallJointDampingIsStable)
{
  const std::string pendulum = R"(<sdf version="1.6"><model name="light">
      <link name="post"><pose>0 0 1 0 0 0</pose>
        <collision name="c"><geometry><box><size>0.05 0.05 0.05</size></box></geometry></collision></link>
      <link name="bob"><pose>0.05 0 1 0 0 0</pose>
        <inertial><mass>0.01</mass><inertia><ixx>1e-7</ixx><iyy>1e-7</iyy><izz>1e-7</izz></inertia></inertial></link>
      <joint name="anchor" type="fixed"><parent>world</parent><child>post</child></joint>
      <joint name="swivel" type="ball"><pose>-0.05 0 0 0 0 0</pose><parent>post</parent><child>bob</child>
        <axis><xyz>0 0 1</xyz><dynamics><damping>0.1</damping></dynamics></axis></joint></model></sdf>)";
  SdfSpawn sdf = parseSdfSpawn(pendulum, "light.sdf", ".");
  ASSERT_TRUE(sdf.robot);
  PhysicsWorld w(flatWorld(), {});
  Robot& r = w.addRobot(sdf.robot, "light", "", sdf.model.pose * sdf.root_in_model);
  run(w, 1.0);
  const btVector3 rod = r.linkPose("bob").getOrigin() - btVector3(0, 0, 1);
  const double angle = std::atan2(-rod.z(), rod.x()), creep = 0.01 * 9.8 * 0.05 / 0.1;  // rad/s
  std::printf("damped ball joint: %.5f rad after 1 s (creep %.5f rad/s)\n", angle, creep);
  EXPECT_NEAR(rod.length(), 0.05, 1e-6);
  EXPECT_NEAR(angle, creep, 0.01 * creep);
  EXPECT_NEAR(rod.y(), 0.0, 1e-9);
}
