// Our own URDF reader: urdfdom only logs vague errors, while we must name the
// file and element of every problem, and we need the <gazebo> blocks anyway.
#include "mybot_gazebo_lite/parsing.h"

#include <tinyxml2.h>

#include <cmath>
#include <cstdio>
#include <set>

namespace mybot_gazebo_lite
{

namespace
{
using tinyxml2::XMLElement;

struct Ctx
{
  std::string source;
  const UriResolver* resolver;
  [[noreturn]] void fail(const std::string& where, const std::string& msg) const
  {
    throw LoadError(source + ": " + where + ": " + msg);
  }
};

double attrDouble(const Ctx& c, const XMLElement* e, const char* name, const std::string& where, bool required,
                  double def = 0.0)
{
  const char* v = e->Attribute(name);
  if (!v)
  {
    if (required)
      c.fail(where, std::string("<") + e->Name() + "> missing attribute '" + name + "'");
    return def;
  }
  char* end = nullptr;
  double d = std::strtod(v, &end);
  if (end == v || *end != '\0' || !std::isfinite(d))
    c.fail(where, std::string("<") + e->Name() + " " + name + "=\"" + v + "\"> is not a number");
  return d;
}

btTransform parseOrigin(const Ctx& c, const XMLElement* parent, const std::string& where)
{
  const XMLElement* o = parent->FirstChildElement("origin");
  if (!o)
    return btTransform::getIdentity();
  btVector3 xyz(0, 0, 0), rpy(0, 0, 0);
  try
  {
    if (o->Attribute("xyz"))
      xyz = parseVec3(o->Attribute("xyz"), "<origin xyz>");
    if (o->Attribute("rpy"))
      rpy = parseVec3(o->Attribute("rpy"), "<origin rpy>");
  }
  catch (const LoadError& e)
  {
    c.fail(where, e.what());
  }
  return makeTransform(xyz, rpy);
}

Shape parseGeometry(const Ctx& c, const XMLElement* coll, const std::string& where)
{
  const XMLElement* g = coll->FirstChildElement("geometry");
  if (!g || !g->FirstChildElement())
    c.fail(where, "<collision> without <geometry>");
  const XMLElement* s = g->FirstChildElement();
  Shape shape;
  std::string t = s->Name();
  std::string w = where + " <" + t + ">";
  if (t == "box")
  {
    shape.type = Shape::BOX;
    if (!s->Attribute("size"))
      c.fail(w, "missing attribute 'size'");
    try
    {
      shape.size = parseVec3(s->Attribute("size"), "size");
    }
    catch (const LoadError& e)
    {
      c.fail(w, e.what());
    }
    if (shape.size.x() <= 0 || shape.size.y() <= 0 || shape.size.z() <= 0)
      c.fail(w, "box size must be positive");
  }
  else if (t == "cylinder")
  {
    shape.type = Shape::CYLINDER;
    shape.radius = attrDouble(c, s, "radius", w, true);
    shape.length = attrDouble(c, s, "length", w, true);
    if (shape.radius <= 0 || shape.length <= 0)
      c.fail(w, "cylinder radius and length must be positive");
  }
  else if (t == "sphere")
  {
    shape.type = Shape::SPHERE;
    shape.radius = attrDouble(c, s, "radius", w, true);
    if (shape.radius <= 0)
      c.fail(w, "sphere radius must be positive");
  }
  else if (t == "mesh")
  {
    shape.type = Shape::MESH;
    const char* fn = s->Attribute("filename");
    if (!fn)
      c.fail(w, "missing attribute 'filename'");
    if (s->Attribute("scale"))
    {
      try
      {
        shape.mesh_scale = parseVec3(s->Attribute("scale"), "scale");
      }
      catch (const LoadError& e)
      {
        c.fail(w, e.what());
      }
    }
    if (const std::string error = loadMeshShape(shape, fn, "", *c.resolver); !error.empty())
      c.fail(w, error);
  }
  else
  {
    c.fail(w, "unsupported geometry");
  }
  shape.pose = parseOrigin(c, coll, where);
  return shape;
}

JointSpec::Type jointType(const Ctx& c, const std::string& t, const std::string& where)
{
  if (t == "fixed")
    return JointSpec::FIXED;
  if (t == "revolute")
    return JointSpec::REVOLUTE;
  if (t == "continuous")
    return JointSpec::CONTINUOUS;
  if (t == "prismatic")
    return JointSpec::PRISMATIC;
  if (t == "floating")
    return JointSpec::FLOATING;
  if (t == "planar")
    return JointSpec::PLANAR;
  c.fail(where, "unknown joint type '" + t + "'");
}

// sdformat's booleans: true/false or 1/0.
bool textBool(const std::string& v, bool& out)
{
  if (v == "true" || v == "1")
    return out = true, true;
  if (v == "false" || v == "0")
    return out = false, true;
  return false;
}

bool textDouble(const XmlNode& n, double& out)
{
  char* end = nullptr;
  double d = std::strtod(n.text.c_str(), &end);
  if (n.text.empty() || *end != '\0' || !std::isfinite(d))
    return false;
  out = d;
  return true;
}

// Below this contact stiffness (N/m) a robot of tens of kilograms would sink millimetres.
constexpr double kSoftContactKp = 1e5;

// The tags of <gazebo reference> (gazebo_ros's URDF import) and what gazebo_lite does with each.
struct GazeboTag
{
  enum Kind
  {
    PLUGIN,
    SENSOR,
    FRICTION,
    CONTACT,
    FDIR,
    COSMETIC,
    NOT_SIMULATED,
    UNKNOWN
  } kind;
  std::string name;
};

GazeboTag classifyGazeboTag(const std::string& n, bool on_link, bool has_ref)
{
  if (!has_ref && n == "plugin")
    return {GazeboTag::PLUGIN, n};
  if (on_link && n == "sensor")
    return {GazeboTag::SENSOR, n};
  if (on_link && (n == "mu1" || n == "mu2"))
    return {GazeboTag::FRICTION, n};
  if (on_link && (n == "kp" || n == "kd"))
    return {GazeboTag::CONTACT, n};
  if (on_link && n == "fdir1")
    return {GazeboTag::FDIR, n};
  // Looks, and what changes no motion (feedback, contact counts, laser retro-reflection).
  static const std::set<std::string> cosmetic = {
      "material", "visual",       "gui",         "scene",       "provideFeedback", "maxContacts", "laserRetro",
      "static",   "self_collide", "selfCollide", "enable_wind", "audio_source",    "projector"};
  if (cosmetic.count(n))
    return {GazeboTag::COSMETIC, n};
  static const std::set<std::string> not_simulated = {
      "minDepth",   "maxVel",         "gravity",  "turnGravityOff", "dampingFactor",   "implicitSpringDamper",
      "cfmDamping", "stopCfm",        "stopErp",  "fudgeFactor",    "springReference", "springStiffness",
      "collision",  "velocity_decay", "kinematic"};
  if (not_simulated.count(n))
    return {GazeboTag::NOT_SIMULATED, n};
  return {GazeboTag::UNKNOWN, n};
}

void applyGazeboTag(const Ctx& c, const GazeboTag& tag, const std::string& v, const std::string& where, LinkSpec* link,
                    std::vector<std::string>& warnings)
{
  if (tag.kind == GazeboTag::FDIR)
  {
    btVector3 d;
    try
    {
      d = parseVec3(v, "fdir1");
    }
    catch (const LoadError& e)
    {
      c.fail(where, e.what());
    }
    if (d.length() < 1e-9)
      c.fail(where, "zero direction");
    warnings.push_back(c.source + ": " + where + ": friction is isotropic in gazebo_lite (the smaller of mu1 and mu2 " +
                       "in every direction): Bullet's multibody contacts take one coefficient");
    return;
  }
  if (tag.kind == GazeboTag::NOT_SIMULATED)
  {
    // Their default values change nothing.
    if ((tag.name == "gravity" && (v == "true" || v == "1")) ||
        (tag.name == "turnGravityOff" && (v == "false" || v == "0")))
      return;
    warnings.push_back(c.source + ": " + where + " = '" + v +
                       "' is not simulated by gazebo_lite (see README: Gazebo tags)");
    return;
  }
  XmlNode n;
  n.text = v;
  double d;
  if (!textDouble(n, d) || d < 0)
    c.fail(where, "expected a non-negative number, got '" + v + "'");
  for (auto& s : link->collisions)
  {
    if (tag.name == "mu1")
      s.mu1 = d;
    if (tag.name == "mu2")
      s.mu2 = d;
    if (tag.name == "kp")
      s.kp = d;
    if (tag.name == "kd")
      s.kd = d;
  }
  // Contacts are rigid. Bullet can make them soft from kp and kd, but from the values robots
  // use in Gazebo (kp 1e6, kd 100) it made mybot's wheels slip (313 of 360 degrees in a turn in
  // place), while in ODE those values are as good as rigid (1e6 N/m sinks 5 kg by 50 um).
  // Only a kp soft enough to be meant as soft is worth a word.
  if (tag.name == "kp" && d < kSoftContactKp)
    warnings.push_back(c.source + ": " + where + " = " + v + " N/m: soft contacts are simulated rigid by gazebo_lite");
}
// One <link>: name (unique), inertial, collisions.
LinkSpec parseLink(const Ctx& c, const XMLElement* l, std::set<std::string>& names, std::vector<std::string>& warnings)
{
  LinkSpec link;
  if (!l->Attribute("name"))
    c.fail("<link>", "missing attribute 'name'");
  link.name = l->Attribute("name");
  std::string where = "link '" + link.name + "'";
  if (!names.insert(link.name).second)
    c.fail(where, "duplicate link name");
  if (const XMLElement* in = l->FirstChildElement("inertial"))
  {
    link.has_inertial = true;
    link.inertial.origin = parseOrigin(c, in, where + " <inertial>");
    const XMLElement* m = in->FirstChildElement("mass");
    if (!m)
      c.fail(where, "<inertial> without <mass>");
    link.inertial.mass = attrDouble(c, m, "value", where + " <inertial>", true);
    if (link.inertial.mass < 0)
      c.fail(where + " <mass>", "negative mass");
    const XMLElement* i = in->FirstChildElement("inertia");
    if (!i)
      c.fail(where, "<inertial> without <inertia>");
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
  if (link.has_inertial)
    checkInertia(c.source, link, where, warnings);
  return link;
}

// One <joint>: type, parent and child (links, one parent each), origin, axis, limits, dynamics.
JointSpec parseJoint(const Ctx& c, const XMLElement* j, const std::set<std::string>& links,
                     std::set<std::string>& children, std::set<std::string>& jnames)
{
  JointSpec js;
  if (!j->Attribute("name"))
    c.fail("<joint>", "missing attribute 'name'");
  js.name = j->Attribute("name");
  std::string where = "joint '" + js.name + "'";
  if (!jnames.insert(js.name).second)
    c.fail(where, "duplicate joint name");
  if (!j->Attribute("type"))
    c.fail(where, "missing attribute 'type'");
  js.type = jointType(c, j->Attribute("type"), where);
  const XMLElement* p = j->FirstChildElement("parent");
  const XMLElement* ch = j->FirstChildElement("child");
  if (!p || !p->Attribute("link"))
    c.fail(where, "missing <parent link=...>");
  if (!ch || !ch->Attribute("link"))
    c.fail(where, "missing <child link=...>");
  js.parent = p->Attribute("link");
  js.child = ch->Attribute("link");
  if (!links.count(js.parent))
    c.fail(where, "<parent link='" + js.parent + "'> is not a link");
  if (!links.count(js.child))
    c.fail(where, "<child link='" + js.child + "'> is not a link");
  if (!children.insert(js.child).second)
    c.fail(where, "link '" + js.child + "' has two parents");
  js.origin = parseOrigin(c, j, where);
  if (const XMLElement* a = j->FirstChildElement("axis"))
  {
    if (a->Attribute("xyz"))
    {
      try
      {
        js.axis = parseVec3(a->Attribute("xyz"), "<axis xyz>");
      }
      catch (const LoadError& e)
      {
        c.fail(where, e.what());
      }
    }
    if (!normalizeDirection(js.axis))
      c.fail(where + " <axis>", "zero axis");
  }
  if (const XMLElement* lim = j->FirstChildElement("limit"))
  {
    std::string w = where + " <limit>";
    js.has_effort = lim->Attribute("effort") != nullptr;
    js.has_velocity = lim->Attribute("velocity") != nullptr;
    js.effort = attrDouble(c, lim, "effort", w, js.type == JointSpec::REVOLUTE || js.type == JointSpec::PRISMATIC);
    js.velocity = attrDouble(c, lim, "velocity", w, js.type == JointSpec::REVOLUTE || js.type == JointSpec::PRISMATIC);
    if (js.type == JointSpec::REVOLUTE || js.type == JointSpec::PRISMATIC)
    {
      js.lower = attrDouble(c, lim, "lower", w, false);
      js.upper = attrDouble(c, lim, "upper", w, false);
      js.has_limits = js.upper > js.lower;
    }
    if (js.effort < 0)
      c.fail(w, "negative effort");
  }
  else if (js.type == JointSpec::REVOLUTE || js.type == JointSpec::PRISMATIC)
  {
    c.fail(where, "revolute/prismatic joint without <limit>");
  }
  if (const XMLElement* d = j->FirstChildElement("dynamics"))
  {
    js.damping = attrDouble(c, d, "damping", where + " <dynamics>", false);
    js.friction = attrDouble(c, d, "friction", where + " <dynamics>", false);
    if (js.damping < 0 || js.friction < 0)
      c.fail(where + " <dynamics>", "negative damping/friction");
  }
  if (const XMLElement* m = j->FirstChildElement("mimic"))
    js.mimic = m->Attribute("joint") ? m->Attribute("joint") : "";
  if (js.type == JointSpec::FLOATING || js.type == JointSpec::PLANAR)
    c.fail(where, "floating/planar joints are not supported");
  return js;
}

// One <transmission>: type, joint, hardware interfaces (also the pre-Indigo place), reduction.
TransmissionSpec parseTransmission(const Ctx& c, const XMLElement* t, const std::set<std::string>& jnames)
{
  TransmissionSpec ts;
  ts.name = t->Attribute("name") ? t->Attribute("name") : "";
  const std::string where = "<transmission name='" + ts.name + "'>";
  // <type> element (ROS Indigo on) or type="..." attribute (the older pr2 form).
  if (const XMLElement* ty = t->FirstChildElement("type"))
    ts.type = ty->GetText() ? ty->GetText() : "";
  else if (t->Attribute("type"))
    ts.type = t->Attribute("type");
  const XMLElement* j = t->FirstChildElement("joint");
  if (!j || !j->Attribute("name"))
    c.fail(where, "missing <joint name=...>");
  ts.joint = j->Attribute("name");
  if (!jnames.count(ts.joint))
    c.fail(where + " <joint name='" + ts.joint + "'>", "no such joint");
  for (const XMLElement* hi = j->FirstChildElement("hardwareInterface"); hi;
       hi = hi->NextSiblingElement("hardwareInterface"))
    if (hi->GetText())
      ts.interfaces.push_back(toXmlNode(hi).text);
  const XMLElement* a = t->FirstChildElement("actuator");
  if (a && a->Attribute("name"))
    ts.actuator = a->Attribute("name");
  // Before ROS Indigo the interface sat in <actuator>; gazebo_ros_control still reads it there.
  if (ts.interfaces.empty() && a)
    for (const XMLElement* hi = a->FirstChildElement("hardwareInterface"); hi;
         hi = hi->NextSiblingElement("hardwareInterface"))
      if (hi->GetText())
        ts.interfaces.push_back(toXmlNode(hi).text);
  const XMLElement* mr = a ? a->FirstChildElement("mechanicalReduction") : nullptr;
  if (!mr)
    mr = t->FirstChildElement("mechanicalReduction");
  if (mr)
  {
    XmlNode n = toXmlNode(mr);
    if (!textDouble(n, ts.reduction) || ts.reduction == 0)
      c.fail(where + " <mechanicalReduction>", "expected a non-zero number, got '" + n.text + "'");
  }
  return ts;
}

// The <gazebo> extensions: plugins, sensors and the tags of links, joints and the model; then the
// sensor plugins, each with a copy of its <sensor> block.
void parseGazeboExtensions(const Ctx& c, const XMLElement* robot, const std::set<std::string>& jnames, RobotSpec& spec)
{
  const std::string& source = c.source;
  for (const XMLElement* g = robot->FirstChildElement("gazebo"); g; g = g->NextSiblingElement("gazebo"))
  {
    std::string ref = g->Attribute("reference") ? g->Attribute("reference") : "";
    LinkSpec* link = nullptr;
    if (!ref.empty())
    {
      for (auto& l : spec.links)
        if (l.name == ref)
          link = &l;
      if (!link && !jnames.count(ref))
        c.fail("<gazebo reference='" + ref + "'>", "no such link or joint");
    }
    for (const XMLElement* e = g->FirstChildElement(); e; e = e->NextSiblingElement())
    {
      const XmlNode x = toXmlNode(e);
      const std::string where =
          "<gazebo" + (ref.empty() ? std::string() : " reference='" + ref + "'") + "> <" + x.name + ">";
      const GazeboTag tag = classifyGazeboTag(x.name, link != nullptr, !ref.empty());
      if (tag.kind == GazeboTag::PLUGIN)
      {
        PluginSpec ps;
        ps.xml = x;
        ps.name = ps.xml.attr("name");
        ps.filename = ps.xml.attr("filename");
        if (ps.filename.empty())
          c.fail("<gazebo> <plugin name='" + ps.name + "'>", "missing attribute 'filename'");
        spec.plugins.push_back(std::move(ps));
      }
      else if (tag.kind == GazeboTag::SENSOR)
      {
        link->sensors.push_back(x);
      }
      else if (tag.kind == GazeboTag::COSMETIC && x.name == "material" && link)
      {
        // The colour the cameras draw the link in; any other script renders grey.
        if (!gazeboMaterialColor(x.text, link->color))
          spec.warnings.push_back(source + ": " + where + " '" + x.text +
                                  "': not one of Gazebo's stock colours, drawn grey by the cameras");
      }
      else if ((x.name == "disableFixedJointLumping" || x.name == "preserveFixedJoint") && !link && !ref.empty())
      {
        // Gazebo keeps such a fixed joint, and its child a link of its own (a wrist's force-torque
        // sensor sits on one). On a movable joint it changes nothing.
        const std::string v = x.text.empty() ? x.attr("value") : x.text;
        bool keep = false;
        if (!textBool(v, keep))
          c.fail(where, "expected true or false, got '" + v + "'");
        for (auto& j : spec.joints)
          if (j.name == ref && j.type == JointSpec::FIXED)
            j.keep_fixed = keep;
      }
      else if (tag.kind == GazeboTag::UNKNOWN)
      {
        spec.warnings.push_back(source + ": " + where + ": unknown tag ignored (gazebo_lite reads the tags listed in " +
                                "mybot_gazebo_lite/README.md)");
      }
      else if (tag.kind != GazeboTag::COSMETIC)
      {
        // Gazebo takes the value as element text or as a value="..." attribute.
        const std::string v = x.text.empty() ? x.attr("value") : x.text;
        applyGazeboTag(c, tag, v, where, link, spec.warnings);
      }
    }
  }
  addSensorPlugins(spec, "<gazebo reference='");
}

// A joint's <mimic> no mimic joint plugin holds: Gazebo classic ignores <mimic>, and so does
// gazebo_lite, so the joint moves on its own (a gripper's second finger hangs free). Said once.
void warnUnheldMimics(RobotSpec& spec)
{
  std::set<std::string> held;
  for (const PluginSpec& p : spec.plugins)
    if (p.filename.find("mimic_joint_plugin") != std::string::npos)
      if (const XmlNode* m = p.xml.child("mimicJoint"))
        held.insert(m->text);
  for (const JointSpec& j : spec.joints)
    if (!j.mimic.empty() && !held.count(j.name))
      spec.warnings.push_back(
          spec.source + ": joint '" + j.name + "' <mimic joint='" + j.mimic +
          "'>: Gazebo classic ignores <mimic>, and so does gazebo_lite: the joint moves on its own " +
          "unless a mimic joint plugin (libroboticsgroup_gazebo_mimic_joint_plugin.so, see " +
          "mybot_gazebo_lite/README.md) holds it");
}

// The one link that is no joint's child.
std::string findRoot(const Ctx& c, const RobotSpec& spec, const std::set<std::string>& children)
{
  std::vector<std::string> roots;
  for (const auto& l : spec.links)
    if (!children.count(l.name))
      roots.push_back(l.name);
  if (roots.size() != 1)
    c.fail("<robot>", "expected exactly one root link, found " + std::to_string(roots.size()));
  return roots[0];
}
}  // namespace

RobotSpec parseUrdf(const std::string& xml, const std::string& source, const UriResolver& resolver)
{
  Ctx c{source, &resolver};
  tinyxml2::XMLDocument doc;
  if (doc.Parse(xml.c_str(), xml.size()) != tinyxml2::XML_SUCCESS)
    c.fail("XML", std::string(doc.ErrorStr() ? doc.ErrorStr() : "parse error"));
  const XMLElement* robot = doc.FirstChildElement("robot");
  if (!robot)
    c.fail("document", "no <robot> element");
  RobotSpec spec;
  spec.source = source;
  spec.name = robot->Attribute("name") ? robot->Attribute("name") : "robot";

  std::set<std::string> links, children, joints;
  for (const XMLElement* l = robot->FirstChildElement("link"); l; l = l->NextSiblingElement("link"))
    spec.links.push_back(parseLink(c, l, links, spec.warnings));
  if (spec.links.empty())
    c.fail("<robot>", "no <link> elements");
  for (const XMLElement* j = robot->FirstChildElement("joint"); j; j = j->NextSiblingElement("joint"))
    spec.joints.push_back(parseJoint(c, j, links, children, joints));
  for (const XMLElement* t = robot->FirstChildElement("transmission"); t; t = t->NextSiblingElement("transmission"))
    spec.transmissions.push_back(parseTransmission(c, t, joints));
  spec.root = findRoot(c, spec, children);
  parseGazeboExtensions(c, robot, joints, spec);
  warnUnheldMimics(spec);
  checkMagnitudes(spec, source);
  return spec;
}

}  // namespace mybot_gazebo_lite
