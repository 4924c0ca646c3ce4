// Our own URDF reader: urdfdom only logs vague errors, while we must name the
// file and element of every problem, and we need the <gazebo> blocks anyway.
#include "mybot_gazebo_lite/parsing.h"

#include <Eigen/Eigenvalues>
#include <tinyxml2.h>

#include <cmath>
#include <cstdio>
#include <set>

namespace mybot_gazebo_lite {

namespace {
using tinyxml2::XMLElement;

struct Ctx {
  std::string source;
  const UriResolver* resolver;
  [[noreturn]] void fail(const std::string& where, const std::string& msg) const {
    throw LoadError(source + ": " + where + ": " + msg);
  }
};

double attrDouble(const Ctx& c, const XMLElement* e, const char* name, const std::string& where, bool required,
                  double def = 0.0) {
  const char* v = e->Attribute(name);
  if (!v) {
    if (required) c.fail(where, std::string("<") + e->Name() + "> missing attribute '" + name + "'");
    return def;
  }
  char* end = nullptr;
  double d = std::strtod(v, &end);
  if (end == v || *end != '\0' || !std::isfinite(d))
    c.fail(where, std::string("<") + e->Name() + " " + name + "=\"" + v + "\"> is not a number");
  return d;
}

btTransform parseOrigin(const Ctx& c, const XMLElement* parent, const std::string& where) {
  const XMLElement* o = parent->FirstChildElement("origin");
  if (!o) return btTransform::getIdentity();
  btVector3 xyz(0, 0, 0), rpy(0, 0, 0);
  try {
    if (o->Attribute("xyz")) xyz = parseVec3(o->Attribute("xyz"), "<origin xyz>");
    if (o->Attribute("rpy")) rpy = parseVec3(o->Attribute("rpy"), "<origin rpy>");
  } catch (const LoadError& e) {
    c.fail(where, e.what());
  }
  return makeTransform(xyz, rpy);
}

Shape parseGeometry(const Ctx& c, const XMLElement* coll, const std::string& where) {
  const XMLElement* g = coll->FirstChildElement("geometry");
  if (!g || !g->FirstChildElement()) c.fail(where, "<collision> without <geometry>");
  const XMLElement* s = g->FirstChildElement();
  Shape shape;
  std::string t = s->Name();
  std::string w = where + " <" + t + ">";
  if (t == "box") {
    shape.type = Shape::BOX;
    if (!s->Attribute("size")) c.fail(w, "missing attribute 'size'");
    try {
      shape.size = parseVec3(s->Attribute("size"), "size");
    } catch (const LoadError& e) {
      c.fail(w, e.what());
    }
    if (shape.size.x() <= 0 || shape.size.y() <= 0 || shape.size.z() <= 0) c.fail(w, "box size must be positive");
  } else if (t == "cylinder") {
    shape.type = Shape::CYLINDER;
    shape.radius = attrDouble(c, s, "radius", w, true);
    shape.length = attrDouble(c, s, "length", w, true);
    if (shape.radius <= 0 || shape.length <= 0) c.fail(w, "cylinder radius and length must be positive");
  } else if (t == "sphere") {
    shape.type = Shape::SPHERE;
    shape.radius = attrDouble(c, s, "radius", w, true);
    if (shape.radius <= 0) c.fail(w, "sphere radius must be positive");
  } else if (t == "mesh") {
    shape.type = Shape::MESH;
    const char* fn = s->Attribute("filename");
    if (!fn) c.fail(w, "missing attribute 'filename'");
    if (s->Attribute("scale")) {
      try {
        shape.mesh_scale = parseVec3(s->Attribute("scale"), "scale");
      } catch (const LoadError& e) {
        c.fail(w, e.what());
      }
    }
    shape.mesh_path = (*c.resolver)(fn, "");
    if (shape.mesh_path.empty()) c.fail(w, std::string("mesh file '") + fn + "' not found");
    try {
      shape.triangles = loadMesh(shape.mesh_path, shape.mesh_scale);
    } catch (const LoadError& e) {
      c.fail(w, e.what());
    }
  } else {
    c.fail(w, "unsupported geometry");
  }
  shape.pose = parseOrigin(c, coll, where);
  return shape;
}

JointSpec::Type jointType(const Ctx& c, const std::string& t, const std::string& where) {
  if (t == "fixed") return JointSpec::FIXED;
  if (t == "revolute") return JointSpec::REVOLUTE;
  if (t == "continuous") return JointSpec::CONTINUOUS;
  if (t == "prismatic") return JointSpec::PRISMATIC;
  if (t == "floating") return JointSpec::FLOATING;
  if (t == "planar") return JointSpec::PLANAR;
  c.fail(where, "unknown joint type '" + t + "'");
}

// The solid body of the link's first collision (a sphere of 5 cm if it has none or a mesh):
// principal moments about its centre, for a mass whose inertia the URDF left unusable.
btVector3 solidInertia(const LinkSpec& link) {
  const double m = link.inertial.mass;
  if (!link.collisions.empty()) {
    const Shape& s = link.collisions.front();
    if (s.type == Shape::BOX) {
      const btVector3& d = s.size;
      return btVector3(d.y() * d.y() + d.z() * d.z(), d.x() * d.x() + d.z() * d.z(), d.x() * d.x() + d.y() * d.y()) *
             (m / 12.0);
    }
    if (s.type == Shape::CYLINDER) {
      const double side = m * (3 * s.radius * s.radius + s.length * s.length) / 12.0;
      return btVector3(side, side, m * s.radius * s.radius / 2.0);
    }
    if (s.type == Shape::SPHERE) return btVector3(1, 1, 1) * (0.4 * m * s.radius * s.radius);
  }
  return btVector3(1, 1, 1) * (0.4 * m * 0.05 * 0.05);
}

// A body with mass needs an inertia a physics engine can invert: moments that are not negative
// (refused: a sign error the author must see) and a positive definite tensor whose principal
// moments obey the triangle inequality (all zero, as many hand-written URDFs have, or
// impossible ones: corrected with a warning naming the link, as Gazebo's URDF import does
// rather than let the robot sit still or explode).
void checkInertia(const Ctx& c, LinkSpec& link, const std::string& where, std::vector<std::string>& warnings) {
  Inertial& in = link.inertial;
  const std::string w = where + " <inertia>";
  for (auto [name, v] : {std::pair<const char*, double>{"ixx", in.ixx}, {"iyy", in.iyy}, {"izz", in.izz}})
    if (v < 0) c.fail(w, std::string(name) + "=" + std::to_string(v) + " is negative");
  if (in.mass <= 0) return;
  Eigen::Matrix3d I;
  I << in.ixx, in.ixy, in.ixz, in.ixy, in.iyy, in.iyz, in.ixz, in.iyz, in.izz;
  const Eigen::Vector3d ev = Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d>(I).eigenvalues();  // ascending
  // Relative tolerances: a sensor link of a few grams has moments of 1e-9 and is fine.
  if (ev(2) > 0 && ev(0) > 1e-9 * ev(2) && ev(0) + ev(1) >= ev(2) * (1 - 1e-9)) return;
  const btVector3 d = solidInertia(link);
  char msg[512];
  std::snprintf(msg, sizeof msg,
                "%s: %s: ixx=%g iyy=%g izz=%g ixy=%g ixz=%g iyz=%g is not a physical inertia for mass %g (principal "
                "moments %g %g %g); using ixx=%g iyy=%g izz=%g from its collision shape",
                c.source.c_str(), w.c_str(), in.ixx, in.iyy, in.izz, in.ixy, in.ixz, in.iyz, in.mass, ev(0), ev(1),
                ev(2), d.x(), d.y(), d.z());
  warnings.push_back(msg);
  in.ixx = d.x();
  in.iyy = d.y();
  in.izz = d.z();
  in.ixy = in.ixz = in.iyz = 0;
}

bool textDouble(const XmlNode& n, double& out) {
  char* end = nullptr;
  double d = std::strtod(n.text.c_str(), &end);
  if (n.text.empty() || *end != '\0' || !std::isfinite(d)) return false;
  out = d;
  return true;
}
}  // namespace

RobotSpec parseUrdf(const std::string& xml, const std::string& source, const UriResolver& resolver) {
  Ctx c{source, &resolver};
  tinyxml2::XMLDocument doc;
  if (doc.Parse(xml.c_str(), xml.size()) != tinyxml2::XML_SUCCESS)
    c.fail("XML", std::string(doc.ErrorStr() ? doc.ErrorStr() : "parse error"));
  const XMLElement* robot = doc.FirstChildElement("robot");
  if (!robot) c.fail("document", "no <robot> element");
  RobotSpec spec;
  spec.source = source;
  spec.name = robot->Attribute("name") ? robot->Attribute("name") : "robot";

  std::set<std::string> names;
  for (const XMLElement* l = robot->FirstChildElement("link"); l; l = l->NextSiblingElement("link")) {
    LinkSpec link;
    if (!l->Attribute("name")) c.fail("<link>", "missing attribute 'name'");
    link.name = l->Attribute("name");
    std::string where = "link '" + link.name + "'";
    if (!names.insert(link.name).second) c.fail(where, "duplicate link name");
    if (const XMLElement* in = l->FirstChildElement("inertial")) {
      link.has_inertial = true;
      link.inertial.origin = parseOrigin(c, in, where + " <inertial>");
      const XMLElement* m = in->FirstChildElement("mass");
      if (!m) c.fail(where, "<inertial> without <mass>");
      link.inertial.mass = attrDouble(c, m, "value", where + " <inertial>", true);
      if (link.inertial.mass < 0) c.fail(where + " <mass>", "negative mass");
      const XMLElement* i = in->FirstChildElement("inertia");
      if (!i) c.fail(where, "<inertial> without <inertia>");
      std::string w = where + " <inertia>";
      link.inertial.ixx = attrDouble(c, i, "ixx", w, true);
      link.inertial.ixy = attrDouble(c, i, "ixy", w, false);
      link.inertial.ixz = attrDouble(c, i, "ixz", w, false);
      link.inertial.iyy = attrDouble(c, i, "iyy", w, true);
      link.inertial.iyz = attrDouble(c, i, "iyz", w, false);
      link.inertial.izz = attrDouble(c, i, "izz", w, true);
    }
    int k = 0;
    for (const XMLElement* col = l->FirstChildElement("collision"); col; col = col->NextSiblingElement("collision"))
      link.collisions.push_back(parseGeometry(c, col, where + " <collision> #" + std::to_string(k++)));
    if (link.has_inertial) checkInertia(c, link, where, spec.warnings);
    spec.links.push_back(std::move(link));
  }
  if (spec.links.empty()) c.fail("<robot>", "no <link> elements");

  std::set<std::string> children, jnames;
  for (const XMLElement* j = robot->FirstChildElement("joint"); j; j = j->NextSiblingElement("joint")) {
    JointSpec js;
    if (!j->Attribute("name")) c.fail("<joint>", "missing attribute 'name'");
    js.name = j->Attribute("name");
    std::string where = "joint '" + js.name + "'";
    if (!jnames.insert(js.name).second) c.fail(where, "duplicate joint name");
    if (!j->Attribute("type")) c.fail(where, "missing attribute 'type'");
    js.type = jointType(c, j->Attribute("type"), where);
    const XMLElement* p = j->FirstChildElement("parent");
    const XMLElement* ch = j->FirstChildElement("child");
    if (!p || !p->Attribute("link")) c.fail(where, "missing <parent link=...>");
    if (!ch || !ch->Attribute("link")) c.fail(where, "missing <child link=...>");
    js.parent = p->Attribute("link");
    js.child = ch->Attribute("link");
    if (!names.count(js.parent)) c.fail(where, "<parent link='" + js.parent + "'> is not a link");
    if (!names.count(js.child)) c.fail(where, "<child link='" + js.child + "'> is not a link");
    if (!children.insert(js.child).second) c.fail(where, "link '" + js.child + "' has two parents");
    js.origin = parseOrigin(c, j, where);
    if (const XMLElement* a = j->FirstChildElement("axis")) {
      if (a->Attribute("xyz")) {
        try {
          js.axis = parseVec3(a->Attribute("xyz"), "<axis xyz>");
        } catch (const LoadError& e) {
          c.fail(where, e.what());
        }
      }
      if (js.axis.length() < 1e-9) c.fail(where + " <axis>", "zero axis");
      js.axis.normalize();
    }
    if (const XMLElement* lim = j->FirstChildElement("limit")) {
      std::string w = where + " <limit>";
      js.effort = attrDouble(c, lim, "effort", w, js.type == JointSpec::REVOLUTE || js.type == JointSpec::PRISMATIC);
      js.velocity = attrDouble(c, lim, "velocity", w, js.type == JointSpec::REVOLUTE || js.type == JointSpec::PRISMATIC);
      if (js.type == JointSpec::REVOLUTE || js.type == JointSpec::PRISMATIC) {
        js.lower = attrDouble(c, lim, "lower", w, false);
        js.upper = attrDouble(c, lim, "upper", w, false);
        js.has_limits = js.upper > js.lower;
      }
      if (js.effort < 0) c.fail(w, "negative effort");
    } else if (js.type == JointSpec::REVOLUTE || js.type == JointSpec::PRISMATIC) {
      c.fail(where, "revolute/prismatic joint without <limit>");
    }
    if (const XMLElement* d = j->FirstChildElement("dynamics")) {
      js.damping = attrDouble(c, d, "damping", where + " <dynamics>", false);
      js.friction = attrDouble(c, d, "friction", where + " <dynamics>", false);
      if (js.damping < 0 || js.friction < 0) c.fail(where + " <dynamics>", "negative damping/friction");
    }
    if (js.type == JointSpec::FLOATING || js.type == JointSpec::PLANAR)
      c.fail(where, "floating/planar joints are not supported");
    spec.joints.push_back(js);
  }
  std::vector<std::string> roots;
  for (const auto& l : spec.links)
    if (!children.count(l.name)) roots.push_back(l.name);
  if (roots.size() != 1) c.fail("<robot>", "expected exactly one root link, found " + std::to_string(roots.size()));
  spec.root = roots[0];

  // <gazebo> extensions.
  for (const XMLElement* g = robot->FirstChildElement("gazebo"); g; g = g->NextSiblingElement("gazebo")) {
    std::string ref = g->Attribute("reference") ? g->Attribute("reference") : "";
    LinkSpec* link = nullptr;
    if (!ref.empty()) {
      for (auto& l : spec.links)
        if (l.name == ref) link = &l;
      if (!link && !jnames.count(ref)) c.fail("<gazebo reference='" + ref + "'>", "no such link or joint");
    }
    for (const XMLElement* e = g->FirstChildElement(); e; e = e->NextSiblingElement()) {
      std::string n = e->Name();
      std::string where = "<gazebo reference='" + ref + "'> <" + n + ">";
      if (link && (n == "mu1" || n == "mu2")) {
        XmlNode x = toXmlNode(e);
        double v;
        if (!textDouble(x, v) || v < 0) c.fail(where, "expected a non-negative number, got '" + x.text + "'");
        for (auto& s : link->collisions) (n == "mu1" ? s.mu1 : s.mu2) = v;
      } else if (link && n == "sensor") {
        link->sensors.push_back(toXmlNode(e));
      } else if (ref.empty() && n == "plugin") {
        PluginSpec ps;
        ps.xml = toXmlNode(e);
        ps.name = ps.xml.attr("name");
        ps.filename = ps.xml.attr("filename");
        if (ps.filename.empty()) c.fail("<gazebo> <plugin name='" + ps.name + "'>", "missing attribute 'filename'");
        spec.plugins.push_back(std::move(ps));
      }
    }
  }
  // Sensor plugins carry a copy of their <sensor> block.
  for (const auto& l : spec.links)
    for (const auto& s : l.sensors)
      for (const auto& p : s.children)
        if (p.name == "plugin") {
          PluginSpec ps;
          ps.xml = p;
          ps.name = p.attr("name");
          ps.filename = p.attr("filename");
          ps.reference = l.name;
          ps.has_sensor = true;
          ps.sensor = s;
          if (ps.filename.empty())
            c.fail("<gazebo reference='" + l.name + "'> <sensor> <plugin name='" + ps.name + "'>",
                   "missing attribute 'filename'");
          spec.plugins.push_back(std::move(ps));
        }
  return spec;
}

}  // namespace mybot_gazebo_lite
