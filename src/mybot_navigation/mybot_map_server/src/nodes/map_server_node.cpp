// map_server: loads a map_server YAML + image and serves it like ROS's map_server
// (latched `map` and `map_metadata` in ~frame_id, `static_map` service). ~max_image_side
// (20000 pixels) bounds the image it will decode.
//   rosrun mybot_map_server map_server MAP.yaml
#include <nav_msgs/GetMap.h>
#include <mybot_lockstep/ros/participant.h>
#include <nav_msgs/OccupancyGrid.h>
#include <ros/ros.h>

#include "mybot_nav_common/map_io.h"
#include "mybot_nav_common/ros/node_params.h"
#include "mybot_nav_common/ros/conversions.h"

using namespace mybot_navigation;

int main(int argc, char** argv)
{
  ros::init(argc, argv, "map_server", ros::init_options::AnonymousName);
  std::vector<std::string> args;
  ros::removeROSArgs(argc, argv, args);
  if (args.size() != 2)
  {
    ROS_FATAL("map_server: usage: map_server <map.yaml>");
    return 1;
  }
  ros::NodeHandle nh, pnh("~");
  const std::string frame_id = readParam<std::string>("map_server", pnh, "frame_id", "map");
  if (frame_id.empty())
    fatalParam("map_server", pnh, "frame_id", "must not be empty");
  const int max_side = readParam<int>("map_server", pnh, "max_image_side", mybot_common::kDefaultMaxImageSide);
  if (max_side <= 0)
    fatalParam("map_server", pnh, "max_image_side", "must be a positive number of pixels");
  nav_msgs::GetMap::Response resp;
  try
  {
    const MapYaml meta = readMapYaml(args[1]);
    ROS_INFO("map_server: loading map from image \"%s\"", meta.image.c_str());
    toOccupancyGrid(loadMapImage(meta, max_side), resp.map);
  }
  catch (const MapIoError& e)
  {
    ROS_FATAL("map_server: %s", e.what());
    return 1;
  }
  resp.map.info.map_load_time = ros::Time::now();
  resp.map.header.frame_id = frame_id;
  resp.map.header.stamp = ros::Time::now();
  ROS_INFO("map_server: read a %d X %d map @ %.3f m/cell", resp.map.info.width, resp.map.info.height,
           resp.map.info.resolution);

  auto service = nh.advertiseService<nav_msgs::GetMap::Request, nav_msgs::GetMap::Response>(
      "static_map",
      [&resp](nav_msgs::GetMap::Request&, nav_msgs::GetMap::Response& res)
      {
        res = resp;
        return true;
      });
  ros::Publisher meta_pub = nh.advertise<nav_msgs::MapMetaData>("map_metadata", 1, true);
  meta_pub.publish(resp.map.info);
  ros::Publisher map_pub = nh.advertise<nav_msgs::OccupancyGrid>("map", 1, true);
  map_pub.publish(resp.map);
  // A lockstep participant under the simulator (mybot_lockstep; off lockstep this does nothing):
  // its Acks count the latched map on each connection, so AMCL and move_base take it in the
  // period after the one it was announced in on every run, not whenever it happens to arrive.
  // Named in the simulator's lockstep_wait_for, that is the first period.
  mybot_lockstep::Participant::instance();
  ros::spin();
  return 0;
}
