#include "mybot_gazebo_lite/parsing.h"

#include <Eigen/Eigenvalues>
#include <assimp/Importer.hpp>
#include <assimp/postprocess.h>
#include <assimp/scene.h>
#include <tinyxml2.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <algorithm>
#include <fstream>
#include <mutex>
#include <sstream>
#include <dirent.h>
#include <sys/stat.h>

namespace mybot_gazebo_lite
{

namespace
{
bool fileExists(const std::string& p)
{
  struct stat st;
  return !p.empty() && stat(p.c_str(), &st) == 0;
}

std::vector<std::string> splitPathList(const char* env)
{
  std::vector<std::string> out;
  if (!env)
    return out;
  std::stringstream ss(env);
  std::string item;
  while (std::getline(ss, item, ':'))
    if (!item.empty())
      out.push_back(item);
  return out;
}
bool isDir(const std::string& p)
{
  struct stat st;
  return stat(p.c_str(), &st) == 0 && S_ISDIR(st.st_mode);
}

// The <name> of a package.xml, "" when there is none.
std::string packageName(const std::string& dir)
{
  tinyxml2::XMLDocument doc;
  if (doc.LoadFile((dir + "/package.xml").c_str()) != tinyxml2::XML_SUCCESS)
    return "";
  const tinyxml2::XMLElement* pkg = doc.FirstChildElement("package");
  const tinyxml2::XMLElement* name = pkg ? pkg->FirstChildElement("name") : nullptr;
  return name && name->GetText() ? name->GetText() : "";
}

// rospack's search, without ROS: the folders of ROS_PACKAGE_PATH and below them, a folder with a
// package.xml being a package (not searched further), CATKIN_IGNORE'd folders skipped.
std::string findPackageBelow(const std::string& dir, const std::string& pkg, int depth)
{
  if (fileExists(dir + "/package.xml"))
    return packageName(dir) == pkg ? dir : "";
  if (depth <= 0 || fileExists(dir + "/CATKIN_IGNORE"))
    return "";
  DIR* d = opendir(dir.c_str());
  if (!d)
    return "";
  std::vector<std::string> subdirs;
  while (dirent* e = readdir(d))
  {
    const std::string n = e->d_name;
    if (n.empty() || n[0] == '.')
      continue;
    if (isDir(dir + "/" + n))
      subdirs.push_back(dir + "/" + n);
  }
  closedir(d);
  std::sort(subdirs.begin(), subdirs.end());
  for (const auto& sd : subdirs)
    if (std::string found = findPackageBelow(sd, pkg, depth - 1); !found.empty())
      return found;
  return "";
}
}  // namespace

std::string findPackage(const std::string& pkg)
{
  static std::mutex mtx;
  static std::map<std::string, std::string> cache;
  std::lock_guard<std::mutex> lock(mtx);
  auto it = cache.find(pkg);
  if (it != cache.end())
    return it->second;
  std::string found;
  const std::vector<std::string> roots = splitPathList(std::getenv("ROS_PACKAGE_PATH"));
  // The usual layout first (<root>/<pkg>, as Debian installs them), then the full search.
  for (const auto& root : roots)
    if (packageName(root + "/" + pkg) == pkg)
    {
      found = root + "/" + pkg;
      break;
    }
  for (const auto& root : roots)
    if (found.empty() && !(found = findPackageBelow(root, pkg, 6)).empty())
      break;
  if (!found.empty())
    cache[pkg] = found;
  return found;
}

std::string defaultResolveUri(const std::string& uri, const std::string& base_dir)
{
  if (uri.rfind("file://", 0) == 0)
    return fileExists(uri.substr(7)) ? uri.substr(7) : "";
  if (uri.rfind("package://", 0) == 0)
  {
    std::string rest = uri.substr(10);
    auto slash = rest.find('/');
    std::string pkg = rest.substr(0, slash);
    std::string dir = findPackage(pkg);
    if (dir.empty())
      return "";
    std::string p = dir + (slash == std::string::npos ? "" : rest.substr(slash));
    return fileExists(p) ? p : "";
  }
  if (uri.rfind("model://", 0) == 0)
  {
    // Gazebo looks in GAZEBO_MODEL_PATH; we also accept <pkg>/models of every package path.
    std::string rest = uri.substr(8);
    std::vector<std::string> dirs = splitPathList(std::getenv("GAZEBO_MODEL_PATH"));
    if (!base_dir.empty())
    {
      dirs.push_back(base_dir + "/models");
      dirs.push_back(base_dir + "/../models");
    }
    std::string own = findPackage("mybot_gazebo_lite");
    if (!own.empty())
      dirs.push_back(own + "/models");
    for (const auto& pp : splitPathList(std::getenv("ROS_PACKAGE_PATH")))
      dirs.push_back(pp + "/../models");
    for (const auto& d : dirs)
    {
      std::string p = d + "/" + rest;
      if (fileExists(p))
        return p;
    }
    return "";
  }
  std::string p = (!uri.empty() && uri[0] != '/' && !base_dir.empty()) ? base_dir + "/" + uri : uri;
  return fileExists(p) ? p : "";
}

btVector3 parseVec3(const std::string& s, const std::string& what)
{
  std::istringstream is(s);
  double v[3];
  for (double& x : v)
    if (!(is >> x) || !std::isfinite(x))
      throw LoadError(what + ": expected 3 numbers, got '" + s + "'");
  std::string extra;
  if (is >> extra)
    throw LoadError(what + ": expected 3 numbers, got '" + s + "'");
  return btVector3(v[0], v[1], v[2]);
}

btTransform makeTransform(const btVector3& xyz, const btVector3& rpy)
{
  btQuaternion q;
  q.setEulerZYX(rpy.z(), rpy.y(), rpy.x());  // URDF/SDF fixed-axis roll, pitch, yaw
  return btTransform(q, xyz);
}

btTransform parsePose6(const std::string& s, const std::string& what)
{
  std::istringstream is(s);
  double v[6];
  for (double& x : v)
    if (!(is >> x) || !std::isfinite(x))
      throw LoadError(what + ": expected 6 numbers 'x y z roll pitch yaw', got '" + s + "'");
  return makeTransform(btVector3(v[0], v[1], v[2]), btVector3(v[3], v[4], v[5]));
}

bool gazeboMaterialColor(const std::string& name, float rgb[3])
{
  // Each script's diffuse colour (its ambient where it has no diffuse), from Gazebo classic's
  // media/materials/scripts/gazebo.material; the transparent ones drawn opaque.
  struct Entry
  {
    const char* name;
    float r, g, b;
  };
  static const Entry kStock[] = {
      {"Gazebo/Grey", 0.7f, 0.7f, 0.7f},
      {"Gazebo/DarkGrey", 0.175f, 0.175f, 0.175f},
      {"Gazebo/White", 1.0f, 1.0f, 1.0f},
      {"Gazebo/FlatBlack", 0.1f, 0.1f, 0.1f},
      {"Gazebo/Black", 0.0f, 0.0f, 0.0f},
      {"Gazebo/Red", 1.0f, 0.0f, 0.0f},
      {"Gazebo/RedBright", 0.87f, 0.26f, 0.07f},
      {"Gazebo/Green", 0.0f, 1.0f, 0.0f},
      {"Gazebo/Blue", 0.0f, 0.0f, 1.0f},
      {"Gazebo/SkyBlue", 0.0f, 0.0f, 1.0f},
      {"Gazebo/Yellow", 1.0f, 1.0f, 0.0f},
      {"Gazebo/ZincYellow", 0.9725f, 0.9529f, 0.2078f},
      {"Gazebo/Purple", 1.0f, 0.0f, 1.0f},
      {"Gazebo/Turquoise", 0.0f, 1.0f, 1.0f},
      {"Gazebo/Orange", 1.0f, 0.5088f, 0.0468f},
      {"Gazebo/Gold", 0.8f, 0.64869f, 0.120759f},
      {"Gazebo/GreyTransparent", 0.5f, 0.5f, 0.5f},
      {"Gazebo/GreenTransparent", 0.0f, 1.0f, 0.0f},
      {"Gazebo/BlueTransparent", 0.0f, 0.0f, 1.0f},
      {"Gazebo/YellowTransparent", 1.0f, 1.0f, 0.0f},
      {"Gazebo/OrangeTransparent", 1.0f, 0.44f, 0.0f},
      {"Gazebo/Pioneer2Body", 0.681193f, 0.000923f, 0.000923f},
  };
  // Element text as written: "\n  Gazebo/Orange\n".
  const size_t first = name.find_first_not_of(" \t\r\n"), last = name.find_last_not_of(" \t\r\n");
  const std::string bare = first == std::string::npos ? std::string() : name.substr(first, last - first + 1);
  for (const Entry& e : kStock)
    if (bare == e.name)
    {
      rgb[0] = e.r;
      rgb[1] = e.g;
      rgb[2] = e.b;
      return true;
    }
  return false;
}

std::string dirOf(const std::string& p)
{
  auto s = p.find_last_of('/');
  return s == std::string::npos ? "." : p.substr(0, s);
}

std::string readFile(const std::string& path, const std::string& what)
{
  std::ifstream f(path);
  if (!f)
    throw LoadError(what + ": cannot read '" + path + "'");
  std::stringstream ss;
  ss << f.rdbuf();
  return ss.str();
}

XmlNode toXmlNode(const tinyxml2::XMLElement* e)
{
  XmlNode n;
  n.name = e->Name();
  if (e->GetText())
    n.text = e->GetText();
  // Trim surrounding whitespace of text values.
  auto b = n.text.find_first_not_of(" \t\r\n");
  auto en = n.text.find_last_not_of(" \t\r\n");
  n.text = b == std::string::npos ? "" : n.text.substr(b, en - b + 1);
  for (auto* a = e->FirstAttribute(); a; a = a->Next())
    n.attributes[a->Name()] = a->Value();
  for (auto* c = e->FirstChildElement(); c; c = c->NextSiblingElement())
    n.children.push_back(toXmlNode(c));
  return n;
}

std::string loadMeshShape(Shape& shape, const std::string& uri, const std::string& base_dir,
                          const UriResolver& resolver)
{
  shape.mesh_path = resolver(uri, base_dir);
  if (shape.mesh_path.empty())
    return "mesh file '" + uri + "' not found";
  try
  {
    shape.triangles = loadMesh(shape.mesh_path, shape.mesh_scale);
  }
  catch (const LoadError& e)
  {
    return e.what();
  }
  return "";
}

std::shared_ptr<const std::vector<Triangle>> loadMesh(const std::string& path, const btVector3& scale)
{
  static std::mutex mtx;
  static std::map<std::string, std::shared_ptr<const std::vector<Triangle>>> cache;
  std::ostringstream key;
  key << path << '|' << scale.x() << ',' << scale.y() << ',' << scale.z();
  std::lock_guard<std::mutex> lock(mtx);
  auto it = cache.find(key.str());
  if (it != cache.end())
    return it->second;
  Assimp::Importer importer;
  const aiScene* scene =
      importer.ReadFile(path, aiProcess_Triangulate | aiProcess_JoinIdenticalVertices | aiProcess_PreTransformVertices);
  if (!scene || !scene->mRootNode)
    throw LoadError("mesh '" + path + "': " + importer.GetErrorString());
  auto tris = std::make_shared<std::vector<Triangle>>();
  for (unsigned m = 0; m < scene->mNumMeshes; ++m)
  {
    const aiMesh* mesh = scene->mMeshes[m];
    for (unsigned f = 0; f < mesh->mNumFaces; ++f)
    {
      const aiFace& face = mesh->mFaces[f];
      if (face.mNumIndices != 3)
        continue;
      btVector3 v[3];
      for (int k = 0; k < 3; ++k)
      {
        const aiVector3D& p = mesh->mVertices[face.mIndices[k]];
        v[k] = btVector3(p.x * scale.x(), p.y * scale.y(), p.z * scale.z());
      }
      tris->push_back({v[0], v[1], v[2]});
    }
  }
  if (tris->empty())
    throw LoadError("mesh '" + path + "': no triangles");
  cache[key.str()] = tris;
  return tris;
}

// The solid body of the link's first collision (a sphere of 5 cm if it has none or a mesh):
// principal moments about its centre, for a mass whose inertia the URDF left unusable.
static btVector3 solidInertia(const LinkSpec& link)
{
  const double m = link.inertial.mass;
  if (!link.collisions.empty())
  {
    const Shape& s = link.collisions.front();
    if (s.type == Shape::BOX)
    {
      const btVector3& d = s.size;
      return btVector3(d.y() * d.y() + d.z() * d.z(), d.x() * d.x() + d.z() * d.z(), d.x() * d.x() + d.y() * d.y()) *
             (m / 12.0);
    }
    if (s.type == Shape::CYLINDER)
    {
      const double side = m * (3 * s.radius * s.radius + s.length * s.length) / 12.0;
      return btVector3(side, side, m * s.radius * s.radius / 2.0);
    }
    if (s.type == Shape::SPHERE)
      return btVector3(1, 1, 1) * (0.4 * m * s.radius * s.radius);
  }
  return btVector3(1, 1, 1) * (0.4 * m * 0.05 * 0.05);
}

// A body with mass needs an inertia a physics engine can invert: moments that are not negative
// (refused: a sign error the author must see) and a positive definite tensor whose principal
// moments obey the triangle inequality (all zero, as many hand-written URDFs have, or
// impossible ones: corrected with a warning naming the link, as Gazebo's URDF import does
// rather than let the robot sit still or explode).
void checkInertia(const std::string& source, LinkSpec& link, const std::string& where,
                  std::vector<std::string>& warnings)
{
  Inertial& in = link.inertial;
  const std::string w = where + " <inertia>";
  for (auto [name, v] : {std::pair<const char*, double>{"ixx", in.ixx}, {"iyy", in.iyy}, {"izz", in.izz}})
    if (v < 0)
      throw LoadError(source + ": " + w + ": " + name + "=" + std::to_string(v) + " is negative");
  if (in.mass <= 0)
    return;
  Eigen::Matrix3d I;
  I << in.ixx, in.ixy, in.ixz, in.ixy, in.iyy, in.iyz, in.ixz, in.iyz, in.izz;
  const Eigen::Vector3d ev = Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d>(I).eigenvalues();  // ascending
  // Relative tolerances: a sensor link of a few grams has moments of 1e-9 and is fine.
  if (ev(2) > 0 && ev(0) > 1e-9 * ev(2) && ev(0) + ev(1) >= ev(2) * (1 - 1e-9))
    return;
  const btVector3 d = solidInertia(link);
  char msg[512];
  std::snprintf(msg, sizeof msg,
                "%s: %s: ixx=%g iyy=%g izz=%g ixy=%g ixz=%g iyz=%g is not a physical inertia for mass %g (principal "
                "moments %g %g %g); using ixx=%g iyy=%g izz=%g from its collision shape",
                source.c_str(), w.c_str(), in.ixx, in.iyy, in.izz, in.ixy, in.ixz, in.iyz, in.mass, ev(0), ev(1), ev(2),
                d.x(), d.y(), d.z());
  warnings.push_back(msg);
  in.ixx = d.x();
  in.iyy = d.y();
  in.izz = d.z();
  in.ixy = in.ixz = in.iyz = 0;
}

namespace
{
// Throws when |value| exceeds `max` (in `unit`).
void checkMagnitude(double value, double max, const char* unit, const std::string& source, const std::string& what)
{
  if (std::fabs(value) <= max)
    return;
  char msg[160];
  std::snprintf(msg, sizeof msg, " is %g %s, beyond the %g %s the simulator takes (a typo?)", value, unit, max, unit);
  throw LoadError(source + ": " + what + msg);
}

}  // namespace

void checkLength(const btVector3& v, const std::string& source, const std::string& what)
{
  for (int i = 0; i < 3; ++i)
    checkMagnitude(v[i], kMaxLength, "m", source, what);
}

namespace
{
void checkShapes(const std::vector<Shape>& shapes, const std::string& source, const std::string& where)
{
  for (const Shape& s : shapes)
  {
    const std::string w = where + " <collision" + (s.name.empty() ? "" : " name='" + s.name + "'") + ">";
    checkLength(s.pose.getOrigin(), source, w + "'s offset from its link");
    checkLength(s.size, source, w + " <box size>");
    checkMagnitude(s.radius, kMaxLength, "m", source, w + " radius");
    checkMagnitude(s.length, kMaxLength, "m", source, w + " length");
    // A mesh is scaled into its triangles: their extent is what the physics meets.
    if (s.triangles)
      for (const Triangle& t : *s.triangles)
        for (const btVector3& corner : {t.a, t.b, t.c})
          checkLength(corner, source, w + " <mesh> at its scale");
  }
}
}  // namespace

void checkMagnitudes(const RobotSpec& spec, const std::string& source)
{
  for (const LinkSpec& l : spec.links)
  {
    const std::string w = "<link name='" + l.name + "'>";
    // The shapes first: an inertia the loader made from a shape (checkInertia) tells of the shape.
    checkShapes(l.collisions, source, w);
    const Inertial& i = l.inertial;
    checkMagnitude(i.mass, kMaxMass, "kg", source, w + " <mass>");
    for (double moment : {i.ixx, i.ixy, i.ixz, i.iyy, i.iyz, i.izz})
      checkMagnitude(moment, kMaxMass, "kg m^2", source, w + " <inertia>");
    checkLength(i.origin.getOrigin(), source, w + " <inertial>'s offset from its link");
  }
  for (const JointSpec& j : spec.joints)
  {
    const std::string w = "<joint name='" + j.name + "'>";
    checkLength(j.origin.getOrigin(), source, w + "'s offset from its parent link");
    checkLength(j.pivot.getOrigin(), source, w + "'s offset from its child link");
  }
}

void checkMagnitudes(const WorldModel& model, const std::string& source)
{
  const std::string mw = "<model name='" + model.name + "'>";
  checkLength(model.pose.getOrigin(), source, mw + " <pose>");
  for (const WorldLink& l : model.links)
  {
    const std::string w = mw + " <link name='" + l.name + "'>";
    checkLength(l.pose.getOrigin(), source, w + " <pose>");
    checkMagnitude(l.mass, kMaxMass, "kg", source, w + " <mass>");
    checkShapes(l.shapes, source, w);
  }
}

bool normalizeDirection(btVector3& v)
{
  const btVector3 a = v.absolute();
  const double largest = a[a.maxAxis()];
  if (!(largest >= 1e-9))  // zero, or a denormal whose reciprocal overflows
    return false;
  v = btVector3(v.x() / largest, v.y() / largest, v.z() / largest);
  v.normalize();
  return true;
}

void addSensorPlugins(RobotSpec& spec, const std::string& link_tag)
{
  for (const auto& l : spec.links)
    for (const auto& s : l.sensors)
      for (const auto& p : s.children)
        if (p.name == "plugin")
        {
          PluginSpec ps;
          ps.xml = p;
          ps.name = p.attr("name");
          ps.filename = p.attr("filename");
          ps.reference = l.name;
          ps.has_sensor = true;
          ps.sensor = s;
          if (ps.filename.empty())
            throw LoadError(spec.source + ": " + link_tag + l.name + "'> <sensor> <plugin name='" + ps.name +
                            "'>: missing attribute 'filename'");
          spec.plugins.push_back(std::move(ps));
        }
}

}  // namespace mybot_gazebo_lite
