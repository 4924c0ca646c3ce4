// A lockstep action server for lockstep_action.test (mybot_lockstep's ActionServer with
// actionlib's TestAction): its result says in which lockstep period the request was handled.
//   goal.goal 0: succeeds at once, result = the period the goal was handled in;
//   goal.goal 1: stays active until cancelled, result = the period the cancel was handled in.
// A period's index is its start in sim time over the 10 ms period.
#include <actionlib/TestAction.h>
#include <mybot_lockstep/ros/action_server.h>
#include <ros/ros.h>

#include <cmath>

namespace
{
using Server = mybot_lockstep::ActionServer<actionlib::TestAction>;

int periodNow()
{
  return static_cast<int>(std::lround(ros::Time::now().toSec() / 0.01));
}
}  // namespace

int main(int argc, char** argv)
{
  ros::init(argc, argv, "lockstep_action_server");
  ros::NodeHandle nh;
  Server server(nh, "test_action", false);
  server.registerGoalCallback(
      [](Server::GoalHandle gh)
      {
        gh.setAccepted();
        if (gh.getGoal()->goal == 0)
        {
          actionlib::TestResult r;
          r.result = periodNow();
          gh.setSucceeded(r);
        }
      });
  server.registerCancelCallback(
      [](Server::GoalHandle gh)
      {
        actionlib::TestResult r;
        r.result = periodNow();
        gh.setCanceled(r);
      });
  server.start();
  ros::spin();
  return 0;
}
