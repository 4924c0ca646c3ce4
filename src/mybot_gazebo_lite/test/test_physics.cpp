#include "mybot_gazebo_lite/parsing.h"
#include "mybot_gazebo_lite/physics.h"

#include <BulletDynamics/Featherstone/btMultiBody.h>
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <sstream>

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
  WorldModel wall;
  wall.name = "wall";
  wall.pose.setOrigin(btVector3(1.5, 0, 0.25));
  WorldLink l;
  l.name = "link";
  Shape box;
  box.size = btVector3(0.2, 2.0, 0.5);
  l.shapes.push_back(box);
  wall.links.push_back(l);
  world.models.push_back(wall);
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

int main(int argc, char** argv)
{
  testing::InitGoogleTest(&argc, argv);
  return RUN_ALL_TESTS();
}
