// mybot_lockstep::TransformListener when time goes back, with the clock driven by this test
// (use_sim_time, no simulator: off lockstep the listener is a plain subscriber). The case of
// nav_reset: amcl's map -> odom, stamped just after the last moment before a reset, reaches the
// listener after the clock went back; kept, it made tf2 refuse every newer map -> odom for the
// buffer's cache_time (10 s), and move_base lost the robot's pose.
#include "mybot_lockstep/ros/transform_listener.h"

#include <geometry_msgs/TransformStamped.h>
#include <gtest/gtest.h>
#include <rosgraph_msgs/Clock.h>
#include <ros/ros.h>
#include <tf2_msgs/TFMessage.h>

namespace
{

class JumpTest : public ::testing::Test
{
protected:
  JumpTest()
      : listener_(buffer_, [this] { ++updates_; }),
        clock_pub_(nh_.advertise<rosgraph_msgs::Clock>("/clock", 10)),
        tf_pub_(nh_.advertise<tf2_msgs::TFMessage>("/tf", 10))
  {
    // Both our subscriptions (tf, and roscpp's own /clock) connected before anything is sent.
    waitFor([this] { return tf_pub_.getNumSubscribers() > 0 && clock_pub_.getNumSubscribers() > 0; },
            "the listener's and roscpp's subscriptions");
  }

  template <typename Cond>
  void waitFor(Cond cond, const char* what)
  {
    const ros::WallTime end = ros::WallTime::now() + ros::WallDuration(10.0);
    while (!cond())
    {
      ASSERT_LT(ros::WallTime::now(), end) << "timed out waiting for " << what;
      ros::spinOnce();
      ros::WallDuration(0.001).sleep();
    }
  }

  void setClock(double t)
  {
    rosgraph_msgs::Clock c;
    c.clock = ros::Time(t);
    clock_pub_.publish(c);
    waitFor([t] { return std::abs(ros::Time::now().toSec() - t) < 1e-9; }, "the clock");
  }

  // Publishes parent -> child at x = `x`, stamped `stamp`, and waits until the listener has it.
  void send(const std::string& parent, const std::string& child, double stamp, double x)
  {
    tf2_msgs::TFMessage m;
    geometry_msgs::TransformStamped t;
    t.header.frame_id = parent;
    t.header.stamp = ros::Time(stamp);
    t.child_frame_id = child;
    t.transform.translation.x = x;
    t.transform.rotation.w = 1.0;
    m.transforms.push_back(t);
    const int before = updates_;
    tf_pub_.publish(m);
    waitFor([this, before] { return updates_ > before; }, "the transform to be received");
  }

  ros::NodeHandle nh_;
  tf2_ros::Buffer buffer_;  // tf2's default cache_time, 10 s
  int updates_ = 0;
  mybot_lockstep::TransformListener listener_;
  ros::Publisher clock_pub_, tf_pub_;
};

TEST_F(JumpTest, ATransformSentBeforeTheResetDoesNotHideTheNewOnes)
{
  setClock(19.98);
  send("odom", "base_footprint", 19.98, 5.0);
  send("map", "odom", 20.08, 1.0);  // future-dated by amcl's transform_tolerance
  setClock(0.02);                   // reset_simulation
  send("map", "odom", 20.18, 1.0);  // amcl's, from its last scan before the reset
  send("odom", "base_footprint", 0.02, 0.0);
  send("map", "odom", 0.12, 2.0);  // amcl's, from its first scan after it
  setClock(0.12);
  send("odom", "base_footprint", 0.12, 0.0);
  // Kept, the map -> odom of 20.18 s would have made tf2 refuse the one of 0.12 s as older than
  // the buffer's cache_time, and this lookup would find no map -> odom at 0.12 s.
  geometry_msgs::TransformStamped t;
  ASSERT_NO_THROW(t = buffer_.lookupTransform("map", "base_footprint", ros::Time(0)));
  EXPECT_NEAR(t.header.stamp.toSec(), 0.12, 1e-9);
  EXPECT_NEAR(t.transform.translation.x, 2.0, 1e-9) << "the map -> odom of before the reset was used";
}

TEST_F(JumpTest, TransformsFutureDatedAfterTheResetAreKept)
{
  setClock(12.0);
  send("odom", "base_footprint", 12.0, 1.0);
  setClock(0.0);
  send("odom", "base_footprint", 0.0, 1.0);
  setClock(5.8);
  send("odom", "base_footprint", 5.8, 1.0);
  send("map", "odom", 6.0, 3.0);  // 0.2 s ahead, past the jump's midpoint (6 s)
  geometry_msgs::TransformStamped t;
  ASSERT_NO_THROW(t = buffer_.lookupTransform("map", "odom", ros::Time(6.0)));
  EXPECT_NEAR(t.transform.translation.x, 3.0, 1e-9);
}

}  // namespace

int main(int argc, char** argv)
{
  testing::InitGoogleTest(&argc, argv);
  ros::init(argc, argv, "transform_listener_jump_test");
  return RUN_ALL_TESTS();
}
