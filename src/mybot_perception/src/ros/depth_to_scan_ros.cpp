#include "mybot_perception/ros/depth_to_scan.h"

#include <mybot_common/ros/params.h>
#include <mybot_lockstep/ros/participant.h>
#include <sensor_msgs/LaserScan.h>

namespace mybot_perception
{

DepthToScanRos::DepthToScanRos(ros::NodeHandle nh, ros::NodeHandle pnh, bool lockstep) : nh_(nh)
{
  const mybot_common::ParamReader p(pnh);
  params_.scan_height = p.integer("scan_height", 1);
  scan_time_ = p.number("scan_time", 0.033);
  params_.range_min = p.number("range_min", 0.45);
  params_.range_max = p.number("range_max", 10.0);
  frame_ = p.string("output_frame_id", "camera_depth_frame");
  if (params_.scan_height < 1)
    p.fail("scan_height", "must be at least 1 row");
  if (!(scan_time_ >= 0.0))
    p.fail("scan_time", "must be >= 0 s");
  if (!(params_.range_min >= 0.0 && params_.range_max > params_.range_min && std::isfinite(params_.range_max)))
    p.fail("range_max", "must be finite and above ~range_min (" + std::to_string(params_.range_min) + ")");
  if (frame_.empty())
    p.fail("output_frame_id", "must not be empty");

  scan_pub_ = nh_.advertise<sensor_msgs::LaserScan>("scan", 10);
  auto on_info = [this](const sensor_msgs::CameraInfo::ConstPtr& m) { info_ = m; };
  auto on_image = [this](const sensor_msgs::Image::ConstPtr& m) { onImage(m); };
  if (lockstep)
  {
    auto& ls = mybot_lockstep::Participant::instance();
    info_sub_ = ls.subscribe<sensor_msgs::CameraInfo>(nh_, "camera_info", 10, on_info);
    image_sub_ = ls.subscribe<sensor_msgs::Image>(nh_, "image", 10, on_image);
  }
  else
  {
    info_sub_ = nh_.subscribe<sensor_msgs::CameraInfo>("camera_info", 10, on_info);
    image_sub_ = nh_.subscribe<sensor_msgs::Image>("image", 10, on_image);
  }
}

void DepthToScanRos::onImage(const sensor_msgs::Image::ConstPtr& image)
{
  if (!info_)
  {
    ROS_WARN_THROTTLE(5.0, "depth_to_scan: no camera_info on %s yet; images are dropped",
                      nh_.resolveName("camera_info").c_str());
    return;
  }
  PinholeColumns camera;
  camera.width = static_cast<int>(image->width);
  camera.height = static_cast<int>(image->height);
  camera.fx = info_->K[0];
  camera.cx = info_->K[2];
  camera.cy = info_->K[5];
  if (info_->width != image->width || info_->height != image->height)
  {
    ROS_WARN_THROTTLE(5.0, "depth_to_scan: image of %u x %u on %s but camera_info says %u x %u: dropped", image->width,
                      image->height, nh_.resolveName("image").c_str(), info_->width, info_->height);
    return;
  }
  const std::string error = checkDepthToScan(camera, params_);
  if (!error.empty())
  {
    ROS_ERROR_THROTTLE(5.0, "depth_to_scan: %s", error.c_str());
    return;
  }
  const bool mm = image->encoding == "16UC1" || image->encoding == "mono16";
  const bool metres = image->encoding == "32FC1";
  const std::size_t element = mm ? 2 : 4;
  if ((!mm && !metres) || image->step < image->width * element ||
      image->data.size() < static_cast<std::size_t>(image->step) * image->height || image->is_bigendian)
  {
    ROS_ERROR_THROTTLE(5.0,
                       "depth_to_scan: image on %s is %s, %u x %u, step %u, %zu bytes%s: need 16UC1 (mm) or "
                       "32FC1 (m), little-endian, consistent with its size",
                       nh_.resolveName("image").c_str(), image->encoding.c_str(), image->width, image->height,
                       image->step, image->data.size(), image->is_bigendian ? ", big-endian" : "");
    return;
  }
  const PlanarScan s =
      mm ? depthToScan(reinterpret_cast<const std::uint16_t*>(image->data.data()), image->step / 2, camera, params_)
         : depthToScan(reinterpret_cast<const float*>(image->data.data()), image->step / 4, camera, params_);
  sensor_msgs::LaserScan scan;
  scan.header.stamp = image->header.stamp;
  scan.header.frame_id = frame_;
  scan.angle_min = static_cast<float>(s.angle_min);
  scan.angle_max = static_cast<float>(s.angle_max);
  scan.angle_increment = static_cast<float>(s.angle_increment);
  scan.time_increment = 0.0f;
  scan.scan_time = static_cast<float>(scan_time_);
  scan.range_min = static_cast<float>(params_.range_min);
  scan.range_max = static_cast<float>(params_.range_max);
  scan.ranges = s.ranges;
  scan_pub_.publish(scan);
}

}  // namespace mybot_perception
