// File name -> emulation, with the parameters each upstream plugin reads; plugins of other
// packages are loaded from shared libraries (the way Gazebo loads plugins).
#include "builtin.h"

#include <dlfcn.h>

#include <algorithm>
#include <cctype>
#include <cstring>
#include <functional>
#include <vector>

namespace mybot_gazebo_lite
{

namespace
{

struct Builtin
{
  std::string filename;
  std::unique_ptr<SimPlugin> (*make)(const PluginContext&);
  // The parameters the upstream plugin reads (gazebo_ros_pkgs, Noetic), whether or not the
  // emulation uses them: any other child of <plugin> is most likely a misspelling
  // (<wheelSeperation> silently left the default separation, and the robot turned 12 % wrong).
  std::set<std::string> tags;
};

const std::set<std::string> kLaserTags = {"topicName", "frameName", "gaussianNoise", "hokuyoMinIntensity",
                                          "updateRate"};
const std::set<std::string> kCameraTags = {
    "updateRate",   "cameraName",   "imageTopicName", "cameraInfoTopicName", "frameName",        "hackBaseline",
    "distortionK1", "distortionK2", "distortionK3",   "distortionT1",        "distortionT2",     "Cx",
    "Cy",           "CxPrime",      "focalLength",    "borderCrop",          "triggerTopicName", "autoDistortion"};

const std::set<std::string> kMimicTags = {"joint",         "mimicJoint", "multiplier", "offset",
                                          "sensitiveness", "maxEffort",  "hasPID"};

std::set<std::string> with(std::set<std::string> a, const std::set<std::string>& b)
{
  a.insert(b.begin(), b.end());
  return a;
}

// hector_gazebo_plugins' update timer and error model tags (hector_support.cpp).
std::set<std::string> hectorTags(std::set<std::string> own, const std::vector<std::string>& error_prefixes)
{
  own.insert({"updateRate", "updatePeriod", "updateOffset"});
  for (const std::string& prefix : error_prefixes)
    own = with(own, hectorErrorTags(prefix));
  return own;
}

const std::vector<Builtin>& builtins()
{
  static const std::vector<Builtin> table = {
      {"libgazebo_ros_diff_drive.so",
       makeDiffDrive,
       {"leftJoint", "rightJoint", "wheelSeparation", "wheelDiameter", "wheelAcceleration", "wheelTorque",
        "commandTopic", "odometryTopic", "odometryFrame", "robotBaseFrame", "odometrySource", "publishWheelTF",
        "publishOdomTF", "publishWheelJointState", "publishTf", "legacyMode", "updateRate", "rosDebugLevel",
        "commandTimeout"}},
      {"libgazebo_ros_skid_steer_drive.so",
       makeSkidSteerDrive,
       {"leftFrontJoint", "rightFrontJoint", "leftRearJoint", "rightRearJoint", "wheelSeparation", "wheelDiameter",
        "torque", "MaxForce", "commandTopic", "odometryTopic", "odometryFrame", "robotBaseFrame", "broadcastTF",
        "updateRate", "covariance_x", "covariance_y", "covariance_yaw", "commandTimeout"}},
      {"libgazebo_ros_tricycle_drive.so",
       makeTricycleDrive,
       {"steeringJoint",
        "actuatedWheelJoint",
        "encoderWheelLeftJoint",
        "encoderWheelRightJoint",
        "actuatedWheelDiameter",
        "encoderWheelDiameter",
        "encoderWheelSeparation",
        "wheelTorque",
        "commandTopic",
        "odometryTopic",
        "odometryFrame",
        "robotBaseFrame",
        "updateRate",
        "wheelAcceleration",
        "wheelDeceleration",
        "wheelSpeedTolerance",
        "steeringSpeed",
        "steeringAngleTolerance",
        "odometrySource",
        "publishWheelTF",
        "publishWheelJointState",
        "rosDebugLevel",
        "commandTimeout"}},
      {"libgazebo_ros_planar_move.so",
       makePlanarMove,
       {"commandTopic", "odometryTopic", "odometryFrame", "odometryRate", "robotBaseFrame", "publishOdometryTf",
        "cmdTimeout", "covariance_x", "covariance_y", "covariance_yaw"}},
      {"libgazebo_ros_p3d.so",
       makeP3D,
       {"bodyName", "topicName", "frameName", "xyzOffsets", "rpyOffsets", "xyzOffset", "rpyOffset", "gaussianNoise",
        "updateRate"}},
      {"libgazebo_ros_force.so", makeForce, {"bodyName", "topicName"}},
      {"libgazebo_ros_f3d.so", makeF3D, {"bodyName", "topicName", "frameName"}},
      // roboticsgroup_gazebo_plugins (and its upatras fork): the grippers' mimic joints.
      {"libroboticsgroup_gazebo_mimic_joint_plugin.so", makeMimicJoint, kMimicTags},
      {"libroboticsgroup_upatras_gazebo_mimic_joint_plugin.so", makeMimicJoint, kMimicTags},
      {"libgazebo_ros_vacuum_gripper.so", makeVacuumGripper, {"bodyName", "topicName"}},
      {"libgazebo_ros_ft_sensor.so", makeFTSensor, {"jointName", "topicName", "gaussianNoise", "updateRate"}},
      {"libgazebo_ros_joint_pose_trajectory.so", makeJointPoseTrajectory, {"topicName", "serviceName", "updateRate"}},
      {"libgazebo_ros_joint_state_publisher.so", makeJointStatePublisher, {"jointName", "updateRate"}},
      {"libmybot_joint_command.so", makeJointCommand, {"commandTimeout", "joint"}},
      {"libgazebo_ros_laser.so", makeLaser, kLaserTags},
      {"libgazebo_ros_gpu_laser.so", makeLaser, kLaserTags},
      {"libgazebo_ros_range.so",
       makeRange,
       {"topicName", "frameName", "updateRate", "gaussianNoise", "radiation", "fov"}},
      {"libgazebo_ros_bumper.so", makeBumper, {"bumperTopicName", "frameName"}},
      {"libgazebo_ros_block_laser.so",
       makeBlockLaser,
       {"topicName", "frameName", "gaussianNoise", "hokuyoMinIntensity", "updateRate"}},
      {"libgazebo_ros_imu_sensor.so",
       makeImuSensor,
       {"topicName", "bodyName", "frameName", "updateRateHZ", "gaussianNoise", "xyzOffset", "rpyOffset", "serviceName",
        "initialOrientationAsReference"}},
      {"libgazebo_ros_imu.so",
       makeImu,
       {"bodyName", "topicName", "serviceName", "gaussianNoise", "updateRate", "frameName", "xyzOffset", "rpyOffset"}},
      {"libgazebo_ros_camera.so", makeCamera, kCameraTags},
      {"libgazebo_ros_multicamera.so", makeMultiCamera, kCameraTags},
      {"libgazebo_ros_triggered_camera.so", makeTriggeredCamera, kCameraTags},
      {"libgazebo_ros_triggered_multicamera.so", makeTriggeredMultiCamera, kCameraTags},
      {"libgazebo_ros_openni_kinect.so", makeDepthCamera,
       with(kCameraTags, {"baseline", "depthImageTopicName", "depthImageCameraInfoTopicName", "pointCloudTopicName",
                          "pointCloudCutoff", "pointCloudCutoffMax"})},
      {"libgazebo_ros_depth_camera.so", makeRosDepthCamera,
       with(kCameraTags,
            {"depthImageTopicName", "depthImageCameraInfoTopicName", "pointCloudTopicName", "pointCloudCutoff"})},
      // hector_gazebo_plugins (Noetic): the outdoor robots' GNSS, IMU, compass and sonar.
      {"libhector_gazebo_ros_gps.so", makeHectorGps,
       hectorTags({"bodyName", "frameId", "topicName", "velocityTopicName", "referenceLatitude", "referenceLongitude",
                   "referenceHeading", "referenceAltitude", "status", "service"},
                  {"", "velocity"})},
      {"libhector_gazebo_ros_imu.so", makeHectorImu,
       hectorTags({"bodyName", "frameId", "topicName", "biasTopicName", "serviceName", "gaussianNoise", "xyzOffset",
                   "rpyOffset"},
                  {"accel", "rate", "yaw"})},
      {"libhector_gazebo_ros_magnetic.so", makeHectorMagnetic,
       hectorTags({"bodyName", "frameId", "topicName", "magnitude", "referenceHeading", "declination", "inclination",
                   "useMagneticFieldMsgs"},
                  {""})},
      {"libhector_gazebo_ros_sonar.so", makeHectorSonar, hectorTags({"frameId", "topicName"}, {""})},
      {"libdiffdrive_plugin_multi_wheel.so",
       makeHectorMultiWheelDrive,
       {"leftJoints", "rightJoints", "wheelSeparation", "wheelDiameter", "torque", "commandTopic", "odometryTopic",
        "odometryFrame", "robotBaseFrame", "updateRate", "publishOdometryTf", "publishOdometryMsg", "commandTimeout"}},
      {"libhector_gazebo_ros_force_based_move.so",
       makeHectorForceBasedMove,
       {"commandTopic", "odometryTopic", "odometryFrame", "odometryRate", "robotBaseFrame", "publishOdometryTf",
        "x_velocity_p_gain", "y_velocity_p_gain", "yaw_velocity_p_gain"}},
  };
  return table;
}

std::size_t editDistance(const std::string& a, const std::string& b)
{
  std::vector<std::size_t> row(b.size() + 1);
  for (std::size_t j = 0; j <= b.size(); ++j)
    row[j] = j;
  for (std::size_t i = 1; i <= a.size(); ++i)
  {
    std::size_t diag = row[0];
    row[0] = i;
    for (std::size_t j = 1; j <= b.size(); ++j)
    {
      const std::size_t up = row[j];
      row[j] =
          std::min({row[j] + 1, row[j - 1] + 1, diag + (std::tolower(a[i - 1]) == std::tolower(b[j - 1]) ? 0 : 1)});
      diag = up;
    }
  }
  return row[b.size()];
}

// A plugin of another package: `lib<name>.so` is emulated by `libgazebo_lite_<name>.so` on
// LD_LIBRARY_PATH (catkin puts every workspace's lib/ there). The library stays loaded for the
// life of the process, as in Gazebo. nullptr when there is none.
std::unique_ptr<SimPlugin> loadLibraryPlugin(const PluginContext& c)
{
  std::string f = c.spec->filename;
  if (f.rfind("lib", 0) != 0 || f.size() < 7 || f.compare(f.size() - 3, 3, ".so") != 0)
    return nullptr;
  const std::string lib = "libgazebo_lite_" + f.substr(3);
  void* handle = dlopen(lib.c_str(), RTLD_NOW | RTLD_GLOBAL);
  if (!handle)
  {
    const char* err = dlerror();
    // A library that exists but does not load is worth its own message (a missing symbol, say).
    if (err && !std::strstr(err, "No such file"))
      ROS_ERROR("gazebo_lite: %s: %s", lib.c_str(), err);
    return nullptr;
  }
  auto factory = reinterpret_cast<PluginFactory>(dlsym(handle, "mybot_gazebo_lite_create_plugin"));
  if (!factory)
  {
    ROS_ERROR("gazebo_lite: %s does not export mybot_gazebo_lite_create_plugin", lib.c_str());
    return nullptr;
  }
  return std::unique_ptr<SimPlugin>(factory(c));
}

}  // namespace

void warnUnknownTags(const PluginContext& c, const std::set<std::string>& known)
{
  const std::string link = c.spec->reference.empty() ? "" : " on link '" + c.spec->reference + "'";
  for (const XmlNode& child : c.spec->xml.children)
  {
    if (PluginParams::wasRead(child) || child.name == "robotNamespace" || child.name == "alwaysOn" ||
        child.name == "rosDebugLevel")
      continue;
    if (known.count(child.name))
    {
      ROS_WARN("%s: plugin '%s' (%s)%s: parameter <%s> is not simulated by gazebo_lite; ignored",
               c.robot->spec().source.c_str(), c.spec->name.c_str(), c.spec->filename.c_str(), link.c_str(),
               child.name.c_str());
      continue;
    }
    std::string best;
    std::size_t best_d = 4;  // a few letters off at most
    for (const std::string& k : known)
      if (const std::size_t d = editDistance(child.name, k); d < best_d)
        best_d = d, best = k;
    ROS_WARN("%s: plugin '%s' (%s)%s: unknown parameter <%s> ignored%s", c.robot->spec().source.c_str(),
             c.spec->name.c_str(), c.spec->filename.c_str(), link.c_str(), child.name.c_str(),
             best.empty() ? "" : (" (did you mean <" + best + ">?)").c_str());
  }
}

std::unique_ptr<SimPlugin> createPlugin(const PluginContext& c)
{
  PluginParams::forgetReads(c.spec->xml);
  std::unique_ptr<SimPlugin> plugin;
  try
  {
    for (const Builtin& b : builtins())
      if (b.filename == c.spec->filename)
      {
        plugin = b.make(c);
        warnUnknownTags(c, b.tags);
        PluginParams::forgetReads(c.spec->xml);
        return plugin;
      }
    plugin = loadLibraryPlugin(c);  // it warns about its own tags
  }
  catch (const ros::InvalidNameException& e)
  {
    // A namespace, camera name or topic roscpp refuses (<robotNamespace>a b</robotNamespace>):
    // its message names neither the plugin nor the file.
    PluginParams(c, c.spec->xml).fail("", e.what());
  }
  PluginParams::forgetReads(c.spec->xml);
  if (plugin)
    return plugin;
  ROS_WARN("%s: plugin '%s': unknown plugin file '%s' ignored", c.robot->spec().source.c_str(), c.spec->name.c_str(),
           c.spec->filename.c_str());
  return nullptr;
}

}  // namespace mybot_gazebo_lite
