// Plain descriptions of robots and worlds, parsed from URDF/SDF/YAML and
// consumed by the physics and sensor code. No ROS types.
#pragma once

#include <LinearMath/btTransform.h>

#include <map>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

namespace mybot_gazebo_lite
{

// Thrown for malformed input; what() names the file and the element.
class LoadError : public std::runtime_error
{
public:
  using std::runtime_error::runtime_error;
};

struct Triangle
{
  btVector3 a, b, c;
};

struct Shape
{
  enum Type
  {
    BOX,
    CYLINDER,
    SPHERE,
    PLANE,
    MESH
  } type = BOX;
  btVector3 size{0, 0, 0};        // box full extents
  double radius = 0, length = 0;  // cylinder (axis z) / sphere
  btVector3 normal{0, 0, 1};      // plane
  std::string mesh_path;          // resolved file path
  btVector3 mesh_scale{1, 1, 1};
  std::shared_ptr<const std::vector<Triangle>> triangles;  // mesh, scaled, shape frame
  btTransform pose = btTransform::getIdentity();           // relative to its link
  std::string name;                                        // an SDF <collision name>
  double mu1 = 1.0, mu2 = 1.0;
  // Gazebo's contact stiffness and damping (<gazebo reference> kp, kd); 0 = not set. Read, not
  // simulated: contacts are rigid (see urdf_parser.cpp).
  double kp = 0, kd = 0;
};

struct Inertial
{
  double mass = 0;
  btTransform origin = btTransform::getIdentity();  // COM frame relative to link
  double ixx = 0, ixy = 0, ixz = 0, iyy = 0, iyz = 0, izz = 0;
};

// A generic XML subtree (plugin and sensor blocks) kept for the plugins.
struct XmlNode
{
  std::string name;
  std::string text;
  std::map<std::string, std::string> attributes;
  std::vector<XmlNode> children;
  const XmlNode* child(const std::string& n) const
  {
    for (const auto& c : children)
      if (c.name == n)
        return &c;
    return nullptr;
  }
  std::vector<const XmlNode*> all(const std::string& n) const
  {
    std::vector<const XmlNode*> out;
    for (const auto& c : children)
      if (c.name == n)
        out.push_back(&c);
    return out;
  }
  std::string attr(const std::string& k, const std::string& def = "") const
  {
    auto it = attributes.find(k);
    return it == attributes.end() ? def : it->second;
  }
};

struct LinkSpec
{
  std::string name;
  bool has_inertial = false;
  Inertial inertial;
  std::vector<Shape> collisions;
  std::vector<XmlNode> sensors;  // <sensor> blocks from <gazebo reference>
  // <gazebo reference><material> (Gazebo/Red, ...) as RGB in [0, 1], for the cameras; grey otherwise.
  float color[3] = {0.7f, 0.7f, 0.7f};
};

struct JointSpec
{
  enum Type
  {
    FIXED,
    REVOLUTE,
    CONTINUOUS,
    PRISMATIC,
    FLOATING,
    PLANAR,
    BALL  // SDF's: three rotations about its pivot, free (a caster's)
  } type = FIXED;
  std::string name, parent, child;
  btTransform origin = btTransform::getIdentity();  // child frame in parent frame
  // The joint's own frame in the child's: URDF's is the child frame itself; SDF's joint <pose>
  // puts it elsewhere (a door's hinge at its edge). The axis is in this frame and passes through
  // its origin.
  btTransform pivot = btTransform::getIdentity();
  btVector3 axis{1, 0, 0};
  bool has_limits = false;
  double lower = 0, upper = 0, effort = 0, velocity = 0;
  bool has_effort = false, has_velocity = false;  // <limit effort|velocity> written
  double damping = 0, friction = 0;
  // A fixed joint Gazebo keeps (its <gazebo reference> says <disableFixedJointLumping> or
  // <preserveFixedJoint>): its child stays a body of its own instead of being lumped into its parent.
  bool keep_fixed = false;
  std::string mimic;  // URDF <mimic joint>: the joint it is said to follow ("" for none)
};

// A URDF <transmission> (transmission_interface/SimpleTransmission): one joint, one actuator.
struct TransmissionSpec
{
  std::string name, type, joint, actuator;
  std::vector<std::string> interfaces;  // "hardware_interface/EffortJointInterface" ... as written
  double reduction = 1.0;               // <mechanicalReduction>
};

struct PluginSpec
{
  std::string name, filename;
  std::string reference;  // link for sensor plugins, empty for model plugins
  // A nested model's plugin (SDF): "nested::", the prefix of its own model's joints and links,
  // which it names as Gazebo resolves them, in its model ("pan" for "mast::pan").
  std::string scope;
  XmlNode xml;  // the <plugin> element
  bool has_sensor = false;
  XmlNode sensor;  // owning <sensor> element for sensor plugins
};

struct RobotSpec
{
  std::string name;
  std::string source;  // file name or parameter, for messages
  std::vector<LinkSpec> links;
  std::vector<JointSpec> joints;
  std::vector<PluginSpec> plugins;  // model plugins + sensor plugins
  std::vector<TransmissionSpec> transmissions;
  std::string root;
  // Read from SDF: Gazebo keeps such a model's fixed joints and their child links (a URDF's it
  // lumps into their parents when it converts the URDF), and its model properties list them.
  bool from_sdf = false;
  std::vector<std::string> warnings;  // what the loader corrected, each naming its element; for the log
  const LinkSpec* link(const std::string& n) const
  {
    for (const auto& l : links)
      if (l.name == n)
        return &l;
    return nullptr;
  }
  const JointSpec* joint(const std::string& n) const
  {
    for (const auto& j : joints)
      if (j.name == n)
        return &j;
    return nullptr;
  }
};

// World models (SDF links with shapes; static or dynamic rigid bodies).
struct WorldLink
{
  std::string name;
  btTransform pose = btTransform::getIdentity();  // relative to model
  double mass = 1.0;
  std::vector<Shape> shapes;
  // <visual><material> diffuse (or ambient) RGB in [0, 1], for the cameras.
  bool has_color = false;
  float color[3] = {0.7f, 0.7f, 0.7f};
};

struct WorldModel
{
  std::string name;
  btTransform pose = btTransform::getIdentity();
  bool is_static = true;
  std::vector<WorldLink> links;
};

// A world's <physics> block; each value only when the world sets it (launch parameters win).
struct PhysicsSpec
{
  bool has_step = false, has_iterations = false, has_real_time_factor = false;
  double max_step_size = 0.001;
  int iterations = 10;  // <ode><solver><iters> (or <bullet><solver><iters>)
  double real_time_factor = 1.0;
};

// A shape where it stands now, in its colour: what the cameras draw of robots and dynamic bodies
// (PhysicsWorld::movingShapes). `shape` points into a spec that outlives the frame.
struct PlacedShape
{
  const Shape* shape = nullptr;
  btTransform tf = btTransform::getIdentity();  // the shape's frame in the world
  float color[3] = {0.7f, 0.7f, 0.7f};
};

// A model of the world file with joints or plugins: Gazebo simulates it as a robot (see
// parseSdfSpawn), spawned with the world, its root link at `model_pose * root_in_model`.
struct WorldRobot
{
  std::string name;
  std::shared_ptr<RobotSpec> spec;
  btTransform model_pose = btTransform::getIdentity();
  btTransform root_in_model = btTransform::getIdentity();
};

// A world's <spherical_coordinates>: where its origin is on the Earth (WGS84), and its heading
// offset (degrees, anticlockwise from east to the world's x axis; 0: x east, y north).
struct SphericalCoordinates
{
  double latitude_deg = 0, longitude_deg = 0, elevation = 0, heading_deg = 0;
};

struct WorldSpec
{
  std::string name = "default";
  PhysicsSpec physics;
  std::string source;
  btVector3 gravity{0, 0, -9.8};
  SphericalCoordinates spherical;
  bool ground_plane = false;
  std::vector<WorldModel> models;  // rigid: static, or without joints and plugins
  std::vector<WorldRobot> robots;
  // Every model's name as the file lists them, rigid or robot ("ground_plane" where it is
  // included): /gazebo/model_states' order, as Gazebo's.
  std::vector<std::string> file_order;
};

}  // namespace mybot_gazebo_lite
