// What every plugin shares: the static world slices, parameter reading, frames and messages.
#include "mybot_gazebo_lite/parsing.h"
#include "builtin.h"

#include <ros/names.h>
#include <sensor_msgs/JointState.h>

#include <cmath>
#include <set>
#include <sstream>

namespace mybot_gazebo_lite
{

const RayCaster2D& StaticSliceCache::at(double z)
{
  long key = std::lround(z * 100.0);  // 1 cm bins
  auto it = cache_.find(key);
  if (it == cache_.end())
    it = cache_.emplace(key, std::make_unique<RayCaster2D>(sliceWorld(world_, key / 100.0))).first;
  return *it->second;
}

const PrismScene& StaticSliceCache::prisms()
{
  if (!prisms_)
    prisms_ = std::make_unique<PrismScene>(world_);
  return *prisms_;
}

void PluginParams::fail(const std::string& tag, const std::string& msg) const
{
  std::ostringstream os;
  os << c_.robot->spec().source << ": plugin '" << c_.spec->name << "' (" << c_.spec->filename << ")";
  if (!c_.spec->reference.empty())
    os << " on link '" << c_.spec->reference << "'";
  if (!tag.empty())
    os << ": <" << tag << ">";
  os << ": " << msg;
  throw LoadError(os.str());
}

namespace
{
// The children of <plugin> and <sensor> blocks a plugin has looked at, so that what it never
// read can be named (the simulator is single-threaded; specs outlive their plugins).
std::set<const XmlNode*>& readTags()
{
  static std::set<const XmlNode*> tags;
  return tags;
}
}  // namespace

const XmlNode* PluginParams::node(const std::string& path) const
{
  const XmlNode* n = &x_;
  std::stringstream ss(path);
  std::string part;
  bool first = true;
  while (n && std::getline(ss, part, '/'))
  {
    n = n->child(part);
    if (first && n)
      readTags().insert(n);
    first = false;
  }
  return n;
}

std::vector<const XmlNode*> PluginParams::all(const std::string& tag) const
{
  std::vector<const XmlNode*> out = x_.all(tag);
  for (const XmlNode* n : out)
    readTags().insert(n);
  return out;
}

bool PluginParams::wasRead(const XmlNode& child)
{
  return readTags().count(&child) != 0;
}

void PluginParams::forgetReads(const XmlNode& parent)
{
  for (const XmlNode& child : parent.children)
    readTags().erase(&child);
}

std::string PluginParams::str(const std::string& tag, const std::string& def) const
{
  const XmlNode* n = node(tag);
  return n ? n->text : def;
}

std::string PluginParams::requiredStr(const std::string& tag) const
{
  const XmlNode* n = node(tag);
  if (!n || n->text.empty())
    fail(tag, "required parameter missing");
  return n->text;
}

double PluginParams::num(const std::string& tag, double def) const
{
  const XmlNode* n = node(tag);
  return n ? parse(tag, n->text) : def;
}

double PluginParams::requiredNum(const std::string& tag) const
{
  const XmlNode* n = node(tag);
  if (!n)
    fail(tag, "required parameter missing");
  return parse(tag, n->text);
}

double PluginParams::positive(const std::string& tag, double def) const
{
  const double v = num(tag, def);
  if (!(v > 0))
    fail(tag, "must be positive");
  return v;
}

double PluginParams::nonNegative(const std::string& tag, double def) const
{
  const double v = num(tag, def);
  if (!(v >= 0))
    fail(tag, "must be >= 0");
  return v;
}

bool PluginParams::boolean(const std::string& tag, bool def) const
{
  const XmlNode* n = node(tag);
  if (!n)
    return def;
  if (n->text == "true" || n->text == "1")
    return true;
  if (n->text == "false" || n->text == "0")
    return false;
  fail(tag, "expected true/false, got '" + n->text + "'");
}

std::string scopedJoint(const PluginContext& c, const std::string& name)
{
  const std::string own = c.spec->scope + name;
  return !c.spec->scope.empty() && c.robot->hasJoint(own) ? own : name;
}

std::string scopedLink(const PluginContext& c, const std::string& name)
{
  const std::string own = c.spec->scope + name;
  return !c.spec->scope.empty() && c.robot->hasLink(own) ? own : name;
}

std::string PluginParams::joint(const std::string& tag, const std::string& def) const
{
  return movableJoint(tag, str(tag, def));
}

std::vector<std::string> PluginParams::jointList(const std::string& tag, const std::string& separators) const
{
  std::vector<std::string> out;
  const std::string text = str(tag, "");
  size_t start = 0;
  while (start <= text.size())
  {
    size_t end = text.find_first_of(separators, start);
    if (end == std::string::npos)
      end = text.size();
    std::string name = text.substr(start, end - start);
    name.erase(0, name.find_first_not_of(" \t\n"));
    name.erase(name.find_last_not_of(" \t\n") + 1);
    if (!name.empty())
    {
      movableJoint(tag, name);
      out.push_back(name);
    }
    start = end + 1;
  }
  return out;
}

std::string PluginParams::movableJoint(const std::string& tag, const std::string& name) const
{
  const std::string j = scopedJoint(c_, name);
  if (c_.robot->hasJoint(j))
    return j;
  for (const JointSpec& spec : c_.robot->spec().joints)
    if (spec.name == j && spec.type == JointSpec::FIXED)
      fail(tag, spec.keep_fixed ? "joint '" + j + "' is fixed: this plugin moves or reads a movable joint"
                                : "joint '" + j + "' is fixed: Gazebo lumps its child into its parent, and so does " +
                                      "gazebo_lite, unless its <gazebo reference> sets <preserveFixedJoint> or " +
                                      "<disableFixedJointLumping>");
  fail(tag, "no movable joint named '" + j + "'");
}

std::string PluginParams::link(const std::string& tag, const std::string& def) const
{
  const std::string l = scopedLink(c_, def.empty() ? requiredStr(tag) : str(tag, def));
  if (!c_.robot->hasLink(l))
    fail(tag, "no link named '" + l + "'");
  return l;
}

btTransform PluginParams::pose(const std::string& tag) const
{
  const XmlNode* n = node(tag);
  if (!n)
    return btTransform::getIdentity();
  try
  {
    return parsePose6(n->text, "pose");
  }
  catch (const LoadError& e)
  {
    fail(tag, e.what());
  }
}

std::string PluginParams::topic(const std::string& tag, const std::string& def) const
{
  const std::string t = str(tag, def);
  checkTopic(tag, t);
  return t;
}

void PluginParams::checkTopic(const std::string& tag, const std::string& topic) const
{
  std::string why;
  if (topic.find_first_not_of("/~") == std::string::npos)  // "", "/": no topic the master takes
    fail(tag, "'" + topic + "' names no topic");
  if (!ros::names::validate(topic, why))
    fail(tag, "'" + topic + "' is not a ROS name: " + why);
}

double PluginParams::parse(const std::string& tag, const std::string& t) const
{
  char* end = nullptr;
  double d = std::strtod(t.c_str(), &end);
  if (t.empty() || *end != '\0' || !std::isfinite(d))
    fail(tag, "expected a number, got '" + t + "'");
  return d;
}
std::string resolveFrame(const PluginContext& c, std::string f)
{
  while (!f.empty() && f[0] == '/')
    f.erase(0, 1);
  return c.tf_prefix.empty() ? f : c.tf_prefix + "/" + f;
}

btVector3 addNoise(btVector3 v, std::normal_distribution<double>& noise, std::mt19937& rng)
{
  if (noise.stddev() > 0)
    for (int i = 0; i < 3; ++i)
      v[i] += noise(rng);
  return v;
}

geometry_msgs::Vector3 toMsg(const btVector3& v)
{
  geometry_msgs::Vector3 m;
  m.x = v.x();
  m.y = v.y();
  m.z = v.z();
  return m;
}

geometry_msgs::Quaternion toMsg(const btQuaternion& q)
{
  geometry_msgs::Quaternion m;
  m.x = q.x();
  m.y = q.y();
  m.z = q.z();
  m.w = q.w();
  return m;
}

void toMsg(const btTransform& tf, geometry_msgs::Pose& p)
{
  p.position.x = tf.getOrigin().x();
  p.position.y = tf.getOrigin().y();
  p.position.z = tf.getOrigin().z();
  p.orientation = toMsg(tf.getRotation());
}

geometry_msgs::Twist twistMsg(const Pose& s)
{
  geometry_msgs::Twist t;
  t.linear = toMsg(s.linear);
  t.angular = toMsg(s.angular);
  return t;
}

geometry_msgs::TransformStamped toTf(const btTransform& tf, double t, const std::string& parent,
                                     const std::string& child)
{
  geometry_msgs::TransformStamped m;
  m.header.stamp = ros::Time(t);
  m.header.frame_id = parent;
  m.child_frame_id = child;
  m.transform.translation = toMsg(tf.getOrigin());
  m.transform.rotation = toMsg(tf.getRotation());
  return m;
}

RayScan RayScan::read(const PluginParams& s, int horizontal_samples)
{
  RayScan r;
  const double hs = s.num("ray/scan/horizontal/samples", horizontal_samples);
  const double vs = s.num("ray/scan/vertical/samples", 1);
  if (!(hs >= 1 && vs >= 1 && hs == std::floor(hs) && vs == std::floor(vs) && hs * vs <= 100000))
    s.fail("ray/scan", "need whole numbers of samples, 1 to 100000 rays (horizontal x vertical)");
  r.horizontal = static_cast<int>(hs);
  r.vertical = static_cast<int>(vs);
  r.hmin = s.num("ray/scan/horizontal/min_angle", 0.0);
  r.hmax = s.num("ray/scan/horizontal/max_angle", 0.0);
  r.vmin = s.num("ray/scan/vertical/min_angle", 0.0);
  r.vmax = s.num("ray/scan/vertical/max_angle", 0.0);
  for (const char* axis : {"horizontal", "vertical"})
  {
    const bool h = axis[0] == 'h';
    const double lo = h ? r.hmin : r.vmin, hi = h ? r.hmax : r.vmax;
    if (hi < lo)
      s.fail(std::string("ray/scan/") + axis + "/max_angle", "smaller than min_angle");
    if (!std::isfinite(hi - lo))  // 1e308 and -1e308: every ray's angle would be inf
      s.fail(std::string("ray/scan/") + axis + "/max_angle", "max_angle - min_angle must be finite");
  }
  r.range_min = s.requiredNum("ray/range/min");
  r.range_max = s.requiredNum("ray/range/max");
  if (r.range_min < 0 || r.range_max <= r.range_min)
    s.fail("ray/range/max", "need 0 <= min < max");
  return r;
}

SensorRays SensorRays::fromSensor(const PluginParams& s)
{
  const RayScan scan = RayScan::read(s, 1);
  SensorRays r;
  r.min = scan.range_min;
  r.max = scan.range_max;
  const int nh = scan.horizontal, nv = scan.vertical;
  for (int v = 0; v < nv; ++v)
    for (int h = 0; h < nh; ++h)
    {
      const double a = nh > 1 ? scan.hmin + h * (scan.hmax - scan.hmin) / (nh - 1) : scan.hmin;
      const double e = nv > 1 ? scan.vmin + v * (scan.vmax - scan.vmin) / (nv - 1) : scan.vmin;
      r.dirs.emplace_back(std::cos(e) * std::cos(a), std::cos(e) * std::sin(a), std::sin(e));
    }
  return r;
}

double SensorRays::nearest(const PhysicsWorld& world, const btTransform& sensor, const Robot* self) const
{
  double out = max;
  for (double d : cast(world, sensor, self))
    out = std::min(out, d);
  return out;
}

std::vector<double> SensorRays::cast(const PhysicsWorld& world, const btTransform& sensor, const Robot* self) const
{
  std::vector<double> out;
  out.reserve(dirs.size());
  for (const btVector3& d : dirs)
  {
    const double hit = world.rayTest(sensor * (d * min), sensor * (d * max), self);
    out.push_back(hit >= 0 ? min + hit : max);
  }
  return out;
}

TwistCommand::TwistCommand(const PluginContext& c, ros::NodeHandle& nh, const std::string& topic, double timeout)
    : c_(c), timeout_(timeout)
{
  sub_ = subscribeCommand<geometry_msgs::Twist>(
      c, nh, topic,
      [this](const geometry_msgs::Twist::ConstPtr& m)
      {
        if (!std::isfinite(m->linear.x) || !std::isfinite(m->linear.y) || !std::isfinite(m->angular.z))
        {
          ROS_WARN_THROTTLE(1.0, "%s: ignoring non-finite cmd_vel", c_.robot->name().c_str());
          return;
        }
        cmd_ = *m;
        stamp_ = c_.world->time();
        have_ = true;
      });
}

const geometry_msgs::Twist& TwistCommand::at(double t)
{
  if (have_ && timeout_ > 0 && t - stamp_ > timeout_)
    reset();
  return cmd_;
}

void TwistCommand::reset()
{
  cmd_ = geometry_msgs::Twist();
  have_ = false;
}

nav_msgs::Odometry worldPoseOdometry(const PluginContext& c, double t, const std::string& odom_frame,
                                     const std::string& base_frame, const double cov[3])
{
  const Pose s = c.robot->linkState(c.robot->spec().root);
  nav_msgs::Odometry o;
  o.header.stamp = ros::Time(t);
  o.header.frame_id = odom_frame;
  o.child_frame_id = base_frame;
  toMsg(s.tf, o.pose.pose);
  btScalar yaw, pitch, roll;
  s.tf.getBasis().getEulerZYX(yaw, pitch, roll);
  o.twist.twist.linear.x = std::cos(yaw) * s.linear.x() + std::sin(yaw) * s.linear.y();
  o.twist.twist.linear.y = std::cos(yaw) * s.linear.y() - std::sin(yaw) * s.linear.x();
  o.twist.twist.angular.z = s.angular.z();
  for (auto* m : {&o.pose.covariance, &o.twist.covariance})
  {
    (*m)[0] = cov[0];
    (*m)[7] = cov[1];
    (*m)[14] = (*m)[21] = (*m)[28] = 1e6;  // z, roll, pitch: not estimated
    (*m)[35] = cov[2];
  }
  return o;
}

WheelDriveOutputs::WheelDriveOutputs(const PluginContext& c, const PluginParams& p, ros::NodeHandle& nh,
                                     const std::string& base_default, std::vector<std::string> joints)
    : c_(&c), joints_(std::move(joints))
{
  odom_frame_ = resolveFrame(c, p.str("odometryFrame", "odom"));
  base_frame_ = resolveFrame(c, p.str("robotBaseFrame", base_default));
  wheel_tf_ = p.boolean("publishWheelTF", false);
  wheel_js_ = p.boolean("publishWheelJointState", false);
  odom_pub_ = p.advertise<nav_msgs::Odometry>(nh, "odometryTopic", p.str("odometryTopic", "odom"), 1);
  if (wheel_js_)
    js_pub_ = p.advertise<sensor_msgs::JointState>(nh, "publishWheelJointState", "joint_states", 1);
}

void WheelDriveOutputs::publish(double t, const EncoderOdometry* encoder) const
{
  const PluginContext& c = *c_;
  nav_msgs::Odometry o;
  o.header.stamp = ros::Time(t);
  o.header.frame_id = odom_frame_;
  o.child_frame_id = base_frame_;
  btTransform pose;
  if (encoder)
  {
    btQuaternion q;
    q.setEulerZYX(encoder->theta, 0, 0);
    pose = btTransform(q, btVector3(encoder->x, encoder->y, 0));
    o.twist.twist.linear.x = encoder->v;
    o.twist.twist.angular.z = encoder->w;
  }
  else
  {
    Pose s = c.robot->linkState(c.robot->spec().root);
    pose = s.tf;
    btScalar yaw, pitch, roll;
    pose.getBasis().getEulerZYX(yaw, pitch, roll);
    o.twist.twist.linear.x = std::cos(yaw) * s.linear.x() + std::sin(yaw) * s.linear.y();
    o.twist.twist.linear.y = std::cos(yaw) * s.linear.y() - std::sin(yaw) * s.linear.x();
    o.twist.twist.angular.z = s.angular.z();
  }
  toMsg(pose, o.pose.pose);
  o.pose.covariance[0] = o.pose.covariance[7] = 0.00001;
  o.pose.covariance[14] = o.pose.covariance[21] = o.pose.covariance[28] = 1e12;
  o.pose.covariance[35] = 0.001;
  if (odom_msg)
    odom_pub_.publish(o);
  if (odom_tf)
    c.tf->sendTransform(toTf(pose, t, odom_frame_, base_frame_));
  if (!wheel_tf_ && !wheel_js_)
    return;
  sensor_msgs::JointState js;
  js.header.stamp = ros::Time(t);
  for (const std::string& j : joints_)
  {
    const JointSpec* spec = c.robot->joint(j).spec;
    if (wheel_tf_)
    {
      btTransform rel = c.robot->linkPose(spec->parent).inverse() * c.robot->linkPose(spec->child);
      c.tf->sendTransform(toTf(rel, t, resolveFrame(c, spec->parent), resolveFrame(c, spec->child)));
    }
    js.name.push_back(j);
    js.position.push_back(c.robot->jointPosition(j));
    js.velocity.push_back(c.robot->jointVelocity(j));
  }
  if (wheel_js_)
    js_pub_.publish(js);
}

}  // namespace mybot_gazebo_lite
