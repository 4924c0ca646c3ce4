#include "plugins.h"

#include "mybot_gazebo_lite/kinematics.h"
#include "mybot_gazebo_lite/parsing.h"

#include <geometry_msgs/Twist.h>
#include <nav_msgs/Odometry.h>
#include <sensor_msgs/CameraInfo.h>
#include <sensor_msgs/Image.h>
#include <sensor_msgs/Imu.h>
#include <sensor_msgs/JointState.h>
#include <sensor_msgs/LaserScan.h>
#include <sensor_msgs/PointCloud2.h>
#include <std_msgs/Float64.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstring>
#include <limits>
#include <map>
#include <set>
#include <sstream>

namespace mybot_gazebo_lite {

const RayCaster2D& StaticSliceCache::at(double z) {
  long key = std::lround(z * 100.0);  // 1 cm bins
  auto it = cache_.find(key);
  if (it == cache_.end())
    it = cache_.emplace(key, std::make_unique<RayCaster2D>(sliceWorld(world_, key / 100.0))).first;
  return *it->second;
}

const PrismScene& StaticSliceCache::prisms() {
  if (!prisms_) prisms_ = std::make_unique<PrismScene>(world_);
  return *prisms_;
}

namespace {

// Reads plugin/sensor parameters; every error names tag, link and file.
class Params {
 public:
  Params(const PluginContext& c, const XmlNode& x) : c_(c), x_(x) {}
  [[noreturn]] void fail(const std::string& tag, const std::string& msg) const {
    std::ostringstream os;
    os << c_.robot->spec().source << ": plugin '" << c_.spec->name << "' (" << c_.spec->filename << ")";
    if (!c_.spec->reference.empty()) os << " on link '" << c_.spec->reference << "'";
    os << ": <" << tag << ">: " << msg;
    throw LoadError(os.str());
  }
  const XmlNode* node(const std::string& path) const {
    const XmlNode* n = &x_;
    std::stringstream ss(path);
    std::string part;
    while (n && std::getline(ss, part, '/')) n = n->child(part);
    return n;
  }
  bool has(const std::string& tag) const { return node(tag) != nullptr; }
  std::string str(const std::string& tag, const std::string& def) const {
    const XmlNode* n = node(tag);
    return n ? n->text : def;
  }
  std::string requiredStr(const std::string& tag) const {
    const XmlNode* n = node(tag);
    if (!n || n->text.empty()) fail(tag, "required parameter missing");
    return n->text;
  }
  double num(const std::string& tag, double def) const {
    const XmlNode* n = node(tag);
    if (!n) return def;
    return parse(tag, n->text);
  }
  double requiredNum(const std::string& tag) const {
    const XmlNode* n = node(tag);
    if (!n) fail(tag, "required parameter missing");
    return parse(tag, n->text);
  }
  bool boolean(const std::string& tag, bool def) const {
    const XmlNode* n = node(tag);
    if (!n) return def;
    if (n->text == "true" || n->text == "1") return true;
    if (n->text == "false" || n->text == "0") return false;
    fail(tag, "expected true/false, got '" + n->text + "'");
  }
  std::string joint(const std::string& tag, const std::string& def) const {
    std::string j = str(tag, def);
    if (!c_.robot->hasJoint(j)) fail(tag, "no movable joint named '" + j + "'");
    return j;
  }
  btTransform pose(const std::string& tag) const {
    const XmlNode* n = node(tag);
    if (!n) return btTransform::getIdentity();
    try {
      return parsePose6(n->text, "pose");
    } catch (const LoadError& e) {
      fail(tag, e.what());
    }
  }

 private:
  double parse(const std::string& tag, const std::string& t) const {
    char* end = nullptr;
    double d = std::strtod(t.c_str(), &end);
    if (t.empty() || *end != '\0' || !std::isfinite(d)) fail(tag, "expected a number, got '" + t + "'");
    return d;
  }
  const PluginContext& c_;
  const XmlNode& x_;
};

std::string resolveFrame(const PluginContext& c, std::string f) {
  while (!f.empty() && f[0] == '/') f.erase(0, 1);
  return c.tf_prefix.empty() ? f : c.tf_prefix + "/" + f;
}

// Fires at a fixed sim-time period (0 = every step).
// Fires at a fixed sim-time period (0 = every step). Time going backwards (reset_simulation
// sends the clock back, as Gazebo does) starts it over: the next step fires.
struct Rate {
  double period = 0, next = 0, last = -1;
  explicit Rate(double hz = 0) : period(hz > 0 ? 1.0 / hz : 0) {}
  bool due(double t) {
    if (period <= 0) return true;
    if (t < last) next = t;
    if (t + 1e-9 < next) return false;
    last = t;
    next = (next + period < t) ? t + period : next + period;
    return true;
  }
};

void toMsg(const btTransform& tf, geometry_msgs::Pose& p) {
  p.position.x = tf.getOrigin().x();
  p.position.y = tf.getOrigin().y();
  p.position.z = tf.getOrigin().z();
  btQuaternion q = tf.getRotation();
  p.orientation.x = q.x();
  p.orientation.y = q.y();
  p.orientation.z = q.z();
  p.orientation.w = q.w();
}

geometry_msgs::TransformStamped toTf(const btTransform& tf, double t, const std::string& parent, const std::string& child) {
  geometry_msgs::TransformStamped m;
  m.header.stamp = ros::Time(t);
  m.header.frame_id = parent;
  m.child_frame_id = child;
  m.transform.translation.x = tf.getOrigin().x();
  m.transform.translation.y = tf.getOrigin().y();
  m.transform.translation.z = tf.getOrigin().z();
  btQuaternion q = tf.getRotation();
  m.transform.rotation.x = q.x();
  m.transform.rotation.y = q.y();
  m.transform.rotation.z = q.z();
  m.transform.rotation.w = q.w();
  return m;
}

// ------------------------------------------------ libgazebo_ros_diff_drive.so
class DiffDrive : public SimPlugin {
 public:
  explicit DiffDrive(const PluginContext& c) : c_(c) {
    Params p(c, c.spec->xml);
    ros::NodeHandle nh(c.ns);
    left_ = p.joint("leftJoint", "left_joint");
    right_ = p.joint("rightJoint", "right_joint");
    geo_.separation = p.num("wheelSeparation", 0.34);
    geo_.diameter = p.num("wheelDiameter", 0.15);
    if (!(geo_.separation > 0)) p.fail("wheelSeparation", "must be positive");
    if (!(geo_.diameter > 0)) p.fail("wheelDiameter", "must be positive");
    if (!p.has("legacyMode"))
      ROS_WARN("%s: diff_drive plugin missing <legacyMode>, defaults to true (left/right swapped, as in gazebo_ros)",
               c.robot->name().c_str());
    geo_.legacy = p.boolean("legacyMode", true);
    accel_ = p.num("wheelAcceleration", 0.0);
    torque_ = p.num("wheelTorque", 5.0);
    if (accel_ < 0) p.fail("wheelAcceleration", "must be >= 0");
    if (!(torque_ > 0)) p.fail("wheelTorque", "must be positive");
    rate_ = Rate(p.num("updateRate", 100.0));
    timeout_ = p.num("commandTimeout", 0.5);
    if (timeout_ < 0) p.fail("commandTimeout", "must be >= 0");
    std::string src = p.str("odometrySource", "world");
    if (src == "encoder" || src == "0")
      encoder_ = true;
    else if (src != "world" && src != "1")
      p.fail("odometrySource", "expected 'encoder' or 'world', got '" + src + "'");
    publish_odom_tf_ = p.boolean("publishOdomTF", true);
    publish_wheel_tf_ = p.boolean("publishWheelTF", false);
    publish_wheel_js_ = p.boolean("publishWheelJointState", false);
    odom_frame_ = resolveFrame(c, p.str("odometryFrame", "odom"));
    base_frame_ = resolveFrame(c, p.str("robotBaseFrame", "base_footprint"));
    base_link_ = p.str("robotBaseFrame", "base_footprint");
    if (!c.robot->hasLink(base_link_)) base_link_ = c.robot->spec().root;
    sub_ = subscribeCommand<geometry_msgs::Twist>(c, nh, p.str("commandTopic", "cmd_vel"),
                                                  [this](const geometry_msgs::Twist::ConstPtr& m) { onCmd(m); });
    odom_pub_ = nh.advertise<nav_msgs::Odometry>(p.str("odometryTopic", "odom"), 1);
    if (publish_wheel_js_) js_pub_ = nh.advertise<sensor_msgs::JointState>("joint_states", 1);
    hold();
  }
  void onCmd(const geometry_msgs::Twist::ConstPtr& m) {
    if (!std::isfinite(m->linear.x) || !std::isfinite(m->angular.z)) {
      ROS_WARN_THROTTLE(1.0, "%s: ignoring non-finite cmd_vel", c_.robot->name().c_str());
      return;
    }
    x_ = m->linear.x;
    rot_ = m->angular.z;
    last_cmd_ = c_.world->time();
    have_cmd_ = true;
  }
  void reset() override {
    odo_ = EncoderOdometry();
    x_ = rot_ = 0;
    instr_[0] = instr_[1] = 0;
    hold();
  }
  void update(double t) override {
    double dt = c_.world->stepSize();
    odo_.update(c_.robot->jointVelocity(left_), c_.robot->jointVelocity(right_), dt, geo_);
    if (!rate_.due(t)) return;
    if (have_cmd_ && timeout_ > 0 && t - last_cmd_ > timeout_) {
      x_ = rot_ = 0;
      have_cmd_ = false;
    }
    publishOdometry(t);
    auto [vl, vr] = diffDriveWheelSpeeds(x_, rot_, geo_);
    double r = geo_.diameter / 2;
    double period = rate_.period > 0 ? rate_.period : dt;
    double target[2] = {vl, vr};
    const std::string* joints[2] = {&left_, &right_};
    for (int i = 0; i < 2; ++i) {
      double cur = c_.robot->jointVelocity(*joints[i]) * r;
      instr_[i] = accel_ > 0 ? rampWheelSpeed(instr_[i], target[i], cur, accel_, period) : target[i];
      c_.robot->commandVelocity(*joints[i], instr_[i] / r, torque_);
    }
  }

 private:
  void hold() {
    c_.robot->commandVelocity(left_, 0, torque_);
    c_.robot->commandVelocity(right_, 0, torque_);
  }
  void publishOdometry(double t) {
    nav_msgs::Odometry o;
    o.header.stamp = ros::Time(t);
    o.header.frame_id = odom_frame_;
    o.child_frame_id = base_frame_;
    btTransform pose;
    if (encoder_) {
      btQuaternion q;
      q.setEulerZYX(odo_.theta, 0, 0);
      pose = btTransform(q, btVector3(odo_.x, odo_.y, 0));
      o.twist.twist.linear.x = odo_.v;
      o.twist.twist.angular.z = odo_.w;
    } else {
      Pose s = c_.robot->linkState(c_.robot->spec().root);
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
    odom_pub_.publish(o);
    if (publish_odom_tf_) c_.tf->sendTransform(toTf(pose, t, odom_frame_, base_frame_));
    if (publish_wheel_tf_ || publish_wheel_js_) {
      sensor_msgs::JointState js;
      js.header.stamp = ros::Time(t);
      for (const std::string* j : {&left_, &right_}) {
        const JointSpec* spec = c_.robot->joint(*j).spec;
        if (publish_wheel_tf_) {
          btTransform rel = c_.robot->linkState(spec->parent).tf.inverse() * c_.robot->linkState(spec->child).tf;
          c_.tf->sendTransform(toTf(rel, t, resolveFrame(c_, spec->parent), resolveFrame(c_, spec->child)));
        }
        js.name.push_back(*j);
        js.position.push_back(c_.robot->jointPosition(*j));
        js.velocity.push_back(c_.robot->jointVelocity(*j));
      }
      if (publish_wheel_js_) js_pub_.publish(js);
    }
  }
  PluginContext c_;
  std::string left_, right_, odom_frame_, base_frame_, base_link_;
  DiffDriveGeometry geo_;
  double accel_, torque_, timeout_;
  bool encoder_ = false, publish_odom_tf_, publish_wheel_tf_, publish_wheel_js_;
  Rate rate_;
  double x_ = 0, rot_ = 0, last_cmd_ = 0, instr_[2] = {0, 0};
  bool have_cmd_ = false;
  EncoderOdometry odo_;
  ros::Subscriber sub_;
  ros::Publisher odom_pub_, js_pub_;
};

// ------------------------------------------------ libgazebo_ros_p3d.so
class P3D : public SimPlugin {
 public:
  explicit P3D(const PluginContext& c) : c_(c), noise_(0, 1) {
    Params p(c, c.spec->xml);
    body_ = p.requiredStr("bodyName");
    if (!c.robot->hasLink(body_)) p.fail("bodyName", "no link named '" + body_ + "'");
    std::string topic = p.requiredStr("topicName");
    frame_ = p.str("frameName", "world");
    if (frame_ != "world" && frame_ != "/world" && frame_ != "map" && frame_ != "/map")
      p.fail("frameName", "only the world frame is supported, got '" + frame_ + "'");
    while (!frame_.empty() && frame_[0] == '/') frame_.erase(0, 1);
    rate_ = Rate(p.num("updateRate", 0.0));
    gn_ = p.num("gaussianNoise", 0.0);
    btVector3 xyz(0, 0, 0), rpy(0, 0, 0);
    try {
      if (p.has("xyzOffsets")) xyz = parseVec3(p.str("xyzOffsets", ""), "xyzOffsets");
      if (p.has("rpyOffsets")) rpy = parseVec3(p.str("rpyOffsets", ""), "rpyOffsets");
    } catch (const LoadError& e) {
      p.fail("xyzOffsets/rpyOffsets", e.what());
    }
    offset_ = makeTransform(xyz, rpy);
    pub_ = ros::NodeHandle(c.ns).advertise<nav_msgs::Odometry>(topic, 10);
  }
  void update(double t) override {
    if (!rate_.due(t)) return;
    Pose s = c_.robot->linkState(body_);
    nav_msgs::Odometry o;
    o.header.stamp = ros::Time(t);
    o.header.frame_id = frame_;
    o.child_frame_id = resolveFrame(c_, body_);
    btTransform pose = offset_ * s.tf;
    auto n = [&]() { return gn_ > 0 ? gn_ * noise_(*c_.rng) : 0.0; };
    pose.setOrigin(pose.getOrigin() + btVector3(n(), n(), n()));
    toMsg(pose, o.pose.pose);
    o.twist.twist.linear.x = s.linear.x() + n();
    o.twist.twist.linear.y = s.linear.y() + n();
    o.twist.twist.linear.z = s.linear.z() + n();
    o.twist.twist.angular.x = s.angular.x() + n();
    o.twist.twist.angular.y = s.angular.y() + n();
    o.twist.twist.angular.z = s.angular.z() + n();
    for (int i = 0; i < 6; ++i) o.pose.covariance[i * 7] = o.twist.covariance[i * 7] = gn_ * gn_;
    pub_.publish(o);
  }

 private:
  PluginContext c_;
  std::string body_, frame_;
  Rate rate_;
  double gn_;
  btTransform offset_;
  std::normal_distribution<double> noise_;
  ros::Publisher pub_;
};

// ------------------------------------------------ libgazebo_ros_joint_state_publisher.so
class JointStatePub : public SimPlugin {
 public:
  explicit JointStatePub(const PluginContext& c) : c_(c) {
    Params p(c, c.spec->xml);
    if (p.has("jointName")) {
      std::stringstream ss(p.str("jointName", ""));
      std::string j;
      while (std::getline(ss, j, ',')) {
        j.erase(0, j.find_first_not_of(" \t\n"));
        j.erase(j.find_last_not_of(" \t\n") + 1);
        if (j.empty()) continue;
        if (!c.robot->hasJoint(j)) p.fail("jointName", "no movable joint named '" + j + "'");
        joints_.push_back(j);
      }
    } else {
      joints_ = c.robot->movableJoints();
    }
    rate_ = Rate(p.num("updateRate", 100.0));
    pub_ = ros::NodeHandle(c.ns).advertise<sensor_msgs::JointState>("joint_states", 10);
  }
  void update(double t) override {
    if (!rate_.due(t)) return;
    sensor_msgs::JointState js;
    js.header.stamp = ros::Time(t);
    js.name = joints_;
    for (const auto& j : joints_) {
      js.position.push_back(c_.robot->jointPosition(j));
      js.velocity.push_back(c_.robot->jointVelocity(j));
    }
    pub_.publish(js);
  }

 private:
  PluginContext c_;
  std::vector<std::string> joints_;
  Rate rate_;
  ros::Publisher pub_;
};

// ------------------------------------------------ libmybot_joint_command.so (ours)
class JointCommand : public SimPlugin {
 public:
  explicit JointCommand(const PluginContext& c) : c_(c) {
    Params p(c, c.spec->xml);
    timeout_ = p.num("commandTimeout", 0.5);
    if (timeout_ < 0) p.fail("commandTimeout", "must be >= 0");
    ros::NodeHandle nh(c.ns);
    auto blocks = c.spec->xml.all("joint");
    if (blocks.empty()) p.fail("joint", "at least one <joint> block is required");
    for (const XmlNode* b : blocks) {
      Params jp(c, *b);
      auto e = std::make_unique<Entry>();
      e->name = jp.requiredStr("name");
      if (!c.robot->hasJoint(e->name)) jp.fail("joint/name", "no movable joint named '" + e->name + "'");
      std::string type = jp.requiredStr("type");
      if (type == "velocity")
        e->position = false;
      else if (type == "position")
        e->position = true;
      else
        jp.fail("joint/type", "expected 'velocity' or 'position', got '" + type + "'");
      double urdf_effort = c.robot->joint(e->name).spec->effort;
      e->effort = jp.num("effortLimit", urdf_effort);
      if (!(e->effort > 0))
        jp.fail("joint/effortLimit", "must be positive (URDF <limit effort> of '" + e->name + "' is " +
                                         std::to_string(urdf_effort) + ")");
      // Motor strength relative to the command: 0.8 models a worn motor 20% weaker.
      e->gain = jp.num("gain", 1.0);
      if (!(e->gain > 0)) jp.fail("joint/gain", "must be positive");
      Entry* raw = e.get();
      e->sub = subscribeCommand<std_msgs::Float64>(c, nh, jp.str("topicName", e->name + "/command"),
                                                   [this, raw](const std_msgs::Float64::ConstPtr& m) { onCmd(raw, m->data); });
      entries_.push_back(std::move(e));
    }
    reset();
  }
  void reset() override {
    for (auto& e : entries_) {
      e->target = e->position ? c_.robot->jointPosition(e->name) : 0.0;
      e->have = false;
      apply(*e);
    }
  }
  void update(double t) override {
    if (timeout_ <= 0) return;
    for (auto& e : entries_)
      if (e->have && !e->position && t - e->stamp > timeout_) {
        e->target = 0;  // a velocity joint whose commands stop must stop
        e->have = false;
        apply(*e);
      }
  }

 private:
  struct Entry {
    std::string name;
    bool position = false, have = false;
    double effort = 0, target = 0, stamp = 0, gain = 1;
    ros::Subscriber sub;
  };
  void onCmd(Entry* e, double v) {
    if (!std::isfinite(v)) {
      ROS_WARN_THROTTLE(1.0, "%s: ignoring non-finite command for joint '%s'", c_.robot->name().c_str(), e->name.c_str());
      return;
    }
    e->target = v;
    e->stamp = c_.world->time();
    e->have = true;
    apply(*e);
  }
  void apply(const Entry& e) {
    if (e.position)
      c_.robot->commandPosition(e.name, e.target, e.effort);
    else
      c_.robot->commandVelocity(e.name, e.gain * e.target, e.effort);
  }
  PluginContext c_;
  double timeout_;
  std::vector<std::unique_ptr<Entry>> entries_;
};

// ------------------------------------------------ libgazebo_ros_laser.so / gpu_laser
class Laser : public SimPlugin {
 public:
  explicit Laser(const PluginContext& c) : c_(c), noise_(0, 1) {
    Params p(c, c.spec->xml);
    if (!c.spec->has_sensor) p.fail("sensor", "the laser plugin must sit inside a <sensor type=\"ray\">");
    Params s(c, c.spec->sensor);
    link_ = c.spec->reference;
    sensor_pose_ = s.pose("pose");
    rate_ = Rate(s.num("update_rate", 0.0));
    samples_ = static_cast<int>(s.num("ray/scan/horizontal/samples", 640));
    if (samples_ < 1) s.fail("ray/scan/horizontal/samples", "must be >= 1");
    amin_ = s.num("ray/scan/horizontal/min_angle", 0.0);
    amax_ = s.num("ray/scan/horizontal/max_angle", 0.0);
    if (amax_ < amin_) s.fail("ray/scan/horizontal/max_angle", "smaller than min_angle");
    rmin_ = s.requiredNum("ray/range/min");
    rmax_ = s.requiredNum("ray/range/max");
    if (rmin_ < 0 || rmax_ <= rmin_) s.fail("ray/range/max", "need 0 <= min < max");
    mean_ = s.num("ray/noise/mean", 0.0);
    stddev_ = s.num("ray/noise/stddev", 0.0);
    if (stddev_ < 0) s.fail("ray/noise/stddev", "must be >= 0");
    // gazebo_ros_laser's defaults for both.
    frame_ = resolveFrame(c, p.str("frameName", "/world"));
    std::string topic = p.str("topicName", "/world");
    pub_ = ros::NodeHandle(c.ns).advertise<sensor_msgs::LaserScan>(topic, 1);
    inc_ = samples_ > 1 ? (amax_ - amin_) / (samples_ - 1) : 0.0;
    for (int i = 0; i < samples_; ++i) {
      cos_.push_back(std::cos(amin_ + i * inc_));
      sin_.push_back(std::sin(amin_ + i * inc_));
    }
  }
  void update(double t) override {
    if (!rate_.due(t)) return;
    btTransform tf = c_.robot->linkState(link_).tf * sensor_pose_;
    const btVector3 o = tf.getOrigin();
    btScalar yaw, pitch, roll;
    tf.getBasis().getEulerZYX(yaw, pitch, roll);
    const double cy = std::cos(yaw), sy = std::sin(yaw);
    const RayCaster2D& caster = c_.slices->at(o.z());
    ranges_.resize(samples_);
    for (int i = 0; i < samples_; ++i) {
      double dx = cy * cos_[i] - sy * sin_[i], dy = sy * cos_[i] + cy * sin_[i];
      ranges_[i] = caster.cast(o.x(), o.y(), dx, dy, rmax_);
    }
    // Robots and dynamic bodies: Bullet ray tests only for beams that can reach them.
    for (const auto& ob : c_.world->dynamicObstacles(c_.robot)) {
      if (o.z() < ob.zmin || o.z() > ob.zmax) continue;
      double ddx = ob.center.x() - o.x(), ddy = ob.center.y() - o.y();
      double dist = std::hypot(ddx, ddy);
      if (dist - ob.radius > rmax_) continue;
      double half = dist <= ob.radius ? M_PI : std::asin(ob.radius / dist);
      double bearing = std::atan2(ddy, ddx) - yaw;
      for (int i = 0; i < samples_; ++i) {
        double a = std::remainder(amin_ + i * inc_ - bearing, 2 * M_PI);
        if (std::abs(a) > half) continue;
        double dx = cy * cos_[i] - sy * sin_[i], dy = sy * cos_[i] + cy * sin_[i];
        double reach = std::min(ranges_[i], rmax_);
        double d = c_.world->rayTestObject(ob.object, o, o + btVector3(dx, dy, 0) * reach);
        if (d >= 0 && d < ranges_[i]) ranges_[i] = d;
      }
    }
    sensor_msgs::LaserScan m;
    m.header.stamp = ros::Time(t);
    m.header.frame_id = frame_;
    m.angle_min = amin_;
    m.angle_max = amax_;
    m.angle_increment = inc_;
    m.range_min = rmin_;
    m.range_max = rmax_;
    m.ranges.resize(samples_);
    m.intensities.assign(samples_, 0.0f);
    for (int i = 0; i < samples_; ++i) {
      double n = stddev_ > 0 ? mean_ + stddev_ * noise_(*c_.rng) : mean_;
      m.ranges[i] = static_cast<float>(laserRange(ranges_[i], rmin_, rmax_, n));
    }
    pub_.publish(m);
  }

 private:
  PluginContext c_;
  std::string link_, frame_;
  btTransform sensor_pose_;
  Rate rate_;
  int samples_;
  double amin_, amax_, inc_, rmin_, rmax_, mean_, stddev_;
  std::vector<double> cos_, sin_, ranges_;
  std::normal_distribution<double> noise_;
  ros::Publisher pub_;
};

// ------------------------------------------------ IMU (sensor and model plugin)
class Imu : public SimPlugin {
 public:
  Imu(const PluginContext& c, bool sensor_plugin) : c_(c), noise_(0, 1) {
    Params p(c, c.spec->xml);
    if (sensor_plugin) {
      if (!c.spec->has_sensor) p.fail("sensor", "libgazebo_ros_imu_sensor.so must sit inside a <sensor type=\"imu\">");
      Params s(c, c.spec->sensor);
      body_ = p.str("bodyName", c.spec->reference);
      sensor_pose_ = s.pose("pose");
      rate_ = Rate(p.num("updateRateHZ", s.num("update_rate", 1.0)));
    } else {
      body_ = p.requiredStr("bodyName");
      rate_ = Rate(p.num("updateRate", 0.0));
    }
    if (!c.robot->hasLink(body_)) p.fail("bodyName", "no link named '" + body_ + "'");
    frame_ = resolveFrame(c, p.str("frameName", body_));
    gn_ = p.num("gaussianNoise", 0.0);
    if (gn_ < 0) p.fail("gaussianNoise", "must be >= 0");
    pub_ = ros::NodeHandle(c.ns).advertise<sensor_msgs::Imu>(p.str("topicName", "imu"), 10);
  }
  void reset() override { have_prev_ = false; }
  void update(double t) override {
    Pose s = c_.robot->linkState(body_);
    btTransform tf = s.tf * sensor_pose_;
    btVector3 v = s.linear + s.angular.cross(tf.getOrigin() - s.tf.getOrigin());
    if (have_prev_) accel_ = (v - prev_v_) / c_.world->stepSize();
    prev_v_ = v;
    have_prev_ = true;
    if (!rate_.due(t)) return;
    const btMatrix3x3& R = tf.getBasis();
    btVector3 w = R.transpose() * s.angular;
    btVector3 a = R.transpose() * (accel_ - c_.world->worldSpec().gravity);
    auto n = [&]() { return gn_ > 0 ? gn_ * noise_(*c_.rng) : 0.0; };
    sensor_msgs::Imu m;
    m.header.stamp = ros::Time(t);
    m.header.frame_id = frame_;
    btQuaternion q = tf.getRotation();
    m.orientation.x = q.x();
    m.orientation.y = q.y();
    m.orientation.z = q.z();
    m.orientation.w = q.w();
    m.angular_velocity.x = w.x() + n();
    m.angular_velocity.y = w.y() + n();
    m.angular_velocity.z = w.z() + n();
    m.linear_acceleration.x = a.x() + n();
    m.linear_acceleration.y = a.y() + n();
    m.linear_acceleration.z = a.z() + n();
    double var = gn_ * gn_;
    for (int i = 0; i < 3; ++i)
      m.orientation_covariance[i * 4] = m.angular_velocity_covariance[i * 4] = m.linear_acceleration_covariance[i * 4] = var;
    pub_.publish(m);
  }

 private:
  PluginContext c_;
  std::string body_, frame_;
  btTransform sensor_pose_ = btTransform::getIdentity();
  Rate rate_;
  double gn_;
  btVector3 prev_v_{0, 0, 0}, accel_{0, 0, 0};
  bool have_prev_ = false;
  std::normal_distribution<double> noise_;
  ros::Publisher pub_;
};

// ------------------------------------------------ libgazebo_ros_camera.so / libgazebo_ros_openni_kinect.so
// Renders only when someone subscribes, at the sensor's <update_rate> (and the
// plugin's <updateRate> if lower), both in sim time.
class Camera : public SimPlugin {
 public:
  Camera(const PluginContext& c, bool depth_sensor) : c_(c), depth_sensor_(depth_sensor), noise_(c.rng ? (*c.rng)() : 0) {
    Params p(c, c.spec->xml);
    if (!c.spec->has_sensor)
      p.fail("sensor", "the camera plugin must sit inside a <sensor type=\"" + std::string(depth_sensor ? "depth" : "camera") + "\">");
    Params s(c, c.spec->sensor);
    link_ = c.spec->reference;
    sensor_pose_ = s.pose("pose");
    double sensor_hz = s.num("update_rate", 0.0), plugin_hz = p.num("updateRate", 0.0);
    if (sensor_hz < 0) s.fail("update_rate", "must be >= 0");
    if (plugin_hz < 0) p.fail("updateRate", "must be >= 0");
    double hz = sensor_hz > 0 && plugin_hz > 0 ? std::min(sensor_hz, plugin_hz) : std::max(sensor_hz, plugin_hz);
    rate_ = Rate(hz);
    const double hfov = s.num("camera/horizontal_fov", 1.047);
    if (!(hfov > 0 && hfov < M_PI)) s.fail("camera/horizontal_fov", "must be in (0, pi)");
    const double w = s.num("camera/image/width", 320), h = s.num("camera/image/height", 240);
    if (w < 1 || h < 1 || w != std::floor(w) || h != std::floor(h) || w * h > 16e6)
      s.fail("camera/image", "width and height must be positive integers");
    settings_.near = s.num("camera/clip/near", 0.1);
    settings_.far = s.num("camera/clip/far", 100.0);
    if (!(settings_.near > 0 && settings_.far > settings_.near)) s.fail("camera/clip", "need 0 < near < far");
    std::string format = s.str("camera/image/format", "R8G8B8");
    if (format == "R8G8B8" || format == "RGB_INT8") {
      encoding_ = "rgb8";
    } else if (format == "B8G8R8" || format == "BGR_INT8") {
      encoding_ = "bgr8";
    } else if (format == "L8" || format == "L_INT8") {
      encoding_ = "mono8";
    } else {
      s.fail("camera/image/format", "supported: R8G8B8, B8G8R8, L8; got '" + format + "'");
    }
    noise_mean_ = s.num("camera/noise/mean", 0.0);
    noise_sd_ = s.num("camera/noise/stddev", 0.0);
    if (noise_sd_ < 0) s.fail("camera/noise/stddev", "must be >= 0");
    k_ = gazeboIntrinsics(static_cast<int>(w), static_cast<int>(h), hfov, p.num("focalLength", 0.0), p.num("Cx", 0.0),
                          p.num("Cy", 0.0));
    frame_ = resolveFrame(c, p.str("frameName", "world"));
    info_.header.frame_id = frame_;
    info_.width = k_.width;
    info_.height = k_.height;
    info_.distortion_model = "plumb_bob";
    // D = {k1, k2, t1, t2, k3}, as gazebo_ros_camera_utils orders them.
    info_.D = {p.num("distortionK1", 0.0), p.num("distortionK2", 0.0), p.num("distortionT1", 0.0),
               p.num("distortionT2", 0.0), p.num("distortionK3", 0.0)};
    info_.K = {k_.fx, 0, k_.cx, 0, k_.fy, k_.cy, 0, 0, 1};
    info_.R = {1, 0, 0, 0, 1, 0, 0, 0, 1};
    info_.P = {k_.fx, 0, k_.cx, -k_.fx * p.num("hackBaseline", 0.0), 0, k_.fy, k_.cy, 0, 0, 0, 1, 0};
    ros::NodeHandle nh(ros::NodeHandle(c.ns), p.str("cameraName", ""));
    image_pub_ = nh.advertise<sensor_msgs::Image>(p.str("imageTopicName", "image_raw"), 2);
    info_pub_ = nh.advertise<sensor_msgs::CameraInfo>(p.str("cameraInfoTopicName", "camera_info"), 2);
    if (depth_sensor) {
      cutoff_ = p.num("pointCloudCutoff", 0.4);
      cutoff_max_ = p.num("pointCloudCutoffMax", 5.0);
      if (cutoff_ < 0 || cutoff_max_ <= cutoff_) p.fail("pointCloudCutoffMax", "need 0 <= pointCloudCutoff < pointCloudCutoffMax");
      depth_pub_ = nh.advertise<sensor_msgs::Image>(p.str("depthImageTopicName", "depth/image_raw"), 2);
      depth_info_pub_ = nh.advertise<sensor_msgs::CameraInfo>(p.str("depthImageCameraInfoTopicName", "depth/camera_info"), 2);
      points_pub_ = nh.advertise<sensor_msgs::PointCloud2>(p.str("pointCloudTopicName", "points"), 2);
    }
  }
  void update(double t) override {
    const bool want_image = image_pub_.getNumSubscribers() > 0 || info_pub_.getNumSubscribers() > 0;
    const bool want_points = depth_sensor_ && points_pub_.getNumSubscribers() > 0;
    const bool want_depth = depth_sensor_ && (depth_pub_.getNumSubscribers() > 0 || depth_info_pub_.getNumSubscribers() > 0);
    if (!want_image && !want_depth && !want_points) return;  // nobody looks: costs nothing
    if (!rate_.due(t)) return;
    btTransform tf = c_.robot->linkState(link_).tf * sensor_pose_;
    btScalar yaw, pitch, roll;
    tf.getBasis().getEulerZYX(yaw, pitch, roll);
    CameraPose pose{tf.getOrigin().x(), tf.getOrigin().y(), tf.getOrigin().z(), yaw};
    const size_t n = static_cast<size_t>(k_.width) * k_.height;
    const bool need_rgb = want_image || want_points;
    rgb_.resize(need_rgb ? n * 3 : 0);
    depth_.resize(n);
    renderCamera(c_.slices->prisms(), k_, pose, settings_, need_rgb ? rgb_.data() : nullptr, depth_.data());
    const ros::Time stamp(t);
    info_.header.stamp = stamp;
    if (need_rgb && !depth_sensor_ && noise_sd_ > 0) noise_.addToBytes(rgb_.data(), rgb_.size(), noise_mean_, noise_sd_);
    if (want_image) {
      image_pub_.publish(colorImage(stamp));
      info_pub_.publish(info_);
    }
    if (!depth_sensor_) return;
    // A depth sensor's <noise> is in metres; outside the cutoffs there is no reading (NaN), as in openni_kinect.
    if (noise_sd_ > 0) noise_.addToFloats(depth_.data(), n, noise_mean_, noise_sd_);
    const float nan = std::numeric_limits<float>::quiet_NaN();
    for (float& d : depth_)
      if (!(d > cutoff_ && d < cutoff_max_)) d = nan;
    if (want_depth) {
      sensor_msgs::ImagePtr m = boost::make_shared<sensor_msgs::Image>();
      m->header.stamp = stamp;
      m->header.frame_id = frame_;
      m->width = k_.width;
      m->height = k_.height;
      m->encoding = "32FC1";
      m->step = k_.width * 4;
      m->data.resize(n * 4);
      std::memcpy(m->data.data(), depth_.data(), n * 4);
      depth_pub_.publish(m);
      depth_info_pub_.publish(info_);
    }
    if (want_points) points_pub_.publish(pointCloud(stamp));
  }

 private:
  sensor_msgs::ImagePtr colorImage(const ros::Time& stamp) const {
    sensor_msgs::ImagePtr m = boost::make_shared<sensor_msgs::Image>();
    m->header.stamp = stamp;
    m->header.frame_id = frame_;
    m->width = k_.width;
    m->height = k_.height;
    m->encoding = encoding_;
    const size_t n = static_cast<size_t>(k_.width) * k_.height;
    if (encoding_ == "mono8") {
      m->step = k_.width;
      m->data.resize(n);
      for (size_t i = 0; i < n; ++i)
        m->data[i] = static_cast<uint8_t>((299 * rgb_[3 * i] + 587 * rgb_[3 * i + 1] + 114 * rgb_[3 * i + 2]) / 1000);
    } else {
      m->step = k_.width * 3;
      m->data = rgb_;
      if (encoding_ == "bgr8")
        for (size_t i = 0; i < n; ++i) std::swap(m->data[3 * i], m->data[3 * i + 2]);
    }
    return m;
  }
  // Organised cloud in the optical convention (x right, y down, z forward), NaN where there is no reading.
  sensor_msgs::PointCloud2Ptr pointCloud(const ros::Time& stamp) const {
    sensor_msgs::PointCloud2Ptr pc = boost::make_shared<sensor_msgs::PointCloud2>();
    pc->header.stamp = stamp;
    pc->header.frame_id = frame_;
    pc->width = k_.width;
    pc->height = k_.height;
    const char* names[4] = {"x", "y", "z", "rgb"};
    for (uint32_t i = 0; i < 4; ++i) {
      sensor_msgs::PointField f;
      f.name = names[i];
      f.offset = 4 * i;
      f.datatype = sensor_msgs::PointField::FLOAT32;
      f.count = 1;
      pc->fields.push_back(f);
    }
    pc->point_step = 16;
    pc->row_step = 16 * k_.width;
    pc->is_dense = false;
    pc->data.resize(static_cast<size_t>(pc->row_step) * k_.height);
    for (int v = 0; v < k_.height; ++v)
      for (int u = 0; u < k_.width; ++u) {
        const size_t i = static_cast<size_t>(v) * k_.width + u;
        const float d = depth_[i];
        float xyz_rgb[4] = {static_cast<float>((u - k_.cx) * d / k_.fx), static_cast<float>((v - k_.cy) * d / k_.fy), d, 0};
        const uint32_t packed = (uint32_t(rgb_[3 * i]) << 16) | (uint32_t(rgb_[3 * i + 1]) << 8) | rgb_[3 * i + 2];
        std::memcpy(&xyz_rgb[3], &packed, 4);
        std::memcpy(&pc->data[i * 16], xyz_rgb, 16);
      }
    return pc;
  }
  PluginContext c_;
  bool depth_sensor_;
  std::string link_, frame_, encoding_;
  btTransform sensor_pose_;
  Rate rate_;
  CameraIntrinsics k_;
  RenderSettings settings_;
  double noise_mean_ = 0, noise_sd_ = 0, cutoff_ = 0.4, cutoff_max_ = 5.0;
  NoiseTable noise_;
  sensor_msgs::CameraInfo info_;
  std::vector<uint8_t> rgb_;
  std::vector<float> depth_;
  ros::Publisher image_pub_, info_pub_, depth_pub_, depth_info_pub_, points_pub_;
};

// The parameters each emulated plugin's upstream version reads (gazebo_ros_pkgs, Noetic), whether
// or not the emulation uses them: any other child of <plugin> is most likely a misspelling
// (<wheelSeperation> silently left the default separation, and the robot turned 12 % wrong).
const std::set<std::string>& knownTags(const std::string& f) {
  static const std::map<std::string, std::set<std::string>> tags = {
      {"libgazebo_ros_diff_drive.so",
       {"leftJoint", "rightJoint", "wheelSeparation", "wheelDiameter", "wheelAcceleration", "wheelTorque",
        "commandTopic", "odometryTopic", "odometryFrame", "robotBaseFrame", "odometrySource", "publishWheelTF",
        "publishOdomTF", "publishWheelJointState", "publishTf", "legacyMode", "updateRate", "rosDebugLevel",
        "commandTimeout"}},
      {"libgazebo_ros_p3d.so",
       {"bodyName", "topicName", "frameName", "xyzOffsets", "rpyOffsets", "xyzOffset", "rpyOffset", "gaussianNoise",
        "updateRate"}},
      {"libgazebo_ros_joint_state_publisher.so", {"jointName", "updateRate"}},
      {"libmybot_joint_command.so", {"commandTimeout", "joint"}},
      {"libgazebo_ros_laser.so", {"topicName", "frameName", "gaussianNoise", "hokuyoMinIntensity", "updateRate"}},
      {"libgazebo_ros_gpu_laser.so", {"topicName", "frameName", "gaussianNoise", "hokuyoMinIntensity", "updateRate"}},
      {"libgazebo_ros_imu_sensor.so",
       {"topicName", "bodyName", "frameName", "updateRateHZ", "gaussianNoise", "xyzOffset", "rpyOffset", "serviceName",
        "initialOrientationAsReference"}},
      {"libgazebo_ros_imu.so",
       {"bodyName", "topicName", "serviceName", "gaussianNoise", "updateRate", "frameName", "xyzOffset", "rpyOffset"}},
      {"libgazebo_ros_camera.so",
       {"updateRate", "cameraName", "imageTopicName", "cameraInfoTopicName", "frameName", "hackBaseline",
        "distortionK1", "distortionK2", "distortionK3", "distortionT1", "distortionT2", "Cx", "Cy", "CxPrime",
        "focalLength", "borderCrop", "triggerTopicName", "autoDistortion"}},
      {"libgazebo_ros_openni_kinect.so",
       {"updateRate", "cameraName", "imageTopicName", "cameraInfoTopicName", "frameName", "hackBaseline", "baseline",
        "distortionK1", "distortionK2", "distortionK3", "distortionT1", "distortionT2", "Cx", "Cy", "CxPrime",
        "focalLength", "borderCrop", "triggerTopicName", "autoDistortion", "depthImageTopicName",
        "depthImageCameraInfoTopicName", "pointCloudTopicName", "pointCloudCutoff", "pointCloudCutoffMax"}},
  };
  static const std::set<std::string> none;
  auto it = tags.find(f);
  return it == tags.end() ? none : it->second;
}

std::size_t editDistance(const std::string& a, const std::string& b) {
  std::vector<std::size_t> row(b.size() + 1);
  for (std::size_t j = 0; j <= b.size(); ++j) row[j] = j;
  for (std::size_t i = 1; i <= a.size(); ++i) {
    std::size_t diag = row[0];
    row[0] = i;
    for (std::size_t j = 1; j <= b.size(); ++j) {
      const std::size_t up = row[j];
      row[j] = std::min({row[j] + 1, row[j - 1] + 1, diag + (std::tolower(a[i - 1]) == std::tolower(b[j - 1]) ? 0 : 1)});
      diag = up;
    }
  }
  return row[b.size()];
}

// One warning per unknown child of <plugin>, naming it, the plugin and the file, with the
// closest known name when one is near.
void warnUnknownTags(const PluginContext& c) {
  const std::set<std::string>& known = knownTags(c.spec->filename);
  for (const XmlNode& child : c.spec->xml.children) {
    if (known.count(child.name) || child.name == "robotNamespace" || child.name == "alwaysOn") continue;
    std::string best;
    std::size_t best_d = 4;  // a few letters off at most
    for (const std::string& k : known)
      if (const std::size_t d = editDistance(child.name, k); d < best_d) best_d = d, best = k;
    ROS_WARN("%s: plugin '%s' (%s): unknown parameter <%s> ignored%s", c.robot->spec().source.c_str(),
             c.spec->name.c_str(), c.spec->filename.c_str(), child.name.c_str(),
             best.empty() ? "" : (" (did you mean <" + best + ">?)").c_str());
  }
}

std::unique_ptr<SimPlugin> makePlugin(const PluginContext& c) {
  const std::string& f = c.spec->filename;
  if (f == "libgazebo_ros_diff_drive.so") return std::make_unique<DiffDrive>(c);
  if (f == "libgazebo_ros_p3d.so") return std::make_unique<P3D>(c);
  if (f == "libgazebo_ros_joint_state_publisher.so") return std::make_unique<JointStatePub>(c);
  if (f == "libmybot_joint_command.so") return std::make_unique<JointCommand>(c);
  if (f == "libgazebo_ros_laser.so" || f == "libgazebo_ros_gpu_laser.so") return std::make_unique<Laser>(c);
  if (f == "libgazebo_ros_imu_sensor.so") return std::make_unique<Imu>(c, true);
  if (f == "libgazebo_ros_imu.so") return std::make_unique<Imu>(c, false);
  if (f == "libgazebo_ros_camera.so") return std::make_unique<Camera>(c, false);
  if (f == "libgazebo_ros_openni_kinect.so") return std::make_unique<Camera>(c, true);
  ROS_WARN("%s: plugin '%s': unknown plugin file '%s' ignored", c.robot->spec().source.c_str(), c.spec->name.c_str(),
           f.c_str());
  return nullptr;
}

}  // namespace

std::unique_ptr<SimPlugin> createPlugin(const PluginContext& c) {
  auto plugin = makePlugin(c);
  if (plugin) warnUnknownTags(c);
  return plugin;
}

}  // namespace mybot_gazebo_lite
