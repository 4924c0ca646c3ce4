#include "mybot_common/checks.h"

#include <gtest/gtest.h>

#include <cmath>

using mybot_common::firstInvalid;

TEST(Checks, FiniteValuesPass) { EXPECT_EQ(firstInvalid({{"x", 1.0}, {"y", -2.5e5}}), ""); }

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
