// libgazebo_ros_camera.so, libgazebo_ros_openni_kinect.so, libgazebo_ros_depth_camera.so and
// libgazebo_ros_multicamera.so (a stereo pair: two cameras of one sensor); their triggered kin,
// libgazebo_ros_triggered_camera.so and libgazebo_ros_triggered_multicamera.so
#include "builtin.h"

#include <sensor_msgs/CameraInfo.h>
#include <sensor_msgs/Image.h>
#include <sensor_msgs/PointCloud2.h>
#include <std_msgs/Empty.h>

#include <cstring>
#include <limits>

#include <cmath>

namespace mybot_gazebo_lite
{

namespace
{
// Renders only when someone subscribes, at the sensor's <update_rate> (and the
// plugin's <updateRate> if lower), both in sim time.
// One camera of a <sensor type="multicamera">: the sensor with only that <camera> in it, its
// namespace under <cameraName> ("/left") and the baseline its projection matrix carries
// (gazebo_ros_multicamera: <hackBaseline> for the right one, 0 for the left).
struct CameraMount
{
  XmlNode sensor;
  std::string suffix;
  double baseline = 0;
};

// gazebo_ros_triggered_camera's shutter: a std_msgs/Empty on <triggerTopicName> (image_trigger,
// in the camera's namespace) asks for one frame, rendered at the next step whatever the sensor's
// rate; triggers before it make no more. The cameras of a triggered stereo pair share one, each
// listening on its own topic: either one shutters both, as upstream's one sensor does.
struct Trigger
{
  bool pending = false;
  std::vector<ros::Subscriber> subs;
};

class Camera : public SimPlugin
{
public:
  // The plugin: gazebo_ros_camera, or for a <sensor type="depth"> gazebo_ros_openni_kinect or
  // gazebo_ros_depth_camera (the same images; the latter's colour image defaults to ir/image_raw,
  // and it cuts no depth off beyond the clip).
  enum class Kind
  {
    Camera,
    OpenniKinect,
    DepthCamera
  };
  // `trigger`: the camera's shutter, or none for one that renders at its rate.
  Camera(const PluginContext& c, Kind kind, const CameraMount* mount = nullptr, Trigger* trigger = nullptr)
      : c_(c), depth_sensor_(kind != Kind::Camera), noise_(c.rng ? (*c.rng)() : 0), trigger_(trigger)
  {
    PluginParams p(c, c.spec->xml);
    if (!c.spec->has_sensor)
      p.fail("sensor", "the camera plugin must sit inside a <sensor type=\"" +
                           std::string(depth_sensor_ ? "depth" : "camera") + "\">");
    PluginParams s(c, mount ? mount->sensor : c.spec->sensor);
    link_ = c.spec->reference;
    // The <camera>'s own <pose> places it in the sensor, as Gazebo's CameraSensor composes them.
    sensor_pose_ = s.pose("pose") * s.pose("camera/pose");
    double sensor_hz = s.num("update_rate", 0.0), plugin_hz = p.num("updateRate", 0.0);
    if (sensor_hz < 0)
      s.fail("update_rate", "must be >= 0");
    if (plugin_hz < 0)
      p.fail("updateRate", "must be >= 0");
    double hz = sensor_hz > 0 && plugin_hz > 0 ? std::min(sensor_hz, plugin_hz) : std::max(sensor_hz, plugin_hz);
    rate_ = Rate(hz);
    const double hfov = s.num("camera/horizontal_fov", 1.047);
    if (!(hfov > 0 && hfov < M_PI))
      s.fail("camera/horizontal_fov", "must be in (0, pi)");
    const double w = s.num("camera/image/width", 320), h = s.num("camera/image/height", 240);
    if (w < 1 || h < 1 || w != std::floor(w) || h != std::floor(h) || w * h > 16e6)
      s.fail("camera/image", "width and height must be positive integers");
    settings_.near = s.num("camera/clip/near", 0.1);
    settings_.far = s.num("camera/clip/far", 100.0);
    if (!(settings_.near > 0 && settings_.far > settings_.near))
      s.fail("camera/clip", "need 0 < near < far");
    const std::string format = s.str("camera/image/format", "R8G8B8");
    encoding_ = gazeboImageEncoding(format);
    if (encoding_.empty())
      s.fail("camera/image/format",
             "supported: R8G8B8, B8G8R8, L8, L16, R16G16B16, BAYER_RGGB8, BAYER_BGGR8, "
             "BAYER_GBRG8, BAYER_GRBG8 (and the *_INT* names of the first five); got '" +
                 format + "'");
    noise_mean_ = s.num("camera/noise/mean", 0.0);
    noise_sd_ = s.num("camera/noise/stddev", 0.0);
    if (noise_sd_ < 0)
      s.fail("camera/noise/stddev", "must be >= 0");
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
    const double baseline = mount ? mount->baseline : p.num("hackBaseline", 0.0);
    info_.P = {k_.fx, 0, k_.cx, -k_.fx * baseline, 0, k_.fy, k_.cy, 0, 0, 0, 1, 0};
    ros::NodeHandle nh(ros::NodeHandle(c.ns), p.str("cameraName", "") + (mount ? mount->suffix : ""));
    const bool ir = kind == Kind::DepthCamera;
    if (trigger_)
      trigger_->subs.push_back(subscribeCommand<std_msgs::Empty>(
          c, nh, p.topic("triggerTopicName", "image_trigger"),
          [t = trigger_](const std_msgs::Empty::ConstPtr&) { t->pending = true; }, 10));
    image_pub_ = p.advertise<sensor_msgs::Image>(nh, "imageTopicName",
                                                 p.str("imageTopicName", ir ? "ir/image_raw" : "image_raw"), 2);
    info_pub_ = p.advertise<sensor_msgs::CameraInfo>(
        nh, "cameraInfoTopicName", p.str("cameraInfoTopicName", ir ? "ir/camera_info" : "camera_info"), 2);
    if (depth_sensor_)
    {
      cutoff_ = p.num("pointCloudCutoff", 0.4);
      cutoff_max_ = ir ? std::numeric_limits<double>::infinity() : p.num("pointCloudCutoffMax", 5.0);
      if (cutoff_ < 0 || cutoff_max_ <= cutoff_)
        p.fail("pointCloudCutoffMax", "need 0 <= pointCloudCutoff < pointCloudCutoffMax");
      depth_pub_ = p.advertise<sensor_msgs::Image>(nh, "depthImageTopicName",
                                                   p.str("depthImageTopicName", "depth/image_raw"), 2);
      depth_info_pub_ = p.advertise<sensor_msgs::CameraInfo>(
          nh, "depthImageCameraInfoTopicName", p.str("depthImageCameraInfoTopicName", "depth/camera_info"), 2);
      points_pub_ =
          p.advertise<sensor_msgs::PointCloud2>(nh, "pointCloudTopicName", p.str("pointCloudTopicName", "points"), 2);
    }
  }
  void update(double t) override
  {
    // The period's grid runs whether or not anyone listens, so that a stream's first two frames
    // are a period apart whenever its subscriber came (a grid started at the first frame wanted
    // put the second one on the simulation's first period: 0.010 and 0.033 s). A triggered
    // camera renders when its shutter is pending (its owner releases it after the frame).
    if (trigger_ ? !trigger_->pending : !rate_.due(t))
      return;
    if (trigger_)
      ++rate_.fired;
    const bool want_image = image_pub_.getNumSubscribers() > 0 || info_pub_.getNumSubscribers() > 0;
    const bool want_points = depth_sensor_ && points_pub_.getNumSubscribers() > 0;
    const bool want_depth =
        depth_sensor_ && (depth_pub_.getNumSubscribers() > 0 || depth_info_pub_.getNumSubscribers() > 0);
    if (!want_image && !want_depth && !want_points)
      return;  // nobody looks: costs nothing
    btTransform tf = c_.robot->linkState(link_).tf * sensor_pose_;
    btScalar yaw, pitch, roll;
    tf.getBasis().getEulerZYX(yaw, pitch, roll);
    CameraPose pose{tf.getOrigin().x(), tf.getOrigin().y(), tf.getOrigin().z(), yaw};
    const size_t n = static_cast<size_t>(k_.width) * k_.height;
    const bool need_rgb = want_image || want_points;
    rgb_.resize(need_rgb ? n * 3 : 0);
    depth_.resize(n);
    // Other robots and dynamic bodies where they stand now. Not the camera's own robot: its
    // collision shapes stand in for its visuals, and the 2.5D prism of a body the camera is
    // mounted on or in would fill the image.
    const PrismScene moving(c_.world->movingShapes(c_.robot));
    renderCamera(c_.slices->prisms(), &moving, k_, pose, settings_, need_rgb ? rgb_.data() : nullptr, depth_.data());
    ++frames_;
    const ros::Time stamp(t);
    info_.header.stamp = stamp;
    if (need_rgb && !depth_sensor_ && noise_sd_ > 0)
      noise_.addToBytes(rgb_.data(), rgb_.size(), noise_mean_, noise_sd_);
    if (want_image)
    {
      image_pub_.publish(colorImage(stamp));
      info_pub_.publish(info_);
    }
    if (!depth_sensor_)
      return;
    // A depth sensor's <noise> is in metres; outside the cutoffs there is no reading (NaN), as in openni_kinect.
    if (noise_sd_ > 0)
      noise_.addToFloats(depth_.data(), n, noise_mean_, noise_sd_);
    const float nan = std::numeric_limits<float>::quiet_NaN();
    for (float& d : depth_)
      if (!(d > cutoff_ && d < cutoff_max_))
        d = nan;
    if (want_depth)
    {
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
    if (want_points)
      points_pub_.publish(pointCloud(stamp));
  }

  SensorUpdates sensorUpdates() const override { return {&rate_.fired, &frames_}; }

private:
  sensor_msgs::ImagePtr colorImage(const ros::Time& stamp) const
  {
    sensor_msgs::ImagePtr m = boost::make_shared<sensor_msgs::Image>();
    m->header.stamp = stamp;
    m->header.frame_id = frame_;
    m->width = k_.width;
    m->height = k_.height;
    m->encoding = encoding_;
    m->is_bigendian = 0;
    m->data = encodeImage(rgb_, k_.width, k_.height, encoding_, m->step);
    return m;
  }
  // Organised cloud in the optical convention (x right, y down, z forward), NaN where there is no reading.
  sensor_msgs::PointCloud2Ptr pointCloud(const ros::Time& stamp) const
  {
    sensor_msgs::PointCloud2Ptr pc = boost::make_shared<sensor_msgs::PointCloud2>();
    pc->header.stamp = stamp;
    pc->header.frame_id = frame_;
    pc->width = k_.width;
    pc->height = k_.height;
    const char* names[4] = {"x", "y", "z", "rgb"};
    for (uint32_t i = 0; i < 4; ++i)
    {
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
      for (int u = 0; u < k_.width; ++u)
      {
        const size_t i = static_cast<size_t>(v) * k_.width + u;
        const float d = depth_[i];
        const OpticalPoint pt = depthToPoint(k_, u, v, d);
        float xyz_rgb[4] = {pt.x, pt.y, pt.z, 0};
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
  uint64_t frames_ = 0;  // rendered
  CameraIntrinsics k_;
  RenderSettings settings_;
  double noise_mean_ = 0, noise_sd_ = 0, cutoff_ = 0.4, cutoff_max_ = 5.0;
  NoiseTable noise_;
  sensor_msgs::CameraInfo info_;
  std::vector<uint8_t> rgb_;
  std::vector<float> depth_;
  ros::Publisher image_pub_, info_pub_, depth_pub_, depth_info_pub_, points_pub_;
  Trigger* trigger_;
};

// libgazebo_ros_triggered_camera.so: a camera that renders one frame per trigger.
class TriggeredCamera : public SimPlugin
{
public:
  explicit TriggeredCamera(const PluginContext& c) : camera_(c, Camera::Kind::Camera, nullptr, &trigger_) {}
  void update(double t) override
  {
    camera_.update(t);
    trigger_.pending = false;
  }
  void reset() override { trigger_.pending = false; }
  SensorUpdates sensorUpdates() const override { return camera_.sensorUpdates(); }

private:
  Trigger trigger_;  // before the camera: it subscribes into it
  Camera camera_;
};

// gazebo_ros_multicamera: a <sensor type="multicamera"> of two <camera name="...">, one whose name
// has "left" in it, published under <cameraName>/left, the other's "right", under
// <cameraName>/right; both in <frameName>, the right one's P carrying -fx * <hackBaseline>. Each
// camera is placed by its own <pose> in the sensor and renders on the sensor's period, as upstream
// shutters them together.
class MultiCamera : public SimPlugin
{
public:
  // `triggered`: libgazebo_ros_triggered_multicamera.so, one frame of each camera per trigger.
  MultiCamera(const PluginContext& c, bool triggered) : trigger_(triggered ? std::make_unique<Trigger>() : nullptr)
  {
    PluginParams p(c, c.spec->xml);
    if (!c.spec->has_sensor)
      p.fail("sensor", "libgazebo_ros_multicamera.so must sit inside a <sensor type=\"multicamera\">");
    PluginParams s(c, c.spec->sensor);
    const std::vector<const XmlNode*> cameras = s.all("camera");
    if (cameras.size() != 2)
      s.fail("camera",
             "libgazebo_ros_multicamera.so publishes two cameras (a 'left' and a 'right' one); the sensor has " +
                 std::to_string(cameras.size()));
    for (const XmlNode* cam : cameras)
    {
      const std::string name = cam->attr("name");
      const bool left = name.find("left") != std::string::npos, right = name.find("right") != std::string::npos;
      if (left == right)
        s.fail("camera name='" + name + "'",
               "libgazebo_ros_multicamera.so tells its cameras by 'left' or 'right' in their names (one of the two)");
      auto m = std::make_unique<CameraMount>();
      m->suffix = left ? "/left" : "/right";
      for (const auto& mine : mounts_)
        if (mine->suffix == m->suffix)
          s.fail("camera name='" + name + "'", "two cameras are named '" + m->suffix.substr(1) + "'");
      m->baseline = left ? 0.0 : p.num("hackBaseline", 0.0);
      m->sensor = c.spec->sensor;
      m->sensor.children.clear();
      for (const XmlNode& child : c.spec->sensor.children)
        if (child.name != "camera")
          m->sensor.children.push_back(child);
      m->sensor.children.push_back(*cam);
      mounts_.push_back(std::move(m));
    }
    for (const auto& m : mounts_)
      cameras_.push_back(std::make_unique<Camera>(c, Camera::Kind::Camera, m.get(), trigger_.get()));
  }
  void update(double t) override
  {
    for (auto& cam : cameras_)
      cam->update(t);
    if (trigger_)
      trigger_->pending = false;
  }
  void reset() override
  {
    if (trigger_)
      trigger_->pending = false;
  }
  // The first camera's updates and frames (Gazebo's metrics report the sensor as one).
  SensorUpdates sensorUpdates() const override { return cameras_.front()->sensorUpdates(); }

private:
  std::unique_ptr<Trigger> trigger_;
  std::vector<std::unique_ptr<CameraMount>> mounts_;
  std::vector<std::unique_ptr<Camera>> cameras_;
};
}  // namespace

std::unique_ptr<SimPlugin> makeMultiCamera(const PluginContext& c)
{
  return std::make_unique<MultiCamera>(c, false);
}
std::unique_ptr<SimPlugin> makeTriggeredMultiCamera(const PluginContext& c)
{
  return std::make_unique<MultiCamera>(c, true);
}
std::unique_ptr<SimPlugin> makeTriggeredCamera(const PluginContext& c)
{
  return std::make_unique<TriggeredCamera>(c);
}

std::unique_ptr<SimPlugin> makeCamera(const PluginContext& c)
{
  return std::make_unique<Camera>(c, Camera::Kind::Camera);
}
std::unique_ptr<SimPlugin> makeDepthCamera(const PluginContext& c)
{
  return std::make_unique<Camera>(c, Camera::Kind::OpenniKinect);
}
std::unique_ptr<SimPlugin> makeRosDepthCamera(const PluginContext& c)
{
  return std::make_unique<Camera>(c, Camera::Kind::DepthCamera);
}

}  // namespace mybot_gazebo_lite
