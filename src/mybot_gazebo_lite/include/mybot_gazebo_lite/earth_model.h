// Where the simulated world lies on the Earth, for the GNSS receiver and the magnetometer of
// hector_gazebo_plugins, with their conventions. No ROS.
//
// Position: the world is a plane tangent to the WGS84 ellipsoid at a reference latitude,
// longitude and altitude; a metre north changes the latitude by 1 / R_N radians (R_N the
// meridian's radius of curvature there) and a metre east the longitude by 1 / R_E (R_E the
// prime vertical's radius times cos(latitude)). Over the few hundred metres a simulated robot
// drives, this flat-Earth linearisation is off by millimetres (the error grows with the square
// of the distance over the Earth's radius).
//
// Heading (hector's <referenceHeading>, degrees): the compass direction of the world's x axis.
// At 0, x points north and y west (north-west-up, as Gazebo's world was once read); at 90, x
// points east and y north (east-north-up, REP 103's and robot_localization's convention).
#pragma once

#include <array>

namespace mybot_gazebo_lite
{

struct GeoReference
{
  double latitude_deg = 49.9;  // hector_gazebo_plugins' defaults: near Darmstadt
  double longitude_deg = 8.9;
  double heading_deg = 0.0;
  double altitude = 0.0;  // m
};

struct GeoPoint
{
  double latitude_deg, longitude_deg, altitude;
};

class LocalTangentPlane
{
public:
  explicit LocalTangentPlane(const GeoReference& ref);

  // A world point (m) as WGS84 latitude, longitude (degrees) and altitude (m).
  GeoPoint toGeodetic(double x, double y, double z) const;
  // A world vector (a velocity) in north-west-up axes, as hector's fix_velocity reports it.
  std::array<double, 3> toNorthWestUp(double x, double y, double z) const;

  double northRadius() const { return radius_north_; }  // m per radian of latitude
  double eastRadius() const { return radius_east_; }    // m per radian of longitude

private:
  GeoReference ref_;
  double heading_;  // rad
  double radius_north_, radius_east_;
};

// The Earth's magnetic field in world axes (in the unit of `magnitude`), for a world whose x
// axis points to compass heading `heading` (rad, clockwise from north): its horizontal part
// points to magnetic north, `declination` (rad, east positive) off true north, and it dips
// `inclination` (rad) below the horizon (positive in the northern hemisphere).
std::array<double, 3> magneticFieldInWorld(double magnitude, double heading, double declination, double inclination);

}  // namespace mybot_gazebo_lite
