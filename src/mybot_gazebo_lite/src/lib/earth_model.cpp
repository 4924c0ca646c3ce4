#include "mybot_gazebo_lite/earth_model.h"

#include <cmath>

namespace mybot_gazebo_lite
{

namespace
{
// WGS84
constexpr double kEquatorialRadius = 6378137.0;
constexpr double kFlattening = 1.0 / 298.257223563;
constexpr double kEccentricity2 = 2 * kFlattening - kFlattening * kFlattening;
constexpr double kDeg = M_PI / 180.0;
}  // namespace

LocalTangentPlane::LocalTangentPlane(const GeoReference& ref) : ref_(ref), heading_(ref.heading_deg * kDeg)
{
  const double s = std::sin(ref.latitude_deg * kDeg);
  const double w = 1.0 / (1.0 - kEccentricity2 * s * s);
  const double prime_vertical = kEquatorialRadius * std::sqrt(w);
  radius_north_ = prime_vertical * (1.0 - kEccentricity2) * w;  // the meridian's radius of curvature
  radius_east_ = prime_vertical * std::cos(ref.latitude_deg * kDeg);
}

std::array<double, 3> LocalTangentPlane::toNorthWestUp(double x, double y, double z) const
{
  const double c = std::cos(heading_), s = std::sin(heading_);
  return {c * x + s * y, -s * x + c * y, z};
}

GeoPoint LocalTangentPlane::toGeodetic(double x, double y, double z) const
{
  const std::array<double, 3> nwu = toNorthWestUp(x, y, z);
  return {ref_.latitude_deg + nwu[0] / radius_north_ / kDeg, ref_.longitude_deg - nwu[1] / radius_east_ / kDeg,
          ref_.altitude + z};
}

std::array<double, 3> magneticFieldInWorld(double magnitude, double heading, double declination, double inclination)
{
  // The world's x axis is `heading` clockwise from north, magnetic north `declination` clockwise
  // from it: x sees the field's horizontal part at heading - declination, y (90 degrees
  // anticlockwise of x) at its sine.
  const double horizontal = magnitude * std::cos(inclination);
  return {horizontal * std::cos(heading - declination), horizontal * std::sin(heading - declination),
          -magnitude * std::sin(inclination)};
}

}  // namespace mybot_gazebo_lite
