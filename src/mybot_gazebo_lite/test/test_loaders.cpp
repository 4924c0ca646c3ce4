// Loading URDF, SDF worlds, image worlds and model.config: errors name the element.
#include "mybot_common/temp_dir.h"
#include "mybot_gazebo_lite/parsing.h"
#include "mybot_gazebo_lite/physics.h"
#include "load_error.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <functional>
#include <limits>
#include <sstream>

using namespace mybot_gazebo_lite;

TEST(Loaders, UrdfErrorsNameElement)
{
  try
  {
    parseUrdf(
        "<robot name='r'><link name='a'/><joint name='j' type='revolute'><parent link='a'/>"
        "<child link='b'/></joint><link name='b'/></robot>",
        "x.urdf");
    FAIL();
  }
  catch (const LoadError& e)
  {
    EXPECT_NE(std::string(e.what()).find("x.urdf: joint 'j'"), std::string::npos) << e.what();
  }
}

namespace
{
std::string wheelUrdf(const std::string& inertia)
{
  return "<robot name='r'><link name='base'><inertial><mass value='2'/><inertia ixx='1' iyy='1' izz='1'/></inertial>"
         "</link><link name='wheel'><inertial><mass value='0.5'/>" +
         inertia +
         "</inertial><collision><geometry><cylinder radius='0.1' length='0.04'/></geometry></collision></link>"
         "<joint name='j' type='continuous'><parent link='base'/><child link='wheel'/><axis xyz='0 0 1'/></joint>"
         "</robot>";
}
}  // namespace

// <gazebo> tags gazebo_lite does not read: an unknown one is warned naming the file, the
// reference and the tag; one it knows and does not simulate is warned as such; looks are silent.
TEST(Loaders, UrdfGazeboTagsNotReadAreWarnedNamingThem)
{
  const std::string urdf = wheelUrdf("<inertia ixx='0.001' iyy='0.001' izz='0.002'/>");
  RobotSpec r = parseUrdf(urdf.substr(0, urdf.rfind("</robot>")) +
                              "<gazebo reference='wheel'><fooBar>1</fooBar><minDepth>0.001</minDepth>"
                              "<material>Gazebo/Red</material></gazebo></robot>",
                          "w.urdf");
  ASSERT_EQ(r.warnings.size(), 2u);
  EXPECT_NE(r.warnings[0].find("w.urdf: <gazebo reference='wheel'> <fooBar>: unknown tag ignored"), std::string::npos)
      << r.warnings[0];
  EXPECT_NE(r.warnings[1].find("w.urdf: <gazebo reference='wheel'> <minDepth> = '0.001' is not simulated"),
            std::string::npos)
      << r.warnings[1];
  // The stock material is the colour the cameras draw the link in.
  const LinkSpec* wheel = r.link("wheel");
  ASSERT_NE(wheel, nullptr);
  EXPECT_FLOAT_EQ(wheel->color[0], 1.0f);
  EXPECT_FLOAT_EQ(wheel->color[1], 0.0f);
  EXPECT_FLOAT_EQ(wheel->color[2], 0.0f);
}

// A fixed joint's <gazebo reference> keeps it (Gazebo's preserveFixedJoint and
// disableFixedJointLumping): read silently; a value that is no boolean is refused naming the tag.
TEST(Loaders, UrdfKeptFixedJointsAreRead)
{
  const auto robot = [](const std::string& tags)
  {
    return "<robot name='r'><link name='a'><inertial><mass value='1'/><inertia ixx='1' iyy='1' izz='1'/></inertial>"
           "</link><link name='b'><inertial><mass value='1'/><inertia ixx='1' iyy='1' izz='1'/></inertial></link>"
           "<joint name='wrist' type='fixed'><parent link='a'/><child link='b'/></joint>"
           "<gazebo reference='wrist'>" +
           tags + "</gazebo></robot>";
  };
  EXPECT_FALSE(parseUrdf(robot(""), "k.urdf").joint("wrist")->keep_fixed);
  for (const std::string tags :
       {"<preserveFixedJoint>true</preserveFixedJoint>", "<disableFixedJointLumping>1</disableFixedJointLumping>",
        "<preserveFixedJoint value='true'/>"})
  {
    const RobotSpec r = parseUrdf(robot(tags), "k.urdf");
    EXPECT_TRUE(r.joint("wrist")->keep_fixed) << tags;
    EXPECT_TRUE(r.warnings.empty()) << r.warnings.front();
  }
  try
  {
    parseUrdf(robot("<preserveFixedJoint>yes please</preserveFixedJoint>"), "k.urdf");
    FAIL();
  }
  catch (const LoadError& e)
  {
    EXPECT_NE(std::string(e.what()).find("k.urdf: <gazebo reference='wrist'> <preserveFixedJoint>"), std::string::npos)
        << e.what();
    EXPECT_NE(std::string(e.what()).find("expected true or false, got 'yes please'"), std::string::npos) << e.what();
  }
}

// A URDF <mimic> Gazebo classic ignores: warned once naming the joint, unless a mimic joint
// plugin holds that joint.
TEST(Loaders, UrdfMimicWithoutAPluginIsWarned)
{
  const auto gripper = [](const std::string& gazebo)
  {
    return "<robot name='g'><link name='palm'><inertial><mass value='1'/><inertia ixx='1' iyy='1' izz='1'/>"
           "</inertial></link><link name='l'><inertial><mass value='0.1'/><inertia ixx='1' iyy='1' izz='1'/>"
           "</inertial></link><link name='r'><inertial><mass value='0.1'/><inertia ixx='1' iyy='1' izz='1'/>"
           "</inertial></link><joint name='left' type='continuous'><parent link='palm'/><child link='l'/></joint>"
           "<joint name='right' type='continuous'><parent link='palm'/><child link='r'/>"
           "<mimic joint='left' multiplier='-1'/></joint>" +
           gazebo + "</robot>";
  };
  const RobotSpec bare = parseUrdf(gripper(""), "g.urdf");
  EXPECT_EQ(bare.joint("right")->mimic, "left");
  ASSERT_EQ(bare.warnings.size(), 1u);
  EXPECT_NE(bare.warnings[0].find("g.urdf: joint 'right' <mimic joint='left'>: Gazebo classic ignores <mimic>"),
            std::string::npos)
      << bare.warnings[0];
  const RobotSpec held = parseUrdf(gripper("<gazebo><plugin name='m' filename='libroboticsgroup_upatras_gazebo_mimic_"
                                           "joint_plugin.so'><joint>left</joint><mimicJoint>right</mimicJoint>"
                                           "</plugin></gazebo>"),
                                   "g.urdf");
  EXPECT_TRUE(held.warnings.empty()) << held.warnings.front();
}

// A link's <material> picks its camera colour from Gazebo's stock scripts; any other script is
// drawn grey, with a warning naming it.
TEST(Loaders, UrdfMaterialColoursTheLinkForTheCameras)
{
  const std::string urdf = wheelUrdf("<inertia ixx='0.001' iyy='0.001' izz='0.002'/>");
  const std::string head = urdf.substr(0, urdf.rfind("</robot>"));
  RobotSpec r =
      parseUrdf(head + "<gazebo reference='wheel'><material>\n  Gazebo/Orange\n</material></gazebo></robot>", "w.urdf");
  EXPECT_TRUE(r.warnings.empty());
  EXPECT_FLOAT_EQ(r.link("wheel")->color[0], 1.0f);
  EXPECT_FLOAT_EQ(r.link("wheel")->color[1], 0.5088f);
  EXPECT_FLOAT_EQ(r.link("wheel")->color[2], 0.0468f);
  r = parseUrdf(head + "<gazebo reference='wheel'><material>MyPkg/Chrome</material></gazebo></robot>", "w.urdf");
  ASSERT_EQ(r.warnings.size(), 1u);
  EXPECT_NE(r.warnings[0].find("w.urdf: <gazebo reference='wheel'> <material> 'MyPkg/Chrome': not one of Gazebo's "
                               "stock colours, drawn grey"),
            std::string::npos)
      << r.warnings[0];
  EXPECT_FLOAT_EQ(r.link("wheel")->color[0], 0.7f);
  // A world's <material><script><name> too.
  WorldSpec w = parseSdfWorld(
      "<sdf version='1.6'><world name='w'><model name='m'><static>true</static><link name='l'>"
      "<collision name='c'><geometry><sphere><radius>0.5</radius></sphere></geometry></collision>"
      "<visual name='v'><material><script><uri>file://media/materials/scripts/gazebo.material</uri>"
      "<name>Gazebo/Blue</name></script></material></visual></link></model></world></sdf>",
      "w.world", ".");
  ASSERT_EQ(w.models.size(), 1u);
  EXPECT_TRUE(w.models[0].links[0].has_color);
  EXPECT_FLOAT_EQ(w.models[0].links[0].color[2], 1.0f);
  EXPECT_FLOAT_EQ(w.models[0].links[0].color[0], 0.0f);
}

// Zero inertia (the robot then never moved): corrected from the collision cylinder, with a
// warning naming the file and the link.
TEST(Loaders, UrdfZeroInertiaIsCorrectedWithAWarning)
{
  RobotSpec r = parseUrdf(wheelUrdf("<inertia ixx='0' iyy='0' izz='0'/>"), "w.urdf");
  ASSERT_EQ(r.warnings.size(), 1u);
  EXPECT_NE(r.warnings[0].find("w.urdf: link 'wheel' <inertia>"), std::string::npos) << r.warnings[0];
  const Inertial& in = r.link("wheel")->inertial;
  EXPECT_NEAR(in.izz, 0.5 * 0.5 * 0.1 * 0.1, 1e-12);                     // m r^2 / 2
  EXPECT_NEAR(in.ixx, 0.5 * (3 * 0.1 * 0.1 + 0.04 * 0.04) / 12, 1e-12);  // m (3 r^2 + l^2) / 12
  EXPECT_TRUE(r.link("base")->inertial.ixx == 1.0);                      // a good one is left alone
}

// Moments no body can have (izz larger than ixx + iyy) are corrected too.
TEST(Loaders, UrdfImpossibleInertiaIsCorrected)
{
  RobotSpec r = parseUrdf(wheelUrdf("<inertia ixx='0.001' iyy='0.001' izz='0.1'/>"), "w.urdf");
  ASSERT_EQ(r.warnings.size(), 1u);
  EXPECT_NE(r.warnings[0].find("link 'wheel'"), std::string::npos);
}

TEST(Loaders, UrdfNegativeInertiaIsRefusedNamingTheLink)
{
  try
  {
    parseUrdf(wheelUrdf("<inertia ixx='0.01' iyy='-0.01' izz='0.01'/>"), "w.urdf");
    FAIL();
  }
  catch (const LoadError& e)
  {
    EXPECT_NE(std::string(e.what()).find("w.urdf: link 'wheel' <inertia>: iyy="), std::string::npos) << e.what();
  }
}

TEST(Loaders, UrdfNonFiniteInertiaIsRefused)
{
  EXPECT_THROW(parseUrdf(wheelUrdf("<inertia ixx='nan' iyy='1' izz='1'/>"), "w.urdf"), LoadError);
  EXPECT_THROW(parseUrdf(wheelUrdf("<inertia ixx='1' iyy='inf' izz='1'/>"), "w.urdf"), LoadError);
}

namespace
{
std::string imageWorldError(const std::string& yaml,
                            const std::string& image_bytes = std::string("P5\n2 2\n255\n\x00\xfe\xfe\x00", 15))
{
  const mybot_common::TempDir dir("image_world");
  const std::string& d = dir.path();
  std::ofstream(d + "/m.pgm", std::ios::binary) << image_bytes;
  std::ofstream(d + "/w.yaml") << yaml;
  std::string error = "no error";
  try
  {
    loadWorldFile(d + "/w.yaml");
  }
  catch (const LoadError& e)
  {
    error = e.what();
  }
  return error;
}
}  // namespace

// The fields are map_server's, read by its one reader (mybot_common::readMapYaml, tested there):
// a file map_server refuses, the simulator refuses with the same message. `height` is ours.
TEST(Loaders, ImageWorldFieldsAreMapServersAndCheckedForMeaning)
{
  const std::string fields =
      "resolution: 0.1\norigin: [0, 0, 0]\nnegate: 0\noccupied_thresh: 0.65\nfree_thresh: 0.196\n";
  EXPECT_EQ(imageWorldError("image: m.pgm\n" + fields), "no error");
  EXPECT_EQ(imageWorldError("image: m.pgm\n" + fields + "height: 2.5\n"), "no error");
  EXPECT_NE(imageWorldError("image: m.pgm\nresolution: 0.1\norigin: [0, 0, 0]\n")
                .find("w.yaml: the map does not contain a 'negate' field"),
            std::string::npos);
  EXPECT_NE(imageWorldError("image: [a, b]\n" + fields).find("field 'image' must be a string"), std::string::npos);
  EXPECT_NE(imageWorldError("image: m.pgm\nresolution: 0.1\norigin: [.nan, 0, 0]\nnegate: 0\n"
                            "occupied_thresh: 0.65\nfree_thresh: 0.196\n")
                .find("field 'origin' must be finite"),
            std::string::npos);
  EXPECT_NE(imageWorldError("image: m.pgm\nresolution: .inf\n").find("field 'resolution' must be a finite number"),
            std::string::npos);
  EXPECT_NE(imageWorldError("image: m.pgm\nresolution: 0.1\nnegate: 0\noccupied_thresh: 7\nfree_thresh: 0.1\n")
                .find("field 'occupied_thresh' must be in [0, 1]"),
            std::string::npos);
  EXPECT_NE(imageWorldError("image: m.pgm\n" + fields + "height: -1\n")
                .find("w.yaml: field 'height' must be a positive number of metres, got -1"),
            std::string::npos);
  EXPECT_NE(imageWorldError("image: m.pgm\n" + fields + "height: tall\n").find("field 'height' must be a number"),
            std::string::npos);
}

// The pixels are map_server's too: the mean of the channels against occupied_thresh, so a colour
// floor plan has the walls map_server serves. Pure green is a wall to map_server (mean 85,
// occupancy 0.667); the luminance the simulator took before (150, occupancy 0.41) made it none.
TEST(Loaders, ImageWorldWallsAreTheCellsMapServerServesOccupied)
{
  const mybot_common::TempDir dir("image_world");
  const std::string& d = dir.path();
  // 2 x 1 RGB: pure green and light grey (mean 230, free).
  std::ofstream(d + "/m.ppm", std::ios::binary) << std::string("P6\n2 1\n255\n\x00\xff\x00\xe6\xe6\xe6", 17);
  std::ofstream(d + "/w.yaml") << "image: m.ppm\nresolution: 0.5\norigin: [1, 2, 0]\nnegate: 0\n"
                                  "occupied_thresh: 0.65\nfree_thresh: 0.196\nheight: 2\n";
  const WorldSpec w = loadWorldFile(d + "/w.yaml");
  ASSERT_EQ(w.models.size(), 1u);
  ASSERT_EQ(w.models[0].links.size(), 1u);
  const auto& shapes = w.models[0].links[0].shapes;
  ASSERT_EQ(shapes.size(), 1u);  // the green pixel only
  EXPECT_DOUBLE_EQ(shapes[0].size.x(), 0.5);
  EXPECT_DOUBLE_EQ(shapes[0].size.z(), 2.0);
  EXPECT_DOUBLE_EQ(shapes[0].pose.getOrigin().x(), 0.25);  // in the walls' model frame, at the origin
}

TEST(Loaders, ImageWorldWithAHugeHeaderIsRefusedBeforeDecoding)
{
  const std::string e = imageWorldError(
      "image: m.pgm\nresolution: 0.1\norigin: [0, 0, 0]\nnegate: 0\noccupied_thresh: 0.65\n"
      "free_thresh: 0.196\n",
      "P5\n200000 200000\n255\n");
  EXPECT_NE(e.find("declares 200000 x 200000 pixels, more than 20000 on a side (parameter ~max_image_side)"),
            std::string::npos)
      << e;
}

TEST(Loaders, SdfStateAndIncludeOfBuiltins)
{
  WorldSpec w = parseSdfWorld(
      "<sdf version='1.6'><world name='w'><include><uri>model://ground_plane</uri></include>"
      "<include><uri>model://sun</uri></include><model name='m'><static>true</static><pose>1 2 0 0 0 0</pose>"
      "<link name='l'><collision name='c'><geometry><sphere><radius>0.5</radius></sphere></geometry></collision>"
      "</link></model><state world_name='w'><model name='m'><pose>3 4 0 0 0 0</pose></model></state></world></sdf>",
      "w.world", ".");
  EXPECT_TRUE(w.ground_plane);
  ASSERT_EQ(w.models.size(), 1u);
  EXPECT_DOUBLE_EQ(w.models[0].pose.getOrigin().x(), 3.0);
  EXPECT_THROW(parseSdfWorld("<sdf><world><include><uri>model://nope_xyz</uri></include></world></sdf>", "w", "."),
               LoadError);
}

// A world file's model with joints (or plugins) is a robot, as Gazebo simulates it; a static one,
// or one with neither, stays rigid. A <state> block places the robot too.
TEST(Loaders, SdfWorldModelsWithJointsAreRobots)
{
  const std::string link = "<collision name='c'><geometry><box><size>0.1 0.1 0.1</size></box></geometry></collision>";
  WorldSpec w = parseSdfWorld(
      "<sdf version='1.6'><world name='w'>"
      "<model name='flap'><pose>1 2 0 0 0 0</pose><link name='post'><pose>0 0 0.5 0 0 0</pose>" +
          link + "</link><link name='leaf'><pose>0.3 0 0.5 0 0 0</pose>" + link +
          "</link><joint name='anchor' type='fixed'><parent>world</parent><child>post</child></joint>"
          "<joint name='hinge' type='revolute'><parent>post</parent><child>leaf</child><axis><xyz>0 0 1</xyz></axis>"
          "</joint></model>"
          "<model name='frozen'><static>true</static><link name='a'>" +
          link + "</link><link name='b'>" + link +
          "</link><joint name='j' type='revolute'><parent>a</parent><child>b</child></joint></model>"
          "<model name='crate'><link name='l'>" +
          link +
          "</link></model>"
          "<state world_name='w'><model name='flap'><pose>5 6 0 0 0 0</pose></model></state></world></sdf>",
      "w.world", ".");
  ASSERT_EQ(w.robots.size(), 1u);
  EXPECT_EQ(w.robots[0].name, "flap");
  EXPECT_EQ(w.robots[0].spec->name, "flap");
  EXPECT_EQ(w.robots[0].spec->joints.size(), 2u);
  EXPECT_DOUBLE_EQ(w.robots[0].model_pose.getOrigin().x(), 5.0);  // the <state>'s
  ASSERT_EQ(w.models.size(), 2u);
  EXPECT_EQ(w.models[0].name, "frozen");
  EXPECT_EQ(w.models[1].name, "crate");
  EXPECT_EQ(w.file_order, (std::vector<std::string>{"flap", "frozen", "crate"}));  // model_states' order
}

namespace
{
void expectSameTransform(const btTransform& a, const btTransform& b, const std::string& what)
{
  EXPECT_LT(a.getOrigin().distance(b.getOrigin()), 1e-12) << what;
  EXPECT_LT(std::abs(a.getRotation().dot(b.getRotation())) - 1, 1e-12) << what;
  EXPECT_GT(std::abs(a.getRotation().dot(b.getRotation())), 1 - 1e-12) << what;
}

// A door hinged to a post, with a sensor: SDF 1.6 places every link in the model's frame and
// each joint in its child's. `body` is the model's content after the post.
std::string door(const std::string& version, const std::string& body)
{
  return "<sdf version='" + version +
         "'><model name='door'><pose>1 2 0 0 0 0</pose>"
         "<link name='post'><pose>0 0 1 0 0 0</pose><collision name='c'><geometry><box><size>0.1 0.1 2</size></box>"
         "</geometry></collision></link>"
         "<joint name='anchor' type='fixed'><parent>world</parent><child>post</child></joint>" +
         body + "</model></sdf>";
}
}  // namespace

// SDF 1.7 writes a pose relative_to any frame of its model: here the door of SDF 1.6 (the leaf at
// 0.55 m, hinged 0.5 m from its centre) written as a URDF would, each link placed from its joint
// and the joint from its parent, the axis and the sensor in other frames, a rotation as a
// quaternion and one in degrees. Both files make the same robot.
TEST(Loaders, SdfPosesRelativeToOtherFramesMakeTheSameRobot)
{
  const std::string box = "<geometry><box><size>1 0.04 1.9</size></box></geometry>";
  const std::string inertia = "<mass>10</mass><inertia><ixx>3.4</ixx><iyy>4.2</iyy><izz>0.85</izz></inertia>";
  const std::string ray = "<sensor name='edge' type='ray'><update_rate>10</update_rate>";
  const SdfSpawn sdf16 = parseSdfSpawn(
      door("1.6", "<link name='leaf'><pose>0.55 0 1 0 0 0</pose><inertial><pose>0 0 0.1 0 0 0</pose>" + inertia +
                      "</inertial><collision name='panel'><pose>0 0.01 0 0 0 0</pose>" + box + "</collision>" + ray +
                      "<pose>0.1 0 0.2 0 0 0.3</pose></sensor></link>"
                      "<joint name='hinge' type='revolute'><pose>-0.5 0 0 0 0 0</pose><parent>post</parent>"
                      "<child>leaf</child><axis><xyz>0 0 1</xyz><limit><lower>-2</lower><upper>2</upper></limit>"
                      "</axis></joint>"),
      "door16.sdf", ".");
  const SdfSpawn sdf17 = parseSdfSpawn(
      door("1.7",
           "<frame name='hinge_axis' attached_to='post'><pose relative_to='hinge' rotation_format='quat_xyzw'>"
           "0 0 0 0.70710678118654757 0 0 0.70710678118654757</pose></frame>"
           "<link name='leaf'><pose relative_to='hinge'>0.5 0 0 0 0 0</pose>"
           "<inertial><pose relative_to='__model__'>0.55 0 1.1 0 0 0</pose>" +
               inertia + "</inertial><collision name='panel'><pose relative_to='hinge'>0.5 0.01 0 0 0 0</pose>" + box +
               "</collision>" + ray +
               "<pose relative_to='post' degrees='true'>0.65 0 0.2 0 0 17.188733853924695</pose></sensor></link>"
               "<joint name='hinge' type='revolute'><pose relative_to='post'>0.05 0 0 0 0 0</pose><parent>post</parent>"
               "<child>leaf</child><axis><xyz expressed_in='hinge_axis'>0 1 0</xyz><limit><lower>-2</lower>"
               "<upper>2</upper></limit></axis></joint>"),
      "door17.sdf", ".");
  ASSERT_TRUE(sdf16.robot && sdf17.robot);
  expectSameTransform(sdf16.root_in_model, sdf17.root_in_model, "root");
  const RobotSpec &a = *sdf16.robot, &b = *sdf17.robot;
  ASSERT_EQ(a.links.size(), b.links.size());
  for (size_t i = 0; i < a.links.size(); ++i)
  {
    const LinkSpec &la = a.links[i], &lb = b.links[i];
    ASSERT_EQ(la.name, lb.name);
    expectSameTransform(la.inertial.origin, lb.inertial.origin, la.name + " inertial");
    ASSERT_EQ(la.collisions.size(), lb.collisions.size());
    for (size_t k = 0; k < la.collisions.size(); ++k)
      expectSameTransform(la.collisions[k].pose, lb.collisions[k].pose, la.name + " collision");
    ASSERT_EQ(la.sensors.size(), lb.sensors.size());
    for (size_t k = 0; k < la.sensors.size(); ++k)
      expectSameTransform(parsePose6(la.sensors[k].child("pose")->text, "a"),
                          parsePose6(lb.sensors[k].child("pose")->text, "b"), la.name + " sensor");
  }
  ASSERT_EQ(a.joints.size(), b.joints.size());
  for (size_t i = 0; i < a.joints.size(); ++i)
  {
    const JointSpec &ja = a.joints[i], &jb = b.joints[i];
    ASSERT_EQ(ja.name, jb.name);
    expectSameTransform(ja.origin, jb.origin, ja.name + " origin");
    expectSameTransform(ja.pivot, jb.pivot, ja.name + " pivot");
    EXPECT_LT(ja.axis.distance(jb.axis), 1e-12) << ja.name << " axis";
  }
  EXPECT_NEAR(b.joints[1].pivot.getOrigin().x(), -0.5, 1e-12);  // the hinge, at the leaf's edge
}

// In a world, a model may be placed relative_to another model or a <frame> of the world, and in a
// model a link relative_to a <frame> and a nested model relative_to a link.
TEST(Loaders, SdfWorldModelsArePlacedRelativeToOtherModelsAndFrames)
{
  const std::string box = "<collision name='c'><geometry><box><size>0.1 0.1 0.1</size></box></geometry></collision>";
  const WorldSpec w = parseSdfWorld(
      "<sdf version='1.7'><world name='w'>"
      "<model name='flap'><pose relative_to='crate'>0 2 0 0 0 0</pose><link name='post'>" +
          box + "</link><link name='leaf'>" + box +
          "</link><joint name='hinge' type='revolute'><parent>post</parent><child>leaf</child></joint></model>"
          "<frame name='dock'><pose>10 0 0 0 0 1.5707963267948966</pose></frame>"
          "<model name='crate'><static>true</static><pose relative_to='dock'>1 0 0 0 0 0</pose>"
          "<frame name='corner'><pose>0.5 0.5 0 0 0 0</pose></frame>"
          "<link name='l'><pose relative_to='corner'>0 0 0.1 0 0 0</pose>" +
          box + "</link><model name='bin'><pose relative_to='l'>0 0 1 0 0 0</pose><link name='b'>" + box +
          "</link></model></model></world></sdf>",
      "w.world", ".");
  ASSERT_EQ(w.models.size(), 1u);
  const WorldModel& crate = w.models[0];
  EXPECT_LT(crate.pose.getOrigin().distance(btVector3(10, 1, 0)), 1e-12);  // the dock's y is the world's -x
  ASSERT_EQ(crate.links.size(), 2u);
  EXPECT_LT(crate.links[0].pose.getOrigin().distance(btVector3(0.5, 0.5, 0.1)), 1e-12);
  EXPECT_EQ(crate.links[1].name, "bin::b");
  EXPECT_LT(crate.links[1].pose.getOrigin().distance(btVector3(0.5, 0.5, 1.1)), 1e-12);
  ASSERT_EQ(w.robots.size(), 1u);
  EXPECT_LT(w.robots[0].model_pose.getOrigin().distance(btVector3(8, 1, 0)), 1e-12);
}

// A model's <include>s are part of it, as its nested <model>s are: before 2026-12-01 they were
// left out without a word (a shelf's included crates missing from the world).
TEST(Loaders, SdfIncludesInAModelAreFlattenedIntoIt)
{
  const WorldSpec w = parseSdfWorld(
      "<sdf version='1.7'><world name='w'><model name='shelf'><static>true</static><pose>1 0 0 0 0 0</pose>"
      "<link name='board'><pose>0 0 1 0 0 0</pose><collision name='c'><geometry><box><size>1 0.3 0.02</size></box>"
      "</geometry></collision></link>"
      "<include><uri>model://tutorial_laser</uri><name>scanner</name><pose relative_to='board'>0.2 0 0.1 0 0 0</pose>"
      "</include><include><uri>model://tutorial_laser</uri><name>spare</name></include></model></world></sdf>",
      "w.world", FIXTURE_DIR);
  ASSERT_EQ(w.models.size(), 1u);
  const WorldModel& shelf = w.models[0];
  ASSERT_EQ(shelf.links.size(), 3u);
  EXPECT_EQ(shelf.links[1].name, "scanner::link");
  EXPECT_LT(shelf.links[1].pose.getOrigin().distance(btVector3(0.2, 0, 1.1)), 1e-12);
  EXPECT_EQ(shelf.links[2].name, "spare::link");
  EXPECT_LT(shelf.links[2].pose.getOrigin().distance(btVector3(0, 0, 0.5)), 1e-12);  // the model file's own pose
  ASSERT_EQ(shelf.links[1].shapes.size(), 1u);
  EXPECT_EQ(loadErrorOf(
                []
                {
                  parseSdfWorld(
                      "<sdf version='1.6'><world name='w'><model name='m'><link name='l'/><include><uri>"
                      "model://sun</uri></include></model></world></sdf>",
                      "w.world", ".");
                }),
            "w.world: <world> <model name='m'> <include> <uri>model://sun</uri>: the sun and the ground plane belong "
            "in the world, not in a model");
}

// Two model files that include each other, through a model nested in one of them: refused,
// naming the loop, where it would have been read for ever.
TEST(Loaders, SdfModelsThatIncludeEachOtherAreRefused)
{
  const mybot_common::TempDir dir("include_loop");
  const std::string& d = dir.path();
  ASSERT_EQ(std::system(("mkdir -p " + d + "/models/a " + d + "/models/b").c_str()), 0);
  std::ofstream(d + "/models/a/model.sdf") << "<sdf version='1.6'><model name='a'><link name='l'/><model name='n'>"
                                              "<include><uri>model://b</uri></include></model></model></sdf>";
  std::ofstream(d + "/models/b/model.sdf")
      << "<sdf version='1.6'><model name='b'><link name='l'/><include><uri>model://a</uri></include></model></sdf>";
  const char* old = std::getenv("GAZEBO_MODEL_PATH");  // where one model finds the other, as in Gazebo
  const std::string saved = old ? old : "";
  setenv("GAZEBO_MODEL_PATH", (d + "/models").c_str(), 1);
  const std::string error = loadErrorOf(
      [&]
      {
        parseSdfWorld("<sdf version='1.6'><world name='w'><include><uri>model://a</uri></include></world></sdf>",
                      d + "/w.world", d);
      });
  // A model folder linked under a second name is the same model.
  ASSERT_EQ(
      std::system(("mkdir -p " + d + "/models/self && ln -s " + d + "/models/self " + d + "/models/alias").c_str()), 0);
  std::ofstream(d + "/models/self/model.sdf")
      << "<sdf version='1.6'><model name='s'><link name='l'/><include><uri>model://alias</uri></include></model></sdf>";
  const std::string aliased = loadErrorOf(
      [&]
      {
        parseSdfWorld("<sdf version='1.6'><world name='w'><include><uri>model://self</uri></include></world></sdf>",
                      d + "/w.world", d);
      });
  if (old)
    setenv("GAZEBO_MODEL_PATH", saved.c_str(), 1);
  else
    unsetenv("GAZEBO_MODEL_PATH");
  EXPECT_EQ(aliased, d +
                         "/models/self/model.sdf: <model name='s'> <include> <uri>model://alias</uri>: the model "
                         "includes itself: " +
                         d + "/models/self/model.sdf -> " + d + "/models/alias/model.sdf");
  EXPECT_EQ(error, d +
                       "/models/b/model.sdf: <model name='b'> <include> <uri>model://a</uri>: the model includes "
                       "itself: " +
                       d + "/models/a/model.sdf -> " + d + "/models/b/model.sdf -> " + d + "/models/a/model.sdf");
}

TEST(Loaders, SdfFrameErrorsNameTheElement)
{
  const std::string joint =
      "<link name='leaf'/><joint name='hinge' type='revolute'><parent>post</parent>"
      "<child>leaf</child><axis><xyz expressed_in='nope'>0 0 1</xyz></axis></joint>";
  for (const auto& [xml, says] : std::vector<std::pair<std::string, std::string>>{
           {door("1.7", joint),
            "d.sdf: <model name='door'> <joint name='hinge'> <axis> <xyz expressed_in>: 'nope': no frame of that name "
            "in this model"},
           {door("1.7",
                 "<link name='leaf'><pose relative_to='hinge'/></link><joint name='hinge' type='revolute'>"
                 "<parent>post</parent><child>leaf</child></joint>"),
            "d.sdf: <model name='door'> <link name='leaf'>: relative_to makes a loop: leaf -> hinge -> leaf"},
           {door("1.7", "<frame name='f' attached_to='nope'/>"),
            "d.sdf: <model name='door'> <frame name='f'> attached_to: 'nope': no frame of that name in this model"},
           {door("1.7", "<link name='l'><pose relative_to='world'>0 0 0 0 0 0</pose></link>"),
            "'world': no frame of that name in this model"},
           {"<sdf version='1.7'><model name='m'><pose relative_to='x'>0 0 0 0 0 0</pose><link name='l'/></model></sdf>",
            "d.sdf: <model name='m'> <pose relative_to>: 'x': no frame of that name outside a world"},
           {door("1.9", "<link name='l'><pose degrees='maybe'>0 0 0 0 0 0</pose></link>"),
            "<link name='l'> <pose degrees>: expected true or false, got 'maybe'"},
           {door("1.9", "<link name='l'><pose rotation_format='quat_wxyz'>0 0 0 1 0 0 0</pose></link>"),
            "<link name='l'> <pose rotation_format>: 'quat_wxyz': euler_rpy or quat_xyzw"},
           {door("1.9", "<link name='l'><pose rotation_format='quat_xyzw'>0 0 0 0 0 0 0</pose></link>"),
            "<link name='l'> <pose>: a zero quaternion is no rotation"}})
    EXPECT_NE(loadErrorOf([&] { parseSdfSpawn(xml, "d.sdf", "."); }).find(says), std::string::npos)
        << loadErrorOf([&] { parseSdfSpawn(xml, "d.sdf", "."); });
  EXPECT_EQ(loadErrorOf(
                [&]
                {
                  parseSdfWorld(
                      "<sdf version='1.7'><world name='w'><model name='m'><pose relative_to='ghost'>0 0 0 0 "
                      "0 0</pose><link name='l'/></model></world></sdf>",
                      "w.world", ".");
                }),
            "w.world: <world> <model name='m'> <pose relative_to>: 'ghost': no frame of that name in this world");
}

TEST(Loaders, WorldPhysicsBlockSetsStepIterationsAndRealTimeFactor)
{
  WorldSpec w = parseSdfWorld(
      "<sdf version='1.6'><world name='w'><physics type='ode'><max_step_size>0.002</max_step_size>"
      "<real_time_factor>3</real_time_factor><ode><solver><iters>50</iters></solver></ode></physics></world></sdf>",
      "w.world", ".");
  EXPECT_TRUE(w.physics.has_step && w.physics.has_real_time_factor && w.physics.has_iterations);
  EXPECT_DOUBLE_EQ(w.physics.max_step_size, 0.002);
  EXPECT_DOUBLE_EQ(w.physics.real_time_factor, 3.0);
  EXPECT_EQ(w.physics.iterations, 50);
  WorldSpec none = parseSdfWorld("<sdf version='1.6'><world name='w'></world></sdf>", "w.world", ".");
  EXPECT_FALSE(none.physics.has_step || none.physics.has_real_time_factor || none.physics.has_iterations);
  try
  {
    parseSdfWorld("<sdf><world><physics><max_step_size>fast</max_step_size></physics></world></sdf>", "bad.world", ".");
    FAIL() << "accepted a step of 'fast'";
  }
  catch (const LoadError& e)
  {
    EXPECT_NE(std::string(e.what()).find("bad.world: <physics> <max_step_size>"), std::string::npos) << e.what();
  }
  EXPECT_THROW(
      parseSdfWorld("<sdf><world><physics><ode><solver><iters>2.5</iters></solver></ode></physics></world></sdf>", "w",
                    "."),
      LoadError);
}

// Where the world lies on the Earth, for the compass (hector's magnetometer takes its heading).
TEST(Loaders, WorldSphericalCoordinates)
{
  WorldSpec w = parseSdfWorld(
      "<sdf version='1.6'><world name='w'><spherical_coordinates><surface_model>EARTH_WGS84</surface_model>"
      "<latitude_deg>49.9</latitude_deg><longitude_deg>8.9</longitude_deg><elevation>100</elevation>"
      "<heading_deg>30</heading_deg></spherical_coordinates></world></sdf>",
      "w.world", ".");
  EXPECT_DOUBLE_EQ(w.spherical.latitude_deg, 49.9);
  EXPECT_DOUBLE_EQ(w.spherical.longitude_deg, 8.9);
  EXPECT_DOUBLE_EQ(w.spherical.elevation, 100);
  EXPECT_DOUBLE_EQ(w.spherical.heading_deg, 30);
  EXPECT_DOUBLE_EQ(parseSdfWorld("<sdf version='1.6'><world name='w'/></sdf>", "w", ".").spherical.heading_deg, 0);
  for (const auto& [body, says] : std::vector<std::pair<std::string, std::string>>{
           {"<surface_model>MOON_SCS</surface_model>", "<spherical_coordinates> <surface_model>: 'MOON_SCS'"},
           {"<latitude_deg>91</latitude_deg>", "<latitude_deg>: must be within [-90, 90]"},
           {"<heading_deg>north</heading_deg>", "heading_deg"}})
  {
    try
    {
      parseSdfWorld("<sdf><world><spherical_coordinates>" + body + "</spherical_coordinates></world></sdf>",
                    "bad.world", ".");
      ADD_FAILURE() << "accepted " << body;
    }
    catch (const LoadError& e)
    {
      EXPECT_NE(std::string(e.what()).find(says), std::string::npos) << e.what();
    }
  }
}

TEST(Loaders, ModelConfigPicksTheNewestSdf)
{
  const mybot_common::TempDir dir("model_config");
  const std::string& d = dir.path();
  const std::string m = d + "/models/box";
  ASSERT_EQ(std::system(("mkdir -p " + m).c_str()), 0);
  auto model = [](double r)
  {
    return "<sdf version='1.6'><model name='b'><static>true</static><link name='l'><collision name='c'><geometry>"
           "<sphere><radius>" +
           std::to_string(r) + "</radius></sphere></geometry></collision></link></model></sdf>";
  };
  std::ofstream(m + "/model-1_4.sdf") << model(0.1);
  std::ofstream(m + "/model-1_6.sdf") << model(0.6);
  std::ofstream(m + "/model-1_5.sdf") << model(0.5);
  std::ofstream(m + "/model.config")
      << "<model><name>box</name><sdf version='1.4'>model-1_4.sdf</sdf>"
         "<sdf version='1.6'>model-1_6.sdf</sdf><sdf version='1.5'>model-1_5.sdf</sdf></model>";
  WorldSpec w = parseSdfWorld(
      "<sdf version='1.6'><world name='w'><include><uri>model://box</uri></include></world></sdf>", d + "/w.world", d);
  ASSERT_EQ(w.models.size(), 1u);
  ASSERT_EQ(w.models[0].links.size(), 1u);
  EXPECT_NEAR(w.models[0].links[0].shapes.at(0).radius, 0.6, 1e-9);
}

TEST(Loaders, PackageUrisResolveWithoutRoslib)
{
  const mybot_common::TempDir dir("pkg_path");
  const std::string& d = dir.path();
  ASSERT_EQ(std::system(("mkdir -p " + d + "/ws/src/group/my_robot_description/meshes " + d +
                         "/ws/src/ignored/my_other " + d + "/ws/src/renamed_folder")
                            .c_str()),
            0);
  std::ofstream(d + "/ws/src/group/my_robot_description/package.xml")
      << "<package><name>my_robot_description</name></package>";
  std::ofstream(d + "/ws/src/group/my_robot_description/meshes/wheel.stl") << "solid x\nendsolid x\n";
  std::ofstream(d + "/ws/src/renamed_folder/package.xml") << "<package><name>my_renamed</name></package>";
  std::ofstream(d + "/ws/src/ignored/CATKIN_IGNORE") << "";
  std::ofstream(d + "/ws/src/ignored/my_other/package.xml") << "<package><name>my_other</name></package>";
  const char* old = std::getenv("ROS_PACKAGE_PATH");
  const std::string saved = old ? old : "";
  setenv("ROS_PACKAGE_PATH", (d + "/ws/src").c_str(), 1);
  EXPECT_EQ(findPackage("my_robot_description"), d + "/ws/src/group/my_robot_description");
  EXPECT_EQ(findPackage("my_renamed"), d + "/ws/src/renamed_folder");  // by package.xml name, not folder
  EXPECT_EQ(findPackage("my_other"), "");                              // under CATKIN_IGNORE
  EXPECT_EQ(defaultResolveUri("package://my_robot_description/meshes/wheel.stl", ""),
            d + "/ws/src/group/my_robot_description/meshes/wheel.stl");
  EXPECT_EQ(defaultResolveUri("package://my_robot_description/meshes/nope.stl", ""), "");
  setenv("ROS_PACKAGE_PATH", saved.c_str(), 1);
}

// Every world the package ships loads (the office floor plan is launched by no test otherwise).
TEST(Loaders, ShippedWorldsLoad)
{
  int loaded = 0;
  for (const auto& entry : std::filesystem::directory_iterator(std::string(FIXTURE_DIR) + "/../../worlds"))
  {
    const std::string ext = entry.path().extension().string();
    if (ext != ".world" && ext != ".yaml")
      continue;
    SCOPED_TRACE(entry.path().string());
    const WorldSpec w = loadWorldFile(entry.path().string());
    EXPECT_TRUE(w.ground_plane);
    if (ext == ".yaml")  // a floor plan: its walls, one model of boxes
    {
      ASSERT_EQ(w.models.size(), 1u);
      ASSERT_EQ(w.models[0].links.size(), 1u);
      EXPECT_GT(w.models[0].links[0].shapes.size(), 10u);
    }
    ++loaded;
  }
  EXPECT_GE(loaded, 4);
}

// What scripts/fuzz found, kept in test/fuzz_findings: each file's first line says what the loader
// must do with it, "EXPECT refused: TEXT" (a LoadError naming the file and saying TEXT) or
// "EXPECT simulated" (loaded, and finite after 0.2 s on the ground). Before 2026-12-02 every one of
// them loaded and turned the robot to NaN within 0.2 s; the fuzzer's sanitizer build replays them
// too (scripts/fuzz --replay), for what only a sanitizer sees.
TEST(Loaders, FuzzFindings)
{
  const std::string dir = std::string(FIXTURE_DIR) + "/../fuzz_findings";
  int checked = 0;
  for (const auto& entry : std::filesystem::directory_iterator(dir))
  {
    const std::string path = entry.path().string(), name = entry.path().filename().string();
    std::ifstream f(path);
    std::stringstream text;
    text << f.rdbuf();
    const std::string xml = text.str(), first = xml.substr(0, xml.find('\n'));
    const auto expect = first.find("EXPECT ");
    ASSERT_NE(expect, std::string::npos) << name << ": its first line says nothing it expects";
    const std::string what = first.substr(expect + 7, first.rfind(" -->") - expect - 7);
    SCOPED_TRACE(name + ": " + what);
    const std::string refused = "refused: ";
    if (what.rfind(refused, 0) == 0)
    {
      const std::string error = loadErrorOf([&] { parseUrdf(xml, name); });
      EXPECT_NE(error.find(name + ": "), std::string::npos) << error;
      EXPECT_NE(error.find(what.substr(refused.size())), std::string::npos) << error;
    }
    else
    {
      ASSERT_EQ(what.rfind("simulated", 0), 0u);
      auto spec = std::make_shared<RobotSpec>(parseUrdf(xml, name));
      WorldSpec ground;
      ground.ground_plane = true;
      PhysicsWorld world(ground, {});
      world.addRobot(spec, "bot", "", btTransform(btQuaternion::getIdentity(), btVector3(0, 0, 0.05)));
      for (int i = 0; i < 200; ++i)
        world.step();
      for (const auto& [link, pose] : world.linkStates())
        EXPECT_TRUE(std::isfinite(pose.tf.getOrigin().length()) && std::isfinite(pose.linear.length()))
            << link << " is not finite after 0.2 s";
    }
    ++checked;
  }
  EXPECT_GE(checked, 7);
}
