// The SDF subset gazebo_lite loads: Gazebo classic .world files, model files (<include>, model://)
// and the documents spawn_sdf_model takes, with SDFormat 1.7's pose frames (sdf_frames.cpp).
#include "mybot_gazebo_lite/parsing.h"
#include "mybot_gazebo_lite/sdf_frames.h"

#include <tinyxml2.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <memory>
#include <set>
#include <sstream>

namespace mybot_gazebo_lite
{

namespace
{
using tinyxml2::XMLElement;

struct SdfCtx
{
  std::string source, base_dir;
  const UriResolver* resolver;
  std::vector<std::string> included_from;  // the model files that included this one, outermost first
  [[noreturn]] void fail(const std::string& where, const std::string& msg) const
  {
    // A model file's model is at the top: its `where` starts " <model".
    throw LoadError(source + ": " + (where.rfind(' ', 0) == 0 ? where.substr(1) : where) + ": " + msg);
  }
  void parse(tinyxml2::XMLDocument& doc, const std::string& xml) const
  {
    if (doc.Parse(xml.c_str(), xml.size()) != tinyxml2::XML_SUCCESS)
      fail("XML", doc.ErrorStr() ? doc.ErrorStr() : "parse error");
  }
  std::string text(const XMLElement* e, const char* child, const std::string& where, bool required,
                   const std::string& def = "") const
  {
    const XMLElement* c = e->FirstChildElement(child);
    if (!c || !c->GetText())
    {
      if (required)
        fail(where, std::string("missing <") + child + ">");
      return def;
    }
    return c->GetText();
  }
  double number(const XMLElement* e, const char* child, const std::string& where, bool required, double def = 0) const
  {
    std::string t = text(e, child, where, required);
    if (t.empty())
      return def;
    char* end = nullptr;
    double d = std::strtod(t.c_str(), &end);
    while (end && (*end == ' ' || *end == '\n' || *end == '\t' || *end == '\r'))
      ++end;
    if (*end != '\0' || !std::isfinite(d))
      fail(where + " <" + child + ">", "not a number: '" + t + "'");
    return d;
  }
  // An element's <pose>: "x y z roll pitch yaw" in radians, or as SDF 1.9 allows, in degrees
  // (degrees="true") or with a quaternion (rotation_format="quat_xyzw": "x y z qx qy qz qw").
  // Where it is relative to is relativeTo's business.
  btTransform pose(const XMLElement* e, const std::string& where) const
  {
    const XMLElement* p = e->FirstChildElement("pose");
    if (!p || !p->GetText())
      return btTransform::getIdentity();
    const std::string format = p->Attribute("rotation_format") ? p->Attribute("rotation_format") : "euler_rpy";
    bool degrees = false;
    if (p->Attribute("degrees") && p->QueryBoolAttribute("degrees", &degrees) != tinyxml2::XML_SUCCESS)
      fail(where + " <pose degrees>", std::string("expected true or false, got '") + p->Attribute("degrees") + "'");
    if (format == "quat_xyzw")
    {
      std::istringstream is(p->GetText());
      double v[7];
      for (double& x : v)
        if (!(is >> x) || !std::isfinite(x))
          fail(where + " <pose>", std::string("expected 7 numbers 'x y z qx qy qz qw', got '") + p->GetText() + "'");
      btQuaternion q(v[3], v[4], v[5], v[6]);
      if (q.length() < 1e-9)
        fail(where + " <pose>", "a zero quaternion is no rotation");
      return btTransform(q.normalized(), btVector3(v[0], v[1], v[2]));
    }
    if (format != "euler_rpy")
      fail(where + " <pose rotation_format>", "'" + format + "': euler_rpy or quat_xyzw");
    btTransform t;
    try
    {
      t = parsePose6(p->GetText(), "<pose>");
    }
    catch (const LoadError& ex)
    {
      fail(where, ex.what());
    }
    if (!degrees)
      return t;
    std::istringstream is(p->GetText());  // six numbers: parsePose6 checked them
    double v[6];
    for (double& x : v)
      is >> x;
    const double k = M_PI / 180.0;
    return makeTransform(t.getOrigin(), btVector3(v[3] * k, v[4] * k, v[5] * k));
  }
  // The frame an element's <pose> is written in (SDF 1.7's relative_to), "" for its default.
  static std::string relativeTo(const XMLElement* e)
  {
    const XMLElement* p = e->FirstChildElement("pose");
    const char* r = p ? p->Attribute("relative_to") : nullptr;
    return r ? r : "";
  }
};

Shape parseSdfGeometry(const SdfCtx& c, const XMLElement* g, const std::string& where)
{
  const XMLElement* s = g ? g->FirstChildElement() : nullptr;
  if (!s)
    c.fail(where, "missing <geometry> content");
  Shape shape;
  std::string t = s->Name();
  std::string w = where + " <" + t + ">";
  if (t == "box")
  {
    shape.type = Shape::BOX;
    try
    {
      shape.size = parseVec3(c.text(s, "size", w, true), "<size>");
    }
    catch (const LoadError& e)
    {
      c.fail(w, e.what());
    }
    if (shape.size.x() <= 0 || shape.size.y() <= 0 || shape.size.z() <= 0)
      c.fail(w, "size must be positive");
  }
  else if (t == "cylinder")
  {
    shape.type = Shape::CYLINDER;
    shape.radius = c.number(s, "radius", w, true);
    shape.length = c.number(s, "length", w, true);
    if (shape.radius <= 0 || shape.length <= 0)
      c.fail(w, "radius and length must be positive");
  }
  else if (t == "sphere")
  {
    shape.type = Shape::SPHERE;
    shape.radius = c.number(s, "radius", w, true);
    if (shape.radius <= 0)
      c.fail(w, "radius must be positive");
  }
  else if (t == "plane")
  {
    shape.type = Shape::PLANE;
    std::string n = c.text(s, "normal", w, false, "0 0 1");
    try
    {
      shape.normal = parseVec3(n, "<normal>");
    }
    catch (const LoadError& e)
    {
      c.fail(w, e.what());
    }
    if (!normalizeDirection(shape.normal))
      c.fail(w, "zero normal");
  }
  else if (t == "mesh")
  {
    shape.type = Shape::MESH;
    std::string uri = c.text(s, "uri", w, true);
    std::string sc = c.text(s, "scale", w, false, "1 1 1");
    try
    {
      shape.mesh_scale = parseVec3(sc, "<scale>");
    }
    catch (const LoadError& e)
    {
      c.fail(w, e.what());
    }
    if (const std::string error = loadMeshShape(shape, uri, c.base_dir, *c.resolver); !error.empty())
      c.fail(w, error);
  }
  else
  {
    c.fail(w, "unsupported geometry");
  }
  return shape;
}

std::string nameOf(const XMLElement* e)
{
  return e->Attribute("name") ? e->Attribute("name") : "";
}

// A model file's own model has nothing to be placed relative to (SDF 1.7: its <pose>'s relative_to
// is left empty); in a world of one model, only the world.
void checkOutermostPose(const SdfCtx& c, const XMLElement* m, const std::string& where, bool in_world)
{
  const std::string rel = SdfCtx::relativeTo(m);
  if (!rel.empty() && !(in_world && rel == "world"))
    c.fail(where + " <model name='" + nameOf(m) + "'> <pose relative_to>",
           "'" + rel + "': no frame of that name " + (in_world ? "in this world" : "outside a world"));
}

// A model file found by <include><uri>: model://NAME from GAZEBO_MODEL_PATH and the package
// model paths (its model.config's newest <sdf>), or a file.
struct IncludedModel
{
  SdfCtx ctx;                                  // the included file's, for its errors
  std::shared_ptr<tinyxml2::XMLDocument> doc;  // keeps `model` alive
  const XMLElement* model = nullptr;
};

IncludedModel loadInclude(const SdfCtx& c, const std::string& uri, const std::string& where)
{
  std::string dir = (*c.resolver)(uri, c.base_dir);
  if (dir.empty())
    c.fail(where, "model not found in GAZEBO_MODEL_PATH or package model paths");
  std::string sdf_file = dir + "/model.sdf";
  std::ifstream cfg(dir + "/model.config");
  if (cfg)
  {
    tinyxml2::XMLDocument doc;
    std::stringstream ss;
    ss << cfg.rdbuf();
    // Several <sdf version="..."> files: the newest, as Gazebo picks.
    std::pair<int, int> best{-1, -1};
    if (doc.Parse(ss.str().c_str()) == tinyxml2::XML_SUCCESS)
      if (const XMLElement* mdl = doc.FirstChildElement("model"))
        for (const XMLElement* s = mdl->FirstChildElement("sdf"); s; s = s->NextSiblingElement("sdf"))
        {
          if (!s->GetText())
            continue;
          std::pair<int, int> v{0, 0};
          if (const char* ver = s->Attribute("version"))
            std::sscanf(ver, "%d.%d", &v.first, &v.second);
          if (v > best)
          {
            best = v;
            sdf_file = dir + "/" + s->GetText();
          }
        }
  }
  // A model that includes itself, however far down, would be read for ever: the same file (by its
  // canonical path: a symlinked model folder is the same model) met twice on the way down, or a
  // chain of includes deeper than any model nests.
  std::vector<std::string> chain = c.included_from;
  chain.push_back(c.source);
  std::error_code ec;
  const auto same = [&](const std::string& a)
  { return std::filesystem::weakly_canonical(a, ec) == std::filesystem::weakly_canonical(sdf_file, ec); };
  if (const auto first = std::find_if(chain.begin(), chain.end(), same); first != chain.end())
  {
    std::string loop;
    for (auto it = first; it != chain.end(); ++it)
      loop += *it + " -> ";
    c.fail(where, "the model includes itself: " + loop + sdf_file);
  }
  constexpr size_t kMaxIncludeDepth = 64;
  if (chain.size() > kMaxIncludeDepth)
    c.fail(where, "includes nest more than " + std::to_string(kMaxIncludeDepth) + " deep");
  IncludedModel out{SdfCtx{sdf_file, dir, c.resolver, chain}, std::make_shared<tinyxml2::XMLDocument>(), nullptr};
  std::string xml = readFile(sdf_file, c.source + ": " + where);
  if (out.doc->Parse(xml.c_str(), xml.size()) != tinyxml2::XML_SUCCESS)
    throw LoadError(sdf_file + ": XML: " + (out.doc->ErrorStr() ? out.doc->ErrorStr() : "parse error"));
  const XMLElement* sdf = out.doc->FirstChildElement("sdf");
  out.model = sdf ? sdf->FirstChildElement("model") : nullptr;
  if (!out.model)
    throw LoadError(sdf_file + ": no <sdf><model>");
  checkOutermostPose(out.ctx, out.model, "", false);
  return out;
}

// A model in a model, written in it (<model>) or included (<include>): one more scope, its links,
// joints and plugins named "nested::link" as Gazebo scopes them.
struct NestedModel
{
  const XMLElement* element = nullptr;  // the <model> or <include> in the outer model
  IncludedModel file;                   // the model itself, with the file it is in
  std::string name;
  std::string where_in;                           // the outer model's, for parseSdfModel ("" for an included file's)
  std::string where;                              // the nested model's own
  std::string pose_where;                         // where its <pose> in the outer model is written
  btTransform pose = btTransform::getIdentity();  // as written in the outer model's scope
  std::string relative_to;
};

std::vector<NestedModel> nestedModels(const SdfCtx& c, const XMLElement* m, const std::string& where)
{
  std::vector<NestedModel> out;
  for (const XMLElement* e = m->FirstChildElement(); e; e = e->NextSiblingElement())
  {
    const std::string kind = e->Name();
    NestedModel n;
    n.element = e;
    if (kind == "model")
    {
      n.file = {c, nullptr, e};
      n.name = nameOf(e);
      n.where_in = where;
      n.where = n.pose_where = where + " <model name='" + n.name + "'>";
      n.pose = c.pose(e, n.where);
      n.relative_to = SdfCtx::relativeTo(e);
    }
    else if (kind == "include")
    {
      const std::string uri = c.text(e, "uri", where + " <include>", true);
      n.pose_where = where + " <include> <uri>" + uri + "</uri>";
      if (uri == "model://sun" || uri == "model://ground_plane")
        c.fail(n.pose_where, "the sun and the ground plane belong in the world, not in a model");
      n.file = loadInclude(c, uri, n.pose_where);
      const XMLElement* nm = e->FirstChildElement("name");
      n.name = nm && nm->GetText() ? nm->GetText() : nameOf(n.file.model);
      n.where = " <model name='" + nameOf(n.file.model) + "'>";
      // The <include>'s <pose> places it, else the model file's own.
      n.pose = e->FirstChildElement("pose") ? c.pose(e, n.pose_where) : n.file.ctx.pose(n.file.model, n.where);
      n.relative_to = SdfCtx::relativeTo(e);
    }
    else
    {
      continue;
    }
    if (n.name.empty())
      c.fail(n.pose_where, "a nested model without a name");
    out.push_back(std::move(n));
  }
  return out;
}

// A model's frames (SDF 1.7, SdfFrames): its links, joints, nested (and included) models and
// <frame>s, in the model's scope. SDF 1.6 files come out as before: links and nested models relative to the model,
// joints to their child links.
struct ModelFrames
{
  SdfFrames frames;
  std::map<const XMLElement*, int> of;  // each link's, joint's, nested model's and <frame>'s frame
  // An element's <pose> (written relative_to a frame of the model, or by default to frame
  // `fallback`) in frame `in`.
  btTransform poseIn(const SdfCtx& c, const XMLElement* e, int fallback, int in, const std::string& where) const
  {
    return frames.express(c.pose(e, where), SdfCtx::relativeTo(e), fallback, in, where + " <pose relative_to>");
  }
};

ModelFrames modelFrames(const SdfCtx& c, const XMLElement* m, const std::string& where,
                        const std::vector<NestedModel>& nested)
{
  ModelFrames mf{SdfFrames(c.source, "__model__"), {}};
  std::map<std::string, int> links;
  for (const XMLElement* l = m->FirstChildElement("link"); l; l = l->NextSiblingElement("link"))
  {
    const std::string lw = where + " <link name='" + nameOf(l) + "'>";
    const int id = mf.frames.add(nameOf(l), SdfCtx::relativeTo(l), SdfFrames::kScope, c.pose(l, lw), lw);
    mf.of[l] = id;
    links.emplace(nameOf(l), id);
  }
  for (const NestedModel& n : nested)
    mf.of[n.element] = mf.frames.add(n.name, n.relative_to, SdfFrames::kScope, n.pose, n.pose_where);
  std::vector<std::pair<std::string, std::string>> attached;  // (frame, where)
  for (const XMLElement* f = m->FirstChildElement("frame"); f; f = f->NextSiblingElement("frame"))
  {
    const std::string fw = where + " <frame name='" + nameOf(f) + "'>";
    if (nameOf(f).empty())
      c.fail(fw, "missing attribute 'name'");
    // Its pose is relative to what it is attached to unless it says otherwise.
    const std::string to = f->Attribute("attached_to") ? f->Attribute("attached_to") : "";
    const std::string rel = SdfCtx::relativeTo(f);
    mf.of[f] = mf.frames.add(nameOf(f), rel.empty() ? to : rel, SdfFrames::kScope, c.pose(f, fw), fw);
    if (!to.empty())
      attached.emplace_back(to, fw + " attached_to");
  }
  for (const XMLElement* j = m->FirstChildElement("joint"); j; j = j->NextSiblingElement("joint"))
  {
    const std::string jw = where + " <joint name='" + nameOf(j) + "'>";
    const XMLElement* child = j->FirstChildElement("child");
    auto it = links.find(child && child->GetText() ? child->GetText() : "");
    // A joint's frame is its child link's by default (a missing child is refused by the robot).
    mf.of[j] = mf.frames.add(nameOf(j), SdfCtx::relativeTo(j), it == links.end() ? SdfFrames::kScope : it->second,
                             c.pose(j, jw), jw);
  }
  for (const auto& [to, fw] : attached)
    mf.frames.find(to, fw);
  return mf;
}

// A link's <collision>s: shapes in the link's frame (`link`, of the model's `mf`), with Gazebo's
// <ode> friction.
std::vector<Shape> sdfCollisions(const SdfCtx& c, const XMLElement* l, const std::string& lw, const ModelFrames& mf)
{
  const int link = mf.of.at(l);
  std::vector<Shape> out;
  for (const XMLElement* col = l->FirstChildElement("collision"); col; col = col->NextSiblingElement("collision"))
  {
    std::string cw = lw + " <collision name='" + (col->Attribute("name") ? col->Attribute("name") : "") + "'>";
    Shape s = parseSdfGeometry(c, col->FirstChildElement("geometry"), cw);
    s.pose = mf.poseIn(c, col, link, link, cw);
    s.name = col->Attribute("name") ? col->Attribute("name") : "collision";
    if (const XMLElement* surf = col->FirstChildElement("surface"))
      if (const XMLElement* fr = surf->FirstChildElement("friction"))
        if (const XMLElement* ode = fr->FirstChildElement("ode"))
        {
          s.mu1 = c.number(ode, "mu", cw + " <friction><ode>", false, 1.0);
          s.mu2 = c.number(ode, "mu2", cw + " <friction><ode>", false, s.mu1);
        }
    out.push_back(s);
  }
  return out;
}

// The colour of a link's first <visual><material> that has one (diffuse, else ambient, else one
// of Gazebo's stock scripts), for the cameras; false when none has.
bool sdfVisualColor(const SdfCtx& c, const XMLElement* l, const std::string& lw, float color[3])
{
  for (const XMLElement* vis = l->FirstChildElement("visual"); vis; vis = vis->NextSiblingElement("visual"))
  {
    const XMLElement* mat = vis->FirstChildElement("material");
    if (!mat)
      continue;
    const XMLElement* col = mat->FirstChildElement("diffuse");
    if (!col)
      col = mat->FirstChildElement("ambient");
    if (!col || !col->GetText())
    {
      // <script><name>Gazebo/Orange</name>: one of the stock scripts.
      const XMLElement* script = mat->FirstChildElement("script");
      const XMLElement* name = script ? script->FirstChildElement("name") : nullptr;
      if (name && name->GetText() && gazeboMaterialColor(name->GetText(), color))
        return true;
      continue;
    }
    std::string vw = lw + " <visual><material><" + col->Name() + ">";
    std::istringstream ss(col->GetText());
    double rgb[3];
    if (!(ss >> rgb[0] >> rgb[1] >> rgb[2]))
      c.fail(vw, std::string("expected 'r g b [a]', got '") + col->GetText() + "'");
    for (int i = 0; i < 3; ++i)
      color[i] = static_cast<float>(std::clamp(rgb[i], 0.0, 1.0));
    return true;
  }
  return false;
}

// "x y z roll pitch yaw", to the last digit.
std::string poseText(const btTransform& t)
{
  btScalar yaw, pitch, roll;
  t.getBasis().getEulerZYX(yaw, pitch, roll);
  char buf[200];
  std::snprintf(buf, sizeof buf, "%.17g %.17g %.17g %.17g %.17g %.17g", t.getOrigin().x(), t.getOrigin().y(),
                t.getOrigin().z(), roll, pitch, yaw);
  return buf;
}

// A <sensor> as the plugins read it: its <pose> "x y z roll pitch yaw" in its link's frame,
// however the file wrote it (relative_to another frame of the model, in degrees, a quaternion).
XmlNode sdfSensor(const SdfCtx& c, const XMLElement* sn, int link, const ModelFrames& mf, const std::string& where)
{
  XmlNode n = toXmlNode(sn);
  for (XmlNode& p : n.children)
    if (p.name == "pose" && !p.attributes.empty())
    {
      p.text = poseText(mf.poseIn(c, sn, link, link, where));
      p.attributes.clear();
    }
  return n;
}

// One scope of an SDF robot: the model's own, or a nested or included model's, flattened into it.
struct RobotScope
{
  SdfCtx ctx;
  const XMLElement* model;
  std::string prefix;  // "" for the robot's own, "nested::" (and "nested::inner::") for the others
  std::string where;
  btTransform in_root;  // the scope's frame in the robot model's
  std::vector<NestedModel> nested;
  ModelFrames mf;
};

void robotScopes(const SdfCtx& c, const XMLElement* m, const std::string& prefix, const btTransform& in_root,
                 const std::string& where, std::vector<RobotScope>& out)
{
  std::vector<NestedModel> nested = nestedModels(c, m, where);
  ModelFrames mf = modelFrames(c, m, where, nested);
  out.push_back({c, m, prefix, where, in_root, std::move(nested), std::move(mf)});
  const size_t at = out.size() - 1;
  for (size_t i = 0; i < out[at].nested.size(); ++i)
  {
    const NestedModel n = out[at].nested[i];  // a copy: out grows below
    const btTransform n_in_root = out[at].in_root * out[at].mf.frames.resolve(out[at].mf.of.at(n.element));
    robotScopes(n.file.ctx, n.file.model, prefix + n.name + "::", n_in_root, n.where, out);
  }
}

// A model that is not static and has joints or plugins (its own, its sensors' or its nested
// models'), as Gazebo simulates it: a robot (see parseSdfSpawn), its nested and included models
// flattened into it ("hokuyo::link", "hokuyo::joint"; a joint of the robot may name "hokuyo::link",
// as Gazebo's tutorial robot fixes its included laser). Link poses are the model's (SDF 1.6:
// relative to the model frame); a joint's <pose> is its frame in the child link's, its axis in that
// frame unless said to be in another (SdfFrames). False for a rigid model.
bool parseSdfRobot(const SdfCtx& c, const XMLElement* m, const std::string& where, RobotSpec& rs,
                   btTransform& root_in_model)
{
  const std::string st = c.text(m, "static", where, false, "false");
  if (st == "true" || st == "1")
    return false;
  std::vector<RobotScope> scopes;
  robotScopes(c, m, "", btTransform::getIdentity(), where, scopes);
  bool articulated = false;
  for (const RobotScope& s : scopes)
  {
    articulated = articulated || s.model->FirstChildElement("joint") || s.model->FirstChildElement("plugin");
    for (const XMLElement* l = s.model->FirstChildElement("link"); l && !articulated; l = l->NextSiblingElement("link"))
      for (const XMLElement* sn = l->FirstChildElement("sensor"); sn && !articulated;
           sn = sn->NextSiblingElement("sensor"))
        articulated = sn->FirstChildElement("plugin") != nullptr;
  }
  if (!articulated)
    return false;
  rs.name = m->Attribute("name") ? m->Attribute("name") : "";
  rs.source = c.source;
  std::map<std::string, btTransform> pose_of;  // each link's frame in the model's
  for (const RobotScope& s : scopes)
    for (const XMLElement* l = s.model->FirstChildElement("link"); l; l = l->NextSiblingElement("link"))
    {
      const SdfCtx& sc = s.ctx;
      const ModelFrames& mf = s.mf;
      LinkSpec ls;
      ls.name = nameOf(l);
      const std::string lw = s.where + " <link name='" + ls.name + "'>";
      if (ls.name.empty() || ls.name == "world" || pose_of.count(s.prefix + ls.name))
        sc.fail(lw, ls.name.empty() ? "missing attribute 'name'" : "a second link of this name (or 'world')");
      ls.name = s.prefix + ls.name;
      const int link = mf.of.at(l);
      pose_of[ls.name] = s.in_root * mf.frames.resolve(link);
      // SDF's defaults: 1 kg, unit moments.
      ls.has_inertial = true;
      ls.inertial.mass = 1.0;
      ls.inertial.ixx = ls.inertial.iyy = ls.inertial.izz = 1.0;
      if (const XMLElement* in = l->FirstChildElement("inertial"))
      {
        const std::string iw = lw + " <inertial>";
        ls.inertial.mass = sc.number(in, "mass", iw, false, 1.0);
        if (ls.inertial.mass <= 0)
          sc.fail(iw + " <mass>", "mass must be positive");
        ls.inertial.origin = mf.poseIn(sc, in, link, link, iw);
        if (const XMLElement* I = in->FirstChildElement("inertia"))
        {
          const std::string Iw = iw + " <inertia>";
          ls.inertial.ixx = sc.number(I, "ixx", Iw, false, 1.0);
          ls.inertial.iyy = sc.number(I, "iyy", Iw, false, 1.0);
          ls.inertial.izz = sc.number(I, "izz", Iw, false, 1.0);
          ls.inertial.ixy = sc.number(I, "ixy", Iw, false, 0.0);
          ls.inertial.ixz = sc.number(I, "ixz", Iw, false, 0.0);
          ls.inertial.iyz = sc.number(I, "iyz", Iw, false, 0.0);
        }
      }
      ls.collisions = sdfCollisions(sc, l, lw, mf);
      sdfVisualColor(sc, l, lw, ls.color);
      for (const XMLElement* sn = l->FirstChildElement("sensor"); sn; sn = sn->NextSiblingElement("sensor"))
        ls.sensors.push_back(sdfSensor(sc, sn, link, mf, lw + " <sensor name='" + nameOf(sn) + "'>"));
      checkInertia(sc.source, ls, lw, rs.warnings);
      rs.links.push_back(std::move(ls));
    }
  if (rs.links.empty())
    c.fail(where, "no <link>");
  std::set<std::string> children, joint_names;
  for (const RobotScope& s : scopes)
    for (const XMLElement* j = s.model->FirstChildElement("joint"); j; j = j->NextSiblingElement("joint"))
    {
      const SdfCtx& sc = s.ctx;
      const ModelFrames& mf = s.mf;
      JointSpec js;
      js.name = s.prefix + nameOf(j);
      const std::string type = j->Attribute("type") ? j->Attribute("type") : "";
      const std::string jw = s.where + " <joint name='" + nameOf(j) + "'>";
      if (nameOf(j).empty() || !joint_names.insert(js.name).second)
        sc.fail(jw, nameOf(j).empty() ? "missing attribute 'name'" : "a second joint of this name");
      if (type == "revolute")
        js.type = JointSpec::REVOLUTE;
      else if (type == "continuous")
        js.type = JointSpec::CONTINUOUS;
      else if (type == "prismatic")
        js.type = JointSpec::PRISMATIC;
      else if (type == "fixed")
        js.type = JointSpec::FIXED;
      else if (type == "ball")
        js.type = JointSpec::BALL;
      else
        sc.fail(jw, "type '" + type + "' is not simulated (revolute, continuous, prismatic, ball, fixed)");
      // A nested model's joint names its own links; `world` is the world's.
      const auto scoped = [&](const std::string& n) { return n == "world" ? n : s.prefix + n; };
      js.parent = scoped(sc.text(j, "parent", jw, true));
      js.child = scoped(sc.text(j, "child", jw, true));
      // Gazebo keeps an SDF model's fixed joints (it lumps only a URDF's): the child stays a link of
      // its own, with its own mass, and a force-torque sensor can read the joint. One to the world
      // anchors the model instead.
      js.keep_fixed = js.type == JointSpec::FIXED && js.parent != "world";
      if (js.parent == "world" && !pose_of.count("world"))
      {
        LinkSpec world;  // the world itself, as a URDF's `world` link: what anchors the model
        world.name = "world";
        rs.links.push_back(world);
        pose_of["world"] = btTransform::getIdentity();
      }
      for (const std::string* l : {&js.parent, &js.child})
        if (!pose_of.count(*l))
          sc.fail(jw, "no link named '" + *l + "' in the model");
      if (js.child == "world" || !children.insert(js.child).second)
        sc.fail(jw, "link '" + js.child + "' is the child of a second joint (or the world)");
      js.origin = pose_of[js.parent].inverse() * pose_of[js.child];
      // The joint's frame: in its child link's by default (as SDF 1.6 knows it; the child may be
      // in a nested model), else where its relative_to says.
      const btTransform joint_in_root = SdfCtx::relativeTo(j).empty() ? pose_of[js.child] * sc.pose(j, jw)
                                                                      : s.in_root * mf.frames.resolve(mf.of.at(j));
      js.pivot = pose_of[js.child].inverse() * joint_in_root;
      js.axis = btVector3(0, 0, 1);
      if (const XMLElement* ax = j->FirstChildElement("axis"))
      {
        const std::string aw = jw + " <axis>";
        if (const XMLElement* x = ax->FirstChildElement("xyz"); x && x->GetText())
        {
          try
          {
            js.axis = parseVec3(x->GetText(), "<xyz>");
          }
          catch (const LoadError& e)
          {
            sc.fail(aw, e.what());
          }
          // In the joint's frame unless expressed_in names another frame of the model (SDF 1.7),
          // or use_parent_model_frame says the model's (SDF 1.5 and 1.6).
          const char* in = x->Attribute("expressed_in");
          btTransform frame = joint_in_root;
          if (in && *in)
            frame = s.in_root * mf.frames.resolve(mf.frames.find(in, aw + " <xyz expressed_in>"));
          if (sc.text(ax, "use_parent_model_frame", aw, false) == "true")
            frame = s.in_root;
          js.axis = joint_in_root.getBasis().transpose() * frame.getBasis() * js.axis;
        }
        if (!normalizeDirection(js.axis))
          sc.fail(aw + " <xyz>", "zero axis");
        if (const XMLElement* lim = ax->FirstChildElement("limit"))
        {
          // SDF's defaults: +-1e16 (no limits), -1 (no effort or velocity limit).
          js.lower = sc.number(lim, "lower", aw + " <limit>", false, -1e16);
          js.upper = sc.number(lim, "upper", aw + " <limit>", false, 1e16);
          const double effort = sc.number(lim, "effort", aw + " <limit>", false, -1);
          const double velocity = sc.number(lim, "velocity", aw + " <limit>", false, -1);
          js.has_effort = effort >= 0;
          js.effort = std::max(effort, 0.0);
          js.has_velocity = velocity >= 0;
          js.velocity = std::max(velocity, 0.0);
        }
        else
        {
          js.lower = -1e16;
          js.upper = 1e16;
        }
        js.has_limits = js.type != JointSpec::CONTINUOUS && js.lower > -1e15 && js.upper < 1e15 && js.upper > js.lower;
        if (js.type == JointSpec::REVOLUTE && !js.has_limits)
          js.type = JointSpec::CONTINUOUS;  // unlimited, as URDF says it
        if (const XMLElement* dyn = ax->FirstChildElement("dynamics"))
        {
          js.damping = sc.number(dyn, "damping", aw + " <dynamics>", false, 0.0);
          js.friction = sc.number(dyn, "friction", aw + " <dynamics>", false, 0.0);
          if (js.damping < 0 || js.friction < 0)
            sc.fail(aw + " <dynamics>", "negative damping or friction");
        }
      }
      rs.joints.push_back(js);
    }
  std::vector<std::string> roots;
  for (const auto& l : rs.links)
    if (!children.count(l.name))
      roots.push_back(l.name);
  if (roots.empty())
    c.fail(where, "every link is a joint's child: the joints make a loop");
  if (roots.size() > 1)
    c.fail(where, "links '" + roots[0] + "' and '" + roots[1] +
                      "' are not joined: a model with joints is simulated as one tree of links");
  rs.root = roots[0];
  root_in_model = pose_of[rs.root];
  for (const RobotScope& s : scopes)
    for (const XMLElement* p = s.model->FirstChildElement("plugin"); p; p = p->NextSiblingElement("plugin"))
    {
      PluginSpec ps;
      ps.xml = toXmlNode(p);
      ps.name = ps.xml.attr("name");
      ps.filename = ps.xml.attr("filename");
      ps.scope = s.prefix;
      if (ps.filename.empty())
        s.ctx.fail(s.where + " <plugin name='" + ps.name + "'>", "missing attribute 'filename'");
      rs.plugins.push_back(std::move(ps));
    }
  addSensorPlugins(rs, where + " <link name='");
  return true;
}

// A model's rigid links (nested and included models flattened into it, "nested::link"); with
// `spawn`, also the robot it is when it has joints or plugins (parseSdfRobot).
WorldModel parseSdfModel(const SdfCtx& c, const XMLElement* m, const std::string& where_in, SdfSpawn* spawn = nullptr)
{
  WorldModel model;
  model.name = m->Attribute("name") ? m->Attribute("name") : "";
  std::string where = where_in + " <model name='" + model.name + "'>";
  if (model.name.empty())
    c.fail(where_in, "<model> without name");
  model.pose = c.pose(m, where);
  std::string st = c.text(m, "static", where, false, "false");
  model.is_static = (st == "true" || st == "1");
  if (spawn)
  {
    RobotSpec rs;
    rs.from_sdf = true;
    if (parseSdfRobot(c, m, where, rs, spawn->root_in_model))
      spawn->robot = std::make_shared<RobotSpec>(std::move(rs));
  }
  const std::vector<NestedModel> nested = nestedModels(c, m, where);
  const ModelFrames mf = modelFrames(c, m, where, nested);
  for (const XMLElement* l = m->FirstChildElement("link"); l; l = l->NextSiblingElement("link"))
  {
    WorldLink link;
    link.name = l->Attribute("name") ? l->Attribute("name") : "link";
    std::string lw = where + " <link name='" + link.name + "'>";
    link.pose = mf.frames.resolve(mf.of.at(l));
    if (const XMLElement* in = l->FirstChildElement("inertial"))
    {
      link.mass = c.number(in, "mass", lw + " <inertial>", false, 1.0);
      if (link.mass <= 0)
        c.fail(lw + " <inertial> <mass>", "mass must be positive");
    }
    link.shapes = sdfCollisions(c, l, lw, mf);
    link.has_color = sdfVisualColor(c, l, lw, link.color);
    model.links.push_back(std::move(link));
  }
  for (const NestedModel& n : nested)
  {
    WorldModel sub = parseSdfModel(n.file.ctx, n.file.model, n.where_in);
    // Placed in this model's scope (its own <pose>, or the <include>'s, may be relative_to a
    // frame of this model).
    const btTransform pose = mf.frames.resolve(mf.of.at(n.element));
    for (auto& l : sub.links)
    {
      l.pose = pose * l.pose;
      l.name = n.name + "::" + l.name;
      model.links.push_back(l);
    }
  }
  return model;
}

// Resolves <include><uri>model://X</uri></include>. Returns false for the
// built-in sun (a light, nothing to simulate).
bool parseInclude(const SdfCtx& c, const XMLElement* inc, WorldSpec& world, WorldModel& out, SdfSpawn* spawn = nullptr)
{
  std::string where = "<include>";
  std::string uri = c.text(inc, "uri", where, true);
  where = "<include> <uri>" + uri + "</uri>";
  if (uri == "model://sun")
    return false;
  if (uri == "model://ground_plane")
  {
    world.ground_plane = true;
    world.file_order.push_back("ground_plane");
    return false;
  }
  const IncludedModel file = loadInclude(c, uri, where);
  out = parseSdfModel(file.ctx, file.model, "", spawn);
  if (const char* n = inc->FirstChildElement("name") ? inc->FirstChildElement("name")->GetText() : nullptr)
    out.name = n;
  if (inc->FirstChildElement("pose"))
    out.pose = c.pose(inc, where);
  if (const XMLElement* st = inc->FirstChildElement("static"))
    if (st->GetText())
      out.is_static = std::string(st->GetText()) == "true" || std::string(st->GetText()) == "1";
  if (spawn && out.is_static)
    spawn->robot.reset();  // <static> in the <include> wins
  return true;
}
}  // namespace

namespace
{
// Gazebo's <physics>: max_step_size, real_time_factor and the solver's iterations. Values are
// checked here with the node's own bounds, naming the element.
PhysicsSpec parsePhysics(const SdfCtx& c, const XMLElement* ph)
{
  PhysicsSpec p;
  auto number = [&](const XMLElement* e, const std::string& what)
  {
    const char* t = e->GetText();
    char* end = nullptr;
    const double v = t ? std::strtod(t, &end) : 0.0;
    if (!t || end == t || *end != '\0' || !std::isfinite(v))
      c.fail("<physics> <" + what + ">", std::string("expected a number, got '") + (t ? t : "") + "'");
    return v;
  };
  if (const XMLElement* e = ph->FirstChildElement("max_step_size"))
  {
    p.has_step = true;
    p.max_step_size = number(e, "max_step_size");
    if (!(p.max_step_size > 0 && p.max_step_size <= 0.01))
      c.fail("<physics> <max_step_size>", "must be in (0, 0.01] s");
  }
  if (const XMLElement* e = ph->FirstChildElement("real_time_factor"))
  {
    p.has_real_time_factor = true;
    p.real_time_factor = number(e, "real_time_factor");
    if (p.real_time_factor < 0)
      c.fail("<physics> <real_time_factor>", "must be >= 0");
  }
  for (const char* engine : {"ode", "bullet"})
    if (const XMLElement* e = ph->FirstChildElement(engine))
      if (const XMLElement* s = e->FirstChildElement("solver"))
        if (const XMLElement* it = s->FirstChildElement("iters"))
        {
          const double v = number(it, std::string(engine) + "><solver><iters");
          if (v < 1 || v != std::floor(v))
            c.fail(std::string("<physics> <") + engine + "><solver><iters>", "must be a whole number >= 1");
          p.has_iterations = true;
          p.iterations = static_cast<int>(v);
        }
  return p;
}
}  // namespace

WorldSpec parseSdfWorld(const std::string& xml, const std::string& source, const std::string& base_dir,
                        const UriResolver& resolver)
{
  SdfCtx c{source, base_dir, &resolver, {}};
  tinyxml2::XMLDocument doc;
  c.parse(doc, xml);
  const XMLElement* sdf = doc.FirstChildElement("sdf");
  if (!sdf)
    c.fail("document", "no <sdf> element");
  const XMLElement* w = sdf->FirstChildElement("world");
  if (!w)
    c.fail("<sdf>", "no <world> element");
  WorldSpec world;
  world.source = source;
  if (w->Attribute("name"))
    world.name = w->Attribute("name");
  if (const XMLElement* g = w->FirstChildElement("gravity"))
  {
    try
    {
      world.gravity = parseVec3(g->GetText() ? g->GetText() : "", "<gravity>");
    }
    catch (const LoadError& e)
    {
      c.fail("<world>", e.what());
    }
  }
  if (const XMLElement* ph = w->FirstChildElement("physics"))
    world.physics = parsePhysics(c, ph);
  if (const XMLElement* sc = w->FirstChildElement("spherical_coordinates"))
  {
    const std::string where = "<world> <spherical_coordinates>";
    const std::string surface = c.text(sc, "surface_model", where, false, "EARTH_WGS84");
    if (surface != "EARTH_WGS84")
      c.fail(where + " <surface_model>", "'" + surface + "': only EARTH_WGS84 is known (Gazebo's)");
    SphericalCoordinates& s = world.spherical;
    s.latitude_deg = c.number(sc, "latitude_deg", where, false, 0.0);
    s.longitude_deg = c.number(sc, "longitude_deg", where, false, 0.0);
    s.elevation = c.number(sc, "elevation", where, false, 0.0);
    s.heading_deg = c.number(sc, "heading_deg", where, false, 0.0);
    if (std::abs(s.latitude_deg) > 90)
      c.fail(where + " <latitude_deg>", "must be within [-90, 90]");
  }
  // The world's frames (SDF 1.7): a model's or an include's <pose> may be written relative_to
  // another model or a <frame> of the world. Each model's frame, placed once all are read:
  SdfFrames frames(source, "world");
  struct Placed
  {
    int frame;
    bool robot;
    size_t index;  // in world.robots or world.models
  };
  std::vector<Placed> placed;
  std::vector<std::pair<std::string, std::string>> attached;  // (frame, where)
  // A model with joints or plugins is a robot, as Gazebo simulates it (and as spawn_sdf_model takes it).
  const auto add = [&](WorldModel m, const SdfSpawn& spawn, const XMLElement* pose_of, const std::string& where)
  {
    const int frame = frames.add(m.name, SdfCtx::relativeTo(pose_of), SdfFrames::kScope, m.pose, where);
    world.file_order.push_back(m.name);
    if (!spawn.robot)
    {
      world.models.push_back(std::move(m));
      placed.push_back({frame, false, world.models.size() - 1});
      return;
    }
    spawn.robot->name = m.name;
    world.robots.push_back({m.name, spawn.robot, m.pose, spawn.root_in_model});
    placed.push_back({frame, true, world.robots.size() - 1});
  };
  for (const XMLElement* e = w->FirstChildElement(); e; e = e->NextSiblingElement())
  {
    std::string n = e->Name();
    SdfSpawn spawn;
    if (n == "include")
    {
      WorldModel m;
      if (parseInclude(c, e, world, m, &spawn))
        add(std::move(m), spawn, e, "<include> <uri>" + c.text(e, "uri", "<include>", true) + "</uri>");
    }
    else if (n == "model")
    {
      add(parseSdfModel(c, e, "<world>", &spawn), spawn, e, "<world> <model name='" + nameOf(e) + "'>");
    }
    else if (n == "frame")
    {
      const std::string fw = "<world> <frame name='" + nameOf(e) + "'>";
      if (nameOf(e).empty())
        c.fail(fw, "missing attribute 'name'");
      const std::string to = e->Attribute("attached_to") ? e->Attribute("attached_to") : "";
      const std::string rel = SdfCtx::relativeTo(e);
      frames.add(nameOf(e), rel.empty() ? to : rel, SdfFrames::kScope, c.pose(e, fw), fw);
      if (!to.empty())
        attached.emplace_back(to, fw + " attached_to");
    }
  }
  for (const auto& [to, fw] : attached)
    frames.find(to, fw);
  for (const Placed& p : placed)
    (p.robot ? world.robots[p.index].model_pose : world.models[p.index].pose) = frames.resolve(p.frame);
  // Gazebo applies the poses saved in a <state> block on load.
  for (const XMLElement* st = w->FirstChildElement("state"); st; st = st->NextSiblingElement("state"))
  {
    for (const XMLElement* m = st->FirstChildElement("model"); m; m = m->NextSiblingElement("model"))
    {
      std::string name = m->Attribute("name") ? m->Attribute("name") : "";
      std::string where = "<state> <model name='" + name + "'>";
      for (auto& wr : world.robots)
        if (wr.name == name && m->FirstChildElement("pose"))
          wr.model_pose = c.pose(m, where);  // its links follow their joints
      for (auto& wm : world.models)
      {
        if (wm.name != name)
          continue;
        if (m->FirstChildElement("pose"))
          wm.pose = c.pose(m, where);
        for (const XMLElement* l = m->FirstChildElement("link"); l; l = l->NextSiblingElement("link"))
        {
          std::string ln = l->Attribute("name") ? l->Attribute("name") : "";
          // State link poses are in the world frame.
          if (l->FirstChildElement("pose"))
            for (auto& wl : wm.links)
              if (wl.name == ln)
                wl.pose = wm.pose.inverse() * c.pose(l, where + " <link>");
        }
      }
    }
  }
  for (const WorldModel& m : world.models)
    checkMagnitudes(m, source);
  for (const WorldRobot& r : world.robots)
  {
    checkLength(r.model_pose.getOrigin(), source, "<model name='" + r.name + "'> <pose>");
    checkMagnitudes(*r.spec, source + " <model name='" + r.name + "'>");
  }
  return world;
}

namespace
{
// One model of an SDF document as spawn_sdf_model takes it: <sdf><model>, a bare <model>, or a
// <world> of one <model> or <include> (spawn_model -database).
WorldModel parseSdfDocument(const SdfCtx& c, const std::string& xml, SdfSpawn* spawn)
{
  tinyxml2::XMLDocument doc;
  c.parse(doc, xml);
  const XMLElement* root = doc.RootElement();
  const XMLElement* m = nullptr;
  if (root && std::string(root->Name()) == "sdf")
  {
    if (const XMLElement* w = root->FirstChildElement("world"))
    {
      // gazebo_ros's spawn_model -database NAME sends <world><include><uri>model://NAME: a world
      // of one model or include is taken as that model.
      std::vector<const XMLElement*> items;
      for (const XMLElement* e = w->FirstChildElement(); e; e = e->NextSiblingElement())
        if (std::string(e->Name()) == "model" || std::string(e->Name()) == "include")
          items.push_back(e);
      if (items.size() != 1)
        c.fail("<sdf><world>", "holds " + std::to_string(items.size()) + " models; one model was expected");
      if (std::string(items[0]->Name()) == "model")
      {
        checkOutermostPose(c, items[0], "<world>", true);
        return parseSdfModel(c, items[0], "<world>", spawn);
      }
      WorldSpec ignored;
      WorldModel out;
      if (!parseInclude(c, items[0], ignored, out, spawn))
        c.fail("<sdf><world><include>", "the sun and the ground plane are not models to spawn");
      return out;
    }
    m = root->FirstChildElement("model");
    if (!m)
      c.fail("<sdf>", "no <model> element");
  }
  else if (root && std::string(root->Name()) == "model")
    m = root;
  else
    c.fail("document", std::string("<") + (root ? root->Name() : "") + ">, where <sdf><model> was expected");
  checkOutermostPose(c, m, "", false);
  return parseSdfModel(c, m, "", spawn);
}
}  // namespace

WorldModel parseSdfModel(const std::string& xml, const std::string& source, const std::string& base_dir,
                         const UriResolver& resolver)
{
  WorldModel model = parseSdfDocument(SdfCtx{source, base_dir, &resolver, {}}, xml, nullptr);
  checkMagnitudes(model, source);
  return model;
}

SdfSpawn parseSdfSpawn(const std::string& xml, const std::string& source, const std::string& base_dir,
                       const UriResolver& resolver)
{
  SdfSpawn out;
  out.model = parseSdfDocument(SdfCtx{source, base_dir, &resolver, {}}, xml, &out);
  if (out.robot)
  {
    out.robot->name = out.model.name;
    checkMagnitudes(*out.robot, source + " <model name='" + out.model.name + "'>");
  }
  checkMagnitudes(out.model, source);
  return out;
}
}  // namespace mybot_gazebo_lite
