#include "mybot_common/checks.h"

#include <gtest/gtest.h>

#include <cmath>

using mybot_common::firstInvalid;

TEST(Checks, FiniteValuesPass)
{
  EXPECT_EQ(firstInvalid({{"x", 1.0}, {"y", -2.5e5}}), "");
}

TEST(Checks, NamesTheFirstNonFiniteValue)
{
  EXPECT_EQ(firstInvalid({{"pose.x", 0.0}, {"pose.y", std::nan("")}, {"pose.z", INFINITY}}), "pose.y is nan");
  EXPECT_EQ(firstInvalid({{"pose.z", -INFINITY}}), "pose.z is -inf");
}

TEST(Checks, NamesAValueBeyondTheLimit)
{
  EXPECT_EQ(firstInvalid({{"x", 1e30}}, 1e6), "x is 1e+30, beyond +-1e+06");
  EXPECT_EQ(firstInvalid({{"x", -1e6}}, 1e6), "");
}

using mybot_common::scanGeometryError;
using mybot_common::scanRangeError;

TEST(Checks, NumbersAreShownShort)
{
  EXPECT_EQ(mybot_common::formatNumber(0.003), "0.003");
  EXPECT_EQ(mybot_common::formatNumber(-3.0), "-3");
  EXPECT_EQ(mybot_common::formatNumber(1e30), "1e+30");
}

TEST(Checks, ScanWhoseRangesMatchItsAnglesPasses)
{
  EXPECT_EQ(scanGeometryError(-M_PI / 2, M_PI / 2, M_PI / 360, 361), "");
  // A real log (Freiburg 079): 360 beams over 179 degrees, float rounding in the angles.
  EXPECT_EQ(scanGeometryError(-1.5707964f, 1.5620697f, 0.0087266462f, 360), "");
  EXPECT_EQ(scanGeometryError(1.0, -1.0, -0.5, 5), "");  // sweeping clockwise
  EXPECT_EQ(scanGeometryError(0.0, 0.0, 0.01, 1), "");   // one beam
  // The Freiburg hospital log: 180 beams, angle_max one increment past the last one.
  EXPECT_EQ(scanGeometryError(-1.5577142f, 1.5838941f, 0.017453292f, 180), "");
  EXPECT_NE(scanGeometryError(-1.5577142f, 1.5838941f, 0.017453292f, 179), "");
}

TEST(Checks, ScanWithTooFewRangesGivesBothNumbers)
{
  EXPECT_EQ(
      scanGeometryError(-M_PI / 2, M_PI / 2, M_PI / 360, 100),
      "has 100 ranges where its angles (angle_min -1.5708, angle_max 1.5708, angle_increment 0.00872665) make 361");
}

TEST(Checks, ScanThatIsNoSweepIsRefused)
{
  EXPECT_NE(scanGeometryError(0.0, 1.0, 0.0, 10), "");
  EXPECT_NE(scanGeometryError(0.0, 1.0, -0.1, 11), "");
  EXPECT_NE(scanGeometryError(std::nan(""), 1.0, 0.1, 11), "");
  EXPECT_NE(scanGeometryError(0.0, 1.0, 1e-30, 11), "");  // 1e30 beams: no overflow
}

TEST(Checks, ScanRangeLimitsThatAreNoRangeAreRefused)
{
  EXPECT_EQ(scanRangeError(0.1, 30.0), "");
  EXPECT_EQ(scanRangeError(0.0, INFINITY), "");  // no upper limit
  EXPECT_EQ(scanRangeError(0.1, std::nan("")),
            "has range_min 0.1, range_max nan: not a range (range_min finite and >= 0, range_max above it)");
  EXPECT_NE(scanRangeError(-1.0, 30.0), "");  // a negative range would be a wall behind the laser
  EXPECT_NE(scanRangeError(std::nan(""), 30.0), "");
  EXPECT_NE(scanRangeError(5.0, 5.0), "");
  EXPECT_NE(scanRangeError(5.0, 0.0), "");
}
