// TfGate: scans wait for their transform and are handed on oldest first; a full gate drops the
// oldest; time going back forgets what waits.
#include <boost/make_shared.hpp>
#include <gtest/gtest.h>
#include <sensor_msgs/LaserScan.h>

#include <vector>

#include "mybot_nav_common/ros/tf_gate.h"

namespace
{
using mybot_navigation::TfGate;
using Scan = sensor_msgs::LaserScan;

Scan::ConstPtr scanAt(double t)
{
  auto s = boost::make_shared<Scan>();
  s->header.stamp.fromSec(t);
  return s;
}

// The transform is known up to `known` seconds: what a tf buffer filled to that stamp answers.
struct Harness
{
  Harness() { ros::Time::init(); }  // the drop warning is throttled on ROS time
  TfGate<Scan> gate{"test", "/scan", 3};
  double known = 0.0;
  std::vector<double> handed;
  void release(double now)
  {
    gate.release(
        ros::Time(now), [this](const Scan& s) { return s.header.stamp.toSec() <= known; },
        [this](const Scan::ConstPtr& s) { handed.push_back(s->header.stamp.toSec()); });
  }
};
}  // namespace

TEST(TfGate, WaitsForTheTransformThenHandsOnInOrder)
{
  Harness h;
  h.gate.add(scanAt(1.0));
  h.gate.add(scanAt(1.1));
  h.release(1.1);
  EXPECT_TRUE(h.handed.empty());
  EXPECT_EQ(h.gate.waiting(), 2u);
  h.known = 1.05;  // the first scan's transform came
  h.release(1.1);
  EXPECT_EQ(h.handed, std::vector<double>({1.0}));
  h.known = 1.2;
  h.release(1.2);
  EXPECT_EQ(h.handed, std::vector<double>({1.0, 1.1}));
  EXPECT_EQ(h.gate.waiting(), 0u);
}

TEST(TfGate, AFullGateDropsTheOldest)
{
  Harness h;
  for (double t : {1.0, 1.1, 1.2, 1.3, 1.4})
    h.gate.add(scanAt(t));
  EXPECT_EQ(h.gate.waiting(), 3u);
  EXPECT_EQ(h.gate.dropped(), 2u);
  h.known = 2.0;
  h.release(2.0);
  EXPECT_EQ(h.handed, std::vector<double>({1.2, 1.3, 1.4}));
}

TEST(TfGate, TimeGoingBackForgetsWhatWaits)
{
  Harness h;
  h.gate.add(scanAt(5.0));
  h.release(5.0);  // no transform yet: it waits
  EXPECT_EQ(h.gate.waiting(), 1u);
  // A reset: the clock is at 0.2 s again. The 5.0 s scan belongs to the run before; when the
  // new run's transforms reach 5.0 s they must not place it.
  h.known = 10.0;
  h.release(0.2);
  EXPECT_TRUE(h.handed.empty());
  EXPECT_EQ(h.gate.waiting(), 0u);
}
