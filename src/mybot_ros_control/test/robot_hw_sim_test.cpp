// The simulated robot hardware on its own: transmissions read from a tutorial-style URDF,
// limits, and commands reaching the joints through the physics.
#include "mybot_ros_control/robot_hw_sim.h"

#include <mybot_gazebo_lite/parsing.h>

#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <sstream>

using mybot_gazebo_lite::LoadError;
using mybot_gazebo_lite::PhysicsWorld;
using mybot_gazebo_lite::RobotSpec;
using namespace mybot_ros_control;

namespace
{
std::string readFixture(const std::string& name)
{
  std::ifstream f(std::string(FIXTURE_DIR) + "/" + name);
  std::stringstream ss;
  ss << f.rdbuf();
  return ss.str();
}

std::string withTransmission(const std::string& type, const std::string& joint, const std::string& iface)
{
  return R"(<robot name="t"><link name="a"><inertial><mass value="1"/><inertia ixx="0.1" iyy="0.1" izz="0.1"/></inertial></link>
    <link name="b"><inertial><mass value="1"/><inertia ixx="0.1" iyy="0.1" izz="0.1"/></inertial></link>
    <joint name="j" type="continuous"><parent link="a"/><child link="b"/><axis xyz="0 0 1"/></joint>
    <transmission name="tr"><type>)" +
         type + R"(</type><joint name=")" + joint + R"("><hardwareInterface>)" + iface +
         R"(</hardwareInterface></joint><actuator name="m"><mechanicalReduction>1</mechanicalReduction></actuator></transmission></robot>)";
}
}  // namespace

TEST(RobotHWSim, ReadsTheTutorialTransmissions)
{
  const RobotSpec spec = mybot_gazebo_lite::parseUrdf(readFixture("r2d2_control.urdf"), "r2d2_control.urdf");
  std::vector<std::string> warnings;
  RobotHWSim hw(spec, warnings);
  EXPECT_TRUE(warnings.empty());
  ASSERT_EQ(hw.joints().size(), 8u);
  const SimJoint* wheel = hw.joint("left_front_wheel_joint");
  ASSERT_NE(wheel, nullptr);
  EXPECT_TRUE(wheel->has(Interface::VELOCITY));
  EXPECT_FALSE(wheel->has(Interface::POSITION));
  EXPECT_TRUE(wheel->continuous);
  EXPECT_FALSE(std::isfinite(wheel->max_effort));  // no <limit>: unlimited, as in Gazebo
  const SimJoint* ext = hw.joint("gripper_extension");
  ASSERT_NE(ext, nullptr);
  EXPECT_TRUE(ext->has(Interface::EFFORT));
  EXPECT_TRUE(ext->has_position_limits);
  EXPECT_DOUBLE_EQ(ext->lower, -0.38);
  EXPECT_DOUBLE_EQ(ext->max_velocity, 0.5);
  EXPECT_DOUBLE_EQ(clampPosition(*ext, -1.0), -0.38);
  EXPECT_DOUBLE_EQ(clampPosition(*ext, 0.5), 0.0);
  const SimJoint* head = hw.joint("head_swivel");
  EXPECT_DOUBLE_EQ(head->max_effort, 30.0);
  EXPECT_DOUBLE_EQ(clampPosition(*head, 7.0), 7.0);  // continuous: never clamped
}

TEST(RobotHWSim, ValueAttributesSetFrictionAndStiffness)
{
  const RobotSpec spec = mybot_gazebo_lite::parseUrdf(readFixture("r2d2_control.urdf"), "r2d2_control.urdf");
  const auto* wheel = spec.link("right_back_wheel");
  ASSERT_NE(wheel, nullptr);
  EXPECT_DOUBLE_EQ(wheel->collisions.at(0).mu1, 200.0);
  EXPECT_DOUBLE_EQ(wheel->collisions.at(0).mu2, 100.0);
  EXPECT_DOUBLE_EQ(wheel->collisions.at(0).kp, 1e7);
  EXPECT_DOUBLE_EQ(wheel->collisions.at(0).kd, 1.0);
  ASSERT_EQ(spec.transmissions.size(), 8u);
  EXPECT_EQ(spec.transmissions.front().type, "transmission_interface/SimpleTransmission");
}

TEST(RobotHWSim, RefusesWhatItCannotSimulateNamingTheTransmission)
{
  std::vector<std::string> w;
  const RobotSpec other =
      mybot_gazebo_lite::parseUrdf(withTransmission("transmission_interface/DifferentialTransmission", "j",
                                                    "hardware_interface/EffortJointInterface"),
                                   "t.urdf");
  try
  {
    RobotHWSim hw(other, w);
    FAIL() << "a differential transmission was accepted";
  }
  catch (const LoadError& e)
  {
    EXPECT_NE(std::string(e.what()).find("<transmission name='tr'>"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("DifferentialTransmission"), std::string::npos) << e.what();
  }
  const RobotSpec bad_iface = mybot_gazebo_lite::parseUrdf(
      withTransmission("transmission_interface/SimpleTransmission", "j", "hardware_interface/JointStateInterface"),
      "t.urdf");
  EXPECT_THROW(RobotHWSim(bad_iface, w), LoadError);
  EXPECT_THROW(
      mybot_gazebo_lite::parseUrdf(
          withTransmission("transmission_interface/SimpleTransmission", "nope", "EffortJointInterface"), "t.urdf"),
      LoadError);
  // The short pre-Indigo interface name still works, with a warning.
  const RobotSpec old = mybot_gazebo_lite::parseUrdf(
      withTransmission("transmission_interface/SimpleTransmission", "j", "EffortJointInterface"), "t.urdf");
  RobotHWSim hw(old, w);
  EXPECT_TRUE(hw.joint("j")->has(Interface::EFFORT));
  ASSERT_EQ(w.size(), 1u);
  EXPECT_NE(w[0].find("deprecated"), std::string::npos);
}

TEST(RobotHWSim, PositionCommandsReachTheirTargetAtTheVelocityLimit)
{
  auto spec =
      std::make_shared<RobotSpec>(mybot_gazebo_lite::parseUrdf(readFixture("r2d2_control.urdf"), "r2d2_control.urdf"));
  PhysicsWorld world(mybot_gazebo_lite::WorldSpec{}, PhysicsWorld::Options{});
  auto& robot = world.addRobot(spec, "r2d2", "", btTransform(btQuaternion::getIdentity(), btVector3(0, 0, 5)));
  std::vector<std::string> w;
  RobotHWSim hw(*spec, w);
  hw.reset(robot);
  SimJoint& head = *hw.joint("head_swivel");
  hw.claim(head, Interface::POSITION);
  head.command = 0.5;
  double max_speed = 0, max_effort = 0;
  for (int k = 0; k < 2000; ++k)
  {  // 2 s; no gravity: the world has none
    hw.read(robot);
    max_speed = std::max(max_speed, std::abs(head.velocity));
    max_effort = std::max(max_effort, std::abs(head.effort));
    hw.write(robot, world.stepSize());
    world.step();
  }
  hw.read(robot);
  EXPECT_NEAR(head.position, 0.5, 0.01);
  EXPECT_LT(max_speed, 1.0 + 1e-6);  // <limit velocity="1.0">
  // The state's effort is what the servo exerted: it sped the head up, within its <limit effort>,
  // and holds it with nothing once it is there (no gravity, no load).
  EXPECT_GT(max_effort, 0.1);
  EXPECT_LE(max_effort, 30.0 + 1e-9);
  EXPECT_LT(std::abs(head.effort), 1e-6);
}

TEST(RobotHWSim, EffortCommandsAreClampedToTheLimit)
{
  auto spec =
      std::make_shared<RobotSpec>(mybot_gazebo_lite::parseUrdf(readFixture("r2d2_control.urdf"), "r2d2_control.urdf"));
  PhysicsWorld world(mybot_gazebo_lite::WorldSpec{}, PhysicsWorld::Options{});
  auto& robot = world.addRobot(spec, "r2d2", "", btTransform::getIdentity());
  robot.commandEffort("head_swivel", 1000.0);
  EXPECT_DOUBLE_EQ(robot.jointEffort("head_swivel"), 30.0);
  robot.commandEffort("head_swivel", -1000.0);
  EXPECT_DOUBLE_EQ(robot.jointEffort("head_swivel"), -30.0);
}
