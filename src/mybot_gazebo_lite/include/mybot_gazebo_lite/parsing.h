// URDF (+ <gazebo> extensions), SDF-subset and occupancy-image world loaders.
#pragma once

#include "mybot_common/image_header.h"

#include "mybot_gazebo_lite/model.h"

#include <functional>
#include <memory>
#include <string>

namespace tinyxml2
{
class XMLElement;
}

namespace mybot_gazebo_lite
{

// Resolves package:// and model:// URIs and plain paths to a file path.
// Returns "" when not found. Relative paths resolve against base_dir.
using UriResolver = std::function<std::string(const std::string& uri, const std::string& base_dir)>;
std::string defaultResolveUri(const std::string& uri, const std::string& base_dir);
// A ROS package's folder by its package.xml name, found on ROS_PACKAGE_PATH as rospack does
// ("" when not found). The core library stays ROS-free: it reads the environment, not roslib.
std::string findPackage(const std::string& pkg);

// Parses a URDF document. `source` names the file/parameter in error messages.
RobotSpec parseUrdf(const std::string& xml, const std::string& source, const UriResolver& resolver = defaultResolveUri);

// Loads a world: .yaml -> occupancy-image floor plan, anything else -> SDF. An image with more
// than max_image_side pixels on a side is refused (from its header, before decoding).
WorldSpec loadWorldFile(const std::string& path, const UriResolver& resolver = defaultResolveUri,
                        long max_image_side = mybot_common::kDefaultMaxImageSide);
WorldSpec parseSdfWorld(const std::string& xml, const std::string& source, const std::string& base_dir,
                        const UriResolver& resolver = defaultResolveUri);
// One SDF model, as gazebo_ros's spawn_sdf_model takes it: <sdf><model> (or a bare <model>);
// nested models are flattened into it, as in a world.
WorldModel parseSdfModel(const std::string& xml, const std::string& source, const std::string& base_dir,
                         const UriResolver& resolver = defaultResolveUri);
// What gazebo_ros's spawn_sdf_model makes of an SDF model: a world model of rigid links when it
// is static or has neither joints nor plugins (its own or its sensors'); otherwise a robot as
// Gazebo simulates it (`robot` set): its links, joints (revolute, continuous, prismatic, fixed;
// a joint to `world` anchors it, as a URDF's `world` link) and plugins, its root link at the
// model's pose times `root_in_model`.
struct SdfSpawn
{
  WorldModel model;
  std::shared_ptr<RobotSpec> robot;
  btTransform root_in_model = btTransform::getIdentity();
};
SdfSpawn parseSdfSpawn(const std::string& xml, const std::string& source, const std::string& base_dir,
                       const UriResolver& resolver = defaultResolveUri);
WorldSpec loadImageWorld(const std::string& yaml_path, long max_image_side = mybot_common::kDefaultMaxImageSide);

// Helpers shared by the loaders.
btVector3 parseVec3(const std::string& s, const std::string& what);
btTransform parsePose6(const std::string& s, const std::string& what);  // "x y z r p y"
btTransform makeTransform(const btVector3& xyz, const btVector3& rpy);
XmlNode toXmlNode(const tinyxml2::XMLElement* e);
std::string dirOf(const std::string& path);  // "." for a bare file name
// A file's text; LoadError "<what>: cannot read '<path>'" when it cannot be read.
std::string readFile(const std::string& path, const std::string& what);
// The diffuse RGB of one of Gazebo's stock material scripts (media/materials/scripts/gazebo.material:
// Gazebo/Grey, Gazebo/Orange, ...); false for any other name.
bool gazeboMaterialColor(const std::string& name, float rgb[3]);
std::shared_ptr<const std::vector<Triangle>> loadMesh(const std::string& path, const btVector3& scale);
// A <mesh> shape's file, resolved from `uri` (URDF's filename, SDF's <uri>), and its triangles at
// shape.mesh_scale: "" when loaded, else what went wrong, for the loader to report with its element.
std::string loadMeshShape(Shape& shape, const std::string& uri, const std::string& base_dir,
                          const UriResolver& resolver);
// A link's inertia as a physics engine can invert it: a negative moment is refused (LoadError naming
// `source` and `where`); a zero or impossible tensor is replaced by its first collision's, with a
// warning naming the link.
void checkInertia(const std::string& source, LinkSpec& link, const std::string& where,
                  std::vector<std::string>& warnings);
// The largest length (m), and mass (kg) or moment of inertia (kg m^2), that the loaders take. No
// world is 1000 km across and nothing in one outweighs 1e12 kg; far beyond them the physics' products
// lose the digits that matter or overflow: a wheel joint 1e8 m from its base turned the whole robot
// to NaN within 0.2 s, and a mass of 1e308 overflowed its weight (scripts/fuzz, 2026-12-02).
constexpr double kMaxLength = 1e6;
constexpr double kMaxMass = 1e12;
// Refuse (LoadError naming `source`, the link or joint and the element) any frame offset, shape
// extent, mass or moment beyond those limits. Every loader calls them on what it built.
void checkMagnitudes(const RobotSpec& spec, const std::string& source);
void checkMagnitudes(const WorldModel& model, const std::string& source);
void checkLength(const btVector3& v, const std::string& source, const std::string& what);
// `v` as a unit vector; false when no component reaches 1e-9 (a zero axis). It is scaled by its
// largest component first, so that an axis of "0 1e308 0" is the y axis and not an overflow to NaN.
bool normalizeDirection(btVector3& v);
// Every link's sensor plugins into spec.plugins, each with a copy of its <sensor> block; a plugin
// without a filename is refused, naming the link as `link_tag` + name + "'>" ("<link name='").
void addSensorPlugins(RobotSpec& spec, const std::string& link_tag);

}  // namespace mybot_gazebo_lite
