// World loaders: an SDF subset (Gazebo classic .world files) and a floor plan
// made from an occupancy image with a map_server-style YAML.
#include "mybot_gazebo_lite/parsing.h"

#include <opencv2/imgcodecs.hpp>
#include <tinyxml2.h>
#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <cstdio>
#include <cmath>
#include <fstream>
#include <sstream>

namespace mybot_gazebo_lite
{

namespace
{
using tinyxml2::XMLElement;

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

struct SdfCtx
{
  std::string source, base_dir;
  const UriResolver* resolver;
  [[noreturn]] void fail(const std::string& where, const std::string& msg) const
  {
    throw LoadError(source + ": " + where + ": " + msg);
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
  btTransform pose(const XMLElement* e, const std::string& where) const
  {
    const XMLElement* p = e->FirstChildElement("pose");
    if (!p || !p->GetText())
      return btTransform::getIdentity();
    try
    {
      return parsePose6(p->GetText(), "<pose>");
    }
    catch (const LoadError& ex)
    {
      fail(where, ex.what());
    }
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
    if (shape.normal.length() < 1e-9)
      c.fail(w, "zero normal");
    shape.normal.normalize();
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
    shape.mesh_path = (*c.resolver)(uri, c.base_dir);
    if (shape.mesh_path.empty())
      c.fail(w, "mesh '" + uri + "' not found");
    try
    {
      shape.triangles = loadMesh(shape.mesh_path, shape.mesh_scale);
    }
    catch (const LoadError& e)
    {
      c.fail(w, e.what());
    }
  }
  else
  {
    c.fail(w, "unsupported geometry");
  }
  return shape;
}

WorldModel parseSdfModel(const SdfCtx& c, const XMLElement* m, const std::string& where_in)
{
  WorldModel model;
  model.name = m->Attribute("name") ? m->Attribute("name") : "";
  std::string where = where_in + " <model name='" + model.name + "'>";
  if (model.name.empty())
    c.fail(where_in, "<model> without name");
  model.pose = c.pose(m, where);
  std::string st = c.text(m, "static", where, false, "false");
  model.is_static = (st == "true" || st == "1");
  for (const XMLElement* l = m->FirstChildElement("link"); l; l = l->NextSiblingElement("link"))
  {
    WorldLink link;
    link.name = l->Attribute("name") ? l->Attribute("name") : "link";
    std::string lw = where + " <link name='" + link.name + "'>";
    link.pose = c.pose(l, lw);
    if (const XMLElement* in = l->FirstChildElement("inertial"))
    {
      link.mass = c.number(in, "mass", lw + " <inertial>", false, 1.0);
      if (link.mass <= 0)
        c.fail(lw + " <inertial> <mass>", "mass must be positive");
    }
    for (const XMLElement* col = l->FirstChildElement("collision"); col; col = col->NextSiblingElement("collision"))
    {
      std::string cw = lw + " <collision name='" + (col->Attribute("name") ? col->Attribute("name") : "") + "'>";
      Shape s = parseSdfGeometry(c, col->FirstChildElement("geometry"), cw);
      s.pose = c.pose(col, cw);
      s.name = col->Attribute("name") ? col->Attribute("name") : "collision";
      if (const XMLElement* surf = col->FirstChildElement("surface"))
        if (const XMLElement* fr = surf->FirstChildElement("friction"))
          if (const XMLElement* ode = fr->FirstChildElement("ode"))
          {
            s.mu1 = c.number(ode, "mu", cw + " <friction><ode>", false, 1.0);
            s.mu2 = c.number(ode, "mu2", cw + " <friction><ode>", false, s.mu1);
          }
      link.shapes.push_back(s);
    }
    for (const XMLElement* vis = l->FirstChildElement("visual"); vis && !link.has_color;
         vis = vis->NextSiblingElement("visual"))
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
        if (name && name->GetText())
          link.has_color = gazeboMaterialColor(name->GetText(), link.color);
        continue;
      }
      std::string vw = lw + " <visual><material><" + col->Name() + ">";
      std::istringstream ss(col->GetText());
      double rgb[3];
      if (!(ss >> rgb[0] >> rgb[1] >> rgb[2]))
        c.fail(vw, std::string("expected 'r g b [a]', got '") + col->GetText() + "'");
      for (int i = 0; i < 3; ++i)
        link.color[i] = static_cast<float>(std::clamp(rgb[i], 0.0, 1.0));
      link.has_color = true;
    }
    model.links.push_back(std::move(link));
  }
  // Nested models are flattened into this one.
  for (const XMLElement* n = m->FirstChildElement("model"); n; n = n->NextSiblingElement("model"))
  {
    WorldModel sub = parseSdfModel(c, n, where);
    for (auto& l : sub.links)
    {
      l.pose = sub.pose * l.pose;
      l.name = sub.name + "::" + l.name;
      model.links.push_back(l);
    }
  }
  return model;
}

// Resolves <include><uri>model://X</uri></include>. Returns false for the
// built-in sun (a light, nothing to simulate).
bool parseInclude(const SdfCtx& c, const XMLElement* inc, WorldSpec& world, WorldModel& out)
{
  std::string where = "<include>";
  std::string uri = c.text(inc, "uri", where, true);
  where = "<include> <uri>" + uri + "</uri>";
  if (uri == "model://sun")
    return false;
  if (uri == "model://ground_plane")
  {
    world.ground_plane = true;
    return false;
  }
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
  std::string xml = readFile(sdf_file, c.source + ": " + where);
  tinyxml2::XMLDocument doc;
  if (doc.Parse(xml.c_str(), xml.size()) != tinyxml2::XML_SUCCESS)
    throw LoadError(sdf_file + ": XML: " + (doc.ErrorStr() ? doc.ErrorStr() : "parse error"));
  const XMLElement* sdf = doc.FirstChildElement("sdf");
  const XMLElement* m = sdf ? sdf->FirstChildElement("model") : nullptr;
  if (!m)
    throw LoadError(sdf_file + ": no <sdf><model>");
  SdfCtx sub{sdf_file, dir, c.resolver};
  out = parseSdfModel(sub, m, "");
  if (const char* n = inc->FirstChildElement("name") ? inc->FirstChildElement("name")->GetText() : nullptr)
    out.name = n;
  if (inc->FirstChildElement("pose"))
    out.pose = c.pose(inc, where);
  if (const XMLElement* st = inc->FirstChildElement("static"))
    if (st->GetText())
      out.is_static = std::string(st->GetText()) == "true" || std::string(st->GetText()) == "1";
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
  SdfCtx c{source, base_dir, &resolver};
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
  for (const XMLElement* e = w->FirstChildElement(); e; e = e->NextSiblingElement())
  {
    std::string n = e->Name();
    if (n == "include")
    {
      WorldModel m;
      if (parseInclude(c, e, world, m))
        world.models.push_back(std::move(m));
    }
    else if (n == "model")
    {
      world.models.push_back(parseSdfModel(c, e, "<world>"));
    }
  }
  // Gazebo applies the poses saved in a <state> block on load.
  for (const XMLElement* st = w->FirstChildElement("state"); st; st = st->NextSiblingElement("state"))
  {
    for (const XMLElement* m = st->FirstChildElement("model"); m; m = m->NextSiblingElement("model"))
    {
      std::string name = m->Attribute("name") ? m->Attribute("name") : "";
      std::string where = "<state> <model name='" + name + "'>";
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
  return world;
}

WorldModel parseSdfModel(const std::string& xml, const std::string& source, const std::string& base_dir,
                         const UriResolver& resolver)
{
  SdfCtx c{source, base_dir, &resolver};
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
        return parseSdfModel(c, items[0], "<world>");
      WorldSpec ignored;
      WorldModel out;
      if (!parseInclude(c, items[0], ignored, out))
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
  return parseSdfModel(c, m, "");
}

namespace
{
// A map_server-style YAML's fields, checked (each error names the file and the key).
struct ImageWorld
{
  std::string image;  // absolute path
  double resolution = 0.0;
  double origin_x = 0.0, origin_y = 0.0, origin_yaw = 0.0;
  double occupied_thresh = 0.65;
  bool negate = false;
  double height = 1.0;  // m, of the extruded walls
};

ImageWorld readImageWorldYaml(const std::string& yaml_path)
{
  YAML::Node y;
  try
  {
    y = YAML::LoadFile(yaml_path);
  }
  catch (const std::exception& e)
  {
    throw LoadError(yaml_path + ": YAML: " + e.what());
  }
  auto fail = [&](const std::string& key, const std::string& msg) -> void
  { throw LoadError(yaml_path + ": '" + key + "': " + msg); };
  auto num = [&](const char* key, bool required, double def)
  {
    if (!y[key])
    {
      if (required)
        fail(key, "missing");
      return def;
    }
    double v = def;
    try
    {
      v = y[key].as<double>();
    }
    catch (const std::exception&)
    {
      fail(key, "not a number");
    }
    if (!std::isfinite(v))
      fail(key, "must be finite");
    return v;
  };
  if (!y.IsMap())
    throw LoadError(yaml_path + ": expected a map_server-style YAML mapping");
  if (!y["image"])
    fail("image", "missing");
  if (!y["image"].IsScalar())
    fail("image", "expected a file name");
  ImageWorld w;
  w.image = y["image"].as<std::string>();
  if (w.image.empty() || w.image[0] != '/')
    w.image = dirOf(yaml_path) + "/" + w.image;
  w.resolution = num("resolution", true, 0);
  if (!(w.resolution > 0))
    fail("resolution", "must be positive");
  if (!y["origin"] || !y["origin"].IsSequence() || y["origin"].size() != 3)
    fail("origin", "expected [x, y, yaw]");
  try
  {
    w.origin_x = y["origin"][0].as<double>();
    w.origin_y = y["origin"][1].as<double>();
    w.origin_yaw = y["origin"][2].as<double>();
  }
  catch (const std::exception&)
  {
    fail("origin", "expected [x, y, yaw] numbers");
  }
  if (!std::isfinite(w.origin_x) || !std::isfinite(w.origin_y) || !std::isfinite(w.origin_yaw))
    fail("origin", "must be finite");
  w.occupied_thresh = num("occupied_thresh", false, 0.65);
  if (!(w.occupied_thresh > 0 && w.occupied_thresh <= 1))
    fail("occupied_thresh", "must be in (0, 1]");
  w.negate = static_cast<int>(num("negate", false, 0)) != 0;
  w.height = num("height", false, 1.0);
  if (!(w.height > 0))
    fail("height", "must be positive");
  return w;
}

cv::Mat readImageWorldImage(const std::string& yaml_path, const ImageWorld& w, long max_image_side)
{
  auto fail = [&](const std::string& msg) { throw LoadError(yaml_path + ": 'image': " + msg); };
  // The header first: a file claiming 200000 x 200000 pixels is refused before decoding.
  std::string too_large = mybot_common::declaredImageSizeError(w.image, max_image_side, "~max_image_side");
  if (!too_large.empty())
    fail(too_large);
  cv::Mat img;
  try
  {
    img = cv::imread(w.image, cv::IMREAD_GRAYSCALE);
  }
  catch (const cv::Exception& e)
  {
    fail("cannot read image '" + w.image + "': " + e.what());
  }
  if (img.empty())
    fail("cannot read image '" + w.image + "'");
  too_large = mybot_common::imageSizeError(w.image, img.cols, img.rows, max_image_side, "~max_image_side");
  if (!too_large.empty())
    fail(too_large);

  return img;
}

// Occupied cells merged into boxes: row runs, extended downwards while identical.
std::vector<Shape> mergeOccupiedCellsIntoBoxes(const cv::Mat& img, const ImageWorld& w)
{
  std::vector<Shape> boxes;
  const int W = img.cols, H = img.rows;
  auto occupied = [&](int r, int col)
  {
    double v = img.at<uint8_t>(r, col) / 255.0;
    double p = w.negate ? v : 1.0 - v;
    return p > w.occupied_thresh;
  };
  struct Run
  {
    int x0, x1, r0;
  };
  std::vector<Run> open;
  auto emit = [&](const Run& run, int r_end)
  {
    // Image row 0 is the top (largest y).
    const double res = w.resolution;
    double x0 = run.x0 * res, x1 = (run.x1 + 1) * res;
    double ytop = (H - run.r0) * res, ybot = (H - r_end) * res;
    Shape s;
    s.type = Shape::BOX;
    s.size = btVector3(x1 - x0, ytop - ybot, w.height);
    s.pose.setIdentity();
    s.pose.setOrigin(btVector3((x0 + x1) / 2, (ytop + ybot) / 2, w.height / 2));
    boxes.push_back(s);
  };
  for (int r = 0; r <= H; ++r)
  {
    std::vector<Run> runs;
    if (r < H)
    {
      for (int col = 0; col < W;)
      {
        if (!occupied(r, col))
        {
          ++col;
          continue;
        }
        int s = col;
        while (col < W && occupied(r, col))
          ++col;
        runs.push_back({s, col - 1, r});
      }
    }
    std::vector<Run> next;
    for (auto& o : open)
    {
      bool cont = false;
      for (auto& n : runs)
        if (n.x0 == o.x0 && n.x1 == o.x1 && n.r0 == r)
        {
          n.r0 = o.r0;
          cont = true;
        }
      if (!cont)
        emit(o, r);
    }
    open = runs;
  }
  return boxes;
}
}  // namespace

WorldSpec loadImageWorld(const std::string& yaml_path, long max_image_side)
{
  const ImageWorld w = readImageWorldYaml(yaml_path);
  const cv::Mat img = readImageWorldImage(yaml_path, w, max_image_side);
  WorldSpec world;
  world.source = yaml_path;
  world.name = "floor_plan";
  world.ground_plane = true;
  WorldModel walls;
  walls.name = "floor_plan_walls";
  walls.is_static = true;
  walls.pose = makeTransform(btVector3(w.origin_x, w.origin_y, 0), btVector3(0, 0, w.origin_yaw));
  WorldLink link;
  link.name = "walls";
  link.shapes = mergeOccupiedCellsIntoBoxes(img, w);
  if (!link.shapes.empty())
    walls.links.push_back(std::move(link));
  world.models.push_back(std::move(walls));
  return world;
}

WorldSpec loadWorldFile(const std::string& path, const UriResolver& resolver, long max_image_side)
{
  auto ends = [&](const std::string& s)
  { return path.size() >= s.size() && path.compare(path.size() - s.size(), s.size(), s) == 0; };
  if (ends(".yaml") || ends(".yml"))
    return loadImageWorld(path, max_image_side);
  std::string xml = readFile(path, "world");
  return parseSdfWorld(xml, path, dirOf(path), resolver);
}

}  // namespace mybot_gazebo_lite
