// The world on the WGS84 ellipsoid (hector's GNSS conventions) and the Earth's magnetic field,
// against the geodesy textbooks' figures.
#include "mybot_gazebo_lite/earth_model.h"

#include <gtest/gtest.h>

#include <cmath>

using mybot_gazebo_lite::GeoPoint;
using mybot_gazebo_lite::GeoReference;
using mybot_gazebo_lite::LocalTangentPlane;
using mybot_gazebo_lite::magneticFieldInWorld;

namespace
{
GeoReference at(double lat, double lon, double heading)
{
  GeoReference r;
  r.latitude_deg = lat;
  r.longitude_deg = lon;
  r.heading_deg = heading;
  return r;
}
}  // namespace

TEST(LocalTangentPlane, TheOriginIsTheReference)
{
  GeoReference r = at(49.9, 8.9, 0);
  r.altitude = 120.0;
  const GeoPoint g = LocalTangentPlane(r).toGeodetic(0, 0, 0);
  EXPECT_DOUBLE_EQ(g.latitude_deg, 49.9);
  EXPECT_DOUBLE_EQ(g.longitude_deg, 8.9);
  EXPECT_DOUBLE_EQ(g.altitude, 120.0);
  EXPECT_DOUBLE_EQ(LocalTangentPlane(r).toGeodetic(0, 0, 2.5).altitude, 122.5);
}

// One degree of latitude is 110 574 m at the equator and 111 132 m at 45 degrees; one of longitude
// 111 320 m at the equator and 55 800 m at 60 degrees (WGS84; at 45 degrees 111 132.954 - 559.822
// cos 2 lat + 1.175 cos 4 lat gives 111 131.78 m).
TEST(LocalTangentPlane, ADegreeIsAsLongAsOnTheEllipsoid)
{
  // heading 90: x east, y north
  EXPECT_NEAR(LocalTangentPlane(at(0, 0, 90)).toGeodetic(0, 110574.3, 0).latitude_deg, 1.0, 1e-5);
  EXPECT_NEAR(LocalTangentPlane(at(45, 0, 90)).toGeodetic(0, 111131.75, 0).latitude_deg, 46.0, 1e-5);
  EXPECT_NEAR(LocalTangentPlane(at(0, 0, 90)).toGeodetic(111319.5, 0, 0).longitude_deg, 1.0, 1e-5);
  EXPECT_NEAR(LocalTangentPlane(at(60, 10, 90)).toGeodetic(55800.0, 0, 0).longitude_deg, 11.0, 1e-5);
}

TEST(LocalTangentPlane, AtHeadingZeroXPointsNorthAndYWest)
{
  const LocalTangentPlane p(at(49.9, 8.9, 0));
  const GeoPoint x = p.toGeodetic(100, 0, 0), y = p.toGeodetic(0, 100, 0);
  EXPECT_GT(x.latitude_deg, 49.9);
  EXPECT_DOUBLE_EQ(x.longitude_deg, 8.9);
  EXPECT_DOUBLE_EQ(y.latitude_deg, 49.9);
  EXPECT_LT(y.longitude_deg, 8.9);
  const auto v = p.toNorthWestUp(1, 2, 3);
  EXPECT_DOUBLE_EQ(v[0], 1);
  EXPECT_DOUBLE_EQ(v[1], 2);
  EXPECT_DOUBLE_EQ(v[2], 3);
}

TEST(LocalTangentPlane, AtHeadingNinetyXPointsEastAndYNorth)
{
  const LocalTangentPlane p(at(49.9, 8.9, 90));
  const GeoPoint x = p.toGeodetic(100, 0, 0), y = p.toGeodetic(0, 100, 0);
  EXPECT_NEAR(x.latitude_deg, 49.9, 1e-12);
  EXPECT_GT(x.longitude_deg, 8.9);
  EXPECT_GT(y.latitude_deg, 49.9);
  EXPECT_NEAR(y.longitude_deg, 8.9, 1e-12);
  const auto v = p.toNorthWestUp(1, 0, 0);  // east is minus west
  EXPECT_NEAR(v[0], 0, 1e-12);
  EXPECT_NEAR(v[1], -1, 1e-12);
}

TEST(MagneticField, PointsToMagneticNorthAndDipsByTheInclination)
{
  const double deg = M_PI / 180;
  // x east, y north: the field points north and down.
  auto f = magneticFieldInWorld(1.0, 90 * deg, 0.0, 60 * deg);
  EXPECT_NEAR(f[0], 0.0, 1e-12);
  EXPECT_NEAR(f[1], 0.5, 1e-12);
  EXPECT_NEAR(f[2], -std::sqrt(3.0) / 2, 1e-12);
  // Declination 10 degrees east: the horizontal part leans east.
  f = magneticFieldInWorld(2.0, 90 * deg, 10 * deg, 0.0);
  EXPECT_NEAR(f[0], 2.0 * std::sin(10 * deg), 1e-12);
  EXPECT_NEAR(f[1], 2.0 * std::cos(10 * deg), 1e-12);
  // x north: along x.
  f = magneticFieldInWorld(1.0, 0.0, 0.0, 0.0);
  EXPECT_NEAR(f[0], 1.0, 1e-12);
  EXPECT_NEAR(f[1], 0.0, 1e-12);
}
