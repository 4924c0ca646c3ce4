// Synthetic worlds and a scripted drive with a simulated laser and noisy odometry: test and
// benchmark data without the simulator.
#pragma once

#include <random>
#include <vector>

#include "mybot_navigation/grid_map.h"

namespace mybot_navigation
{

struct Rect
{
  double x0, y0, x1, y1;
};

// Closed rectangular room [0,w]x[0,h] (walls of `wall` thickness) with solid rectangles inside.
GridMap makeWorld(double width, double height, double resolution, const std::vector<Rect>& obstacles,
                  double wall = 0.1);
// A 12 x 10 m two-room office with furniture (loop test world).
GridMap officeWorld(double resolution = 0.01);
// A 50 x 50 m factory floor: rows of shelves, pillars, a partition (benchmark world).
GridMap factoryWorld(double resolution = 0.02);

struct LaserSpec
{
  double angle_min = -M_PI / 2;
  double angle_max = M_PI / 2;
  int beams = 720;
  double range_min = 0.1;
  double range_max = 30.0;
  double noise_sd = 0.01;
  double rate = 40.0;  // Hz
  double angleIncrement() const { return (angle_max - angle_min) / (beams - 1); }
};

struct OdometryNoise
{
  double alpha_trans = 0.0;  // sd of translation error per metre travelled
  double alpha_rot = 0.0;    // sd of rotation error per radian turned
  double drift_rot = 0.0;    // rad of heading bias per metre travelled (wheel-radius mismatch)
};

struct DriveSample
{
  double stamp;
  Pose2D truth;  // base pose in the world
  Pose2D odom;   // noisy dead reckoning, starting at the truth start pose
  std::vector<float> ranges;
};

// Drives a closed-loop-capable route through waypoints (rotate in place, then straight), sampling
// the laser at its rate.
class DriveSimulator
{
public:
  DriveSimulator(const GridMap& world, const std::vector<Point2D>& waypoints, const LaserSpec& laser,
                 const OdometryNoise& noise, double speed = 0.5, double turn_rate = 1.0, unsigned seed = 1);
  // Advances one laser period; false when the route is done. Ranges are simulated only if
  // `with_scan` (ray casting dominates the cost of synthetic data).
  bool next(DriveSample& out, bool with_scan = true);
  // The laser ranges at the current true pose.
  std::vector<float> scan();
  double duration() const;  // total simulated time in s

private:
  const GridMap& world_;
  std::vector<Point2D> waypoints_;
  LaserSpec laser_;
  OdometryNoise noise_;
  double speed_, turn_rate_;
  std::mt19937 rng_;
  size_t target_ = 1;
  Pose2D truth_, odom_;
  double stamp_ = 0.0;
};

}  // namespace mybot_navigation

#include "mybot_navigation/slam.h"

namespace mybot_navigation
{

struct OfflineRun
{
  std::vector<Pose2D> estimate;   // final keyframe poses (after every optimisation)
  std::vector<Pose2D> truth;      // ground truth at the keyframe stamps
  std::vector<Pose2D> odometry;   // raw odometry at the keyframe stamps
  double slam_cpu_seconds = 0.0;  // CPU time spent in scan conversion + SLAM
  double sim_seconds = 0.0;       // simulated time covered
  int scans = 0;
};

// Feeds the drive to the SLAM as a node would: every laser period is offered (Slam::wantsScan),
// wanted scans are converted and added (laser at the base origin). CPU time covers only the SLAM side.
OfflineRun runSlamOnDrive(Slam& slam, DriveSimulator& drive, const LaserSpec& laser, double max_usable_range);

}  // namespace mybot_navigation
