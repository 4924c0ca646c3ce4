// Per-message cost of the control library (what each node does per message), printed as
// "name ns_per_call" lines for bench/bench_control.
#include <chrono>
#include <cstdio>

#include "mybot_control/kinematics.hpp"
#include "mybot_control/odometry.hpp"
#include "mybot_control/pid.hpp"
#include "mybot_control/speed_limiter.hpp"
#include "mybot_control/twist_mux.hpp"

using namespace mybot_control;
using Clock = std::chrono::steady_clock;

namespace
{
volatile double sink;

template <typename F>
double nsPerCall(F&& f, int n)
{
  const auto t0 = Clock::now();
  for (int k = 0; k < n; ++k)
    f(k);
  return std::chrono::duration<double, std::nano>(Clock::now() - t0).count() / n;
}
}  // namespace

int main()
{
  const int n = 2000000;
  // diffdrive_controller per cmd_vel: limiter + inverse kinematics + desaturation.
  {
    TwistLimiter lim(SpeedLimits::symmetric(1.0, 1.0, 5.0), SpeedLimits{}, SpeedLimits::symmetric(2.0, 2.0, 10.0));
    const DiffDriveKinematics kin(0.3, 0.1, 0.1);
    std::printf("controller_step %.1f\n", nsPerCall(
                                              [&](int k)
                                              {
                                                Twist2D t = lim.limit({0.5 + 1e-6 * (k & 7), 0.0, 0.3}, 0.02);
                                                WheelVelocities w = kin.toWheelTangent(t);
                                                desaturate(w, 1.0);
                                                sink = w.left;
                                              },
                                              n));
  }
  // diffdrive_odom per joint_states: one odometry update.
  {
    DiffDriveOdometry::Params p;
    p.velocity_window = 10;
    DiffDriveOdometry odom(p);
    std::printf("odometry_update %.1f\n", nsPerCall(
                                              [&](int k)
                                              {
                                                odom.update(0.01 * k, 0.011 * k, 0.02 * k);
                                                sink = odom.pose().x;
                                              },
                                              n));
  }
  // wheel_controller per wheel step: encoder + PID.
  {
    PidConfig c;
    c.p = 0.3;
    c.i = 4.0;
    c.d = 0.01;
    c.f = 1.0;
    c.d_filter_tau = 0.02;
    c.output_min = -12.0;
    c.output_max = 12.0;
    Pid pid(c);
    WheelEncoder enc(2);
    std::printf("wheel_pid_step %.1f\n", nsPerCall(
                                             [&](int k)
                                             {
                                               enc.update(0.1 * k, 0.02 * k);
                                               sink = pid.compute(5.0, enc.velocity(), 0.02);
                                             },
                                             n));
  }
  // twist_mux per message: selection among 3 topics and 1 lock.
  {
    TwistMux mux;
    mux.addTopic({"nav", "nav_vel", 0.5, 10});
    mux.addTopic({"key", "key_vel", 0.5, 90});
    mux.addTopic({"joy", "joy_vel", 0.5, 100});
    mux.addLock({"pause", "pause", 0.0, 100});
    std::printf("mux_message %.1f\n", nsPerCall(
                                          [&](int k)
                                          {
                                            const double t = 0.01 * k;
                                            mux.topicReceived(k % 3, t);
                                            sink = mux.shouldForward(k % 3, t) + mux.checkStop(t);
                                          },
                                          n));
  }
  return 0;
}
