#include "mybot_navigation/synthetic_world.h"

#include <algorithm>
#include <cmath>

#include "mybot_navigation/ray_cast.h"

namespace mybot_navigation
{

GridMap makeWorld(double width, double height, double resolution, const std::vector<Rect>& obstacles, double wall)
{
  MapInfo info;
  info.resolution = resolution;
  info.width = static_cast<int>(std::ceil(width / resolution));
  info.height = static_cast<int>(std::ceil(height / resolution));
  GridMap map(info, GridMap::kFree);
  std::vector<Rect> all = obstacles;
  all.push_back({0, 0, width, wall});
  all.push_back({0, height - wall, width, height});
  all.push_back({0, 0, wall, height});
  all.push_back({width - wall, 0, width, height});
  for (const Rect& r : all)
  {
    const int x0 = std::max(0, static_cast<int>(std::floor(r.x0 / resolution)));
    const int y0 = std::max(0, static_cast<int>(std::floor(r.y0 / resolution)));
    const int x1 = std::min(info.width - 1, static_cast<int>(std::ceil(r.x1 / resolution)) - 1);
    const int y1 = std::min(info.height - 1, static_cast<int>(std::ceil(r.y1 / resolution)) - 1);
    for (int y = y0; y <= y1; ++y)
      for (int x = x0; x <= x1; ++x)
        map.at(x, y) = GridMap::kOccupied;
  }
  return map;
}

GridMap officeWorld(double resolution)
{
  return makeWorld(12.0, 10.0, resolution,
                   {
                       {6.0, 0.0, 6.1, 3.5},  // partition with a door gap 3.5..5
                       {6.0, 5.0, 6.1, 10.0},
                       {1.5, 7.0, 2.5, 8.0},    // table
                       {3.5, 1.2, 4.3, 1.6},    // desk
                       {8.0, 7.5, 10.5, 8.0},   // shelf
                       {9.0, 2.0, 9.4, 2.4},    // pillar
                       {10.8, 4.0, 11.9, 5.2},  // cabinet
                       {0.1, 4.5, 0.9, 5.0},
                   });
}

GridMap factoryWorld(double resolution)
{
  std::vector<Rect> obs;
  // Shelf rows with gaps, in the western half.
  for (int row = 0; row < 5; ++row)
  {
    const double y = 6.0 + row * 7.0;
    obs.push_back({4.0, y, 12.0 + (row % 2) * 2.0, y + 1.0});
    obs.push_back({15.0 + (row % 3), y, 22.0, y + 1.0});
  }
  // Pillars on an irregular grid in the eastern half.
  for (int i = 0; i < 4; ++i)
    for (int j = 0; j < 5; ++j)
    {
      const double x = 28.0 + i * 5.0 + (j % 2) * 1.2, y = 5.0 + j * 8.0 + (i % 3) * 0.7;
      obs.push_back({x, y, x + 0.5, y + 0.5});
    }
  obs.push_back({25.0, 0.0, 25.2, 20.0});  // partition wall with a 10 m opening
  obs.push_back({25.0, 30.0, 25.2, 50.0});
  obs.push_back({40.0, 42.0, 48.0, 46.0});  // machine
  obs.push_back({2.0, 44.0, 6.0, 48.0});    // office box
  obs.push_back({44.0, 2.0, 46.0, 12.0});   // conveyor
  return makeWorld(50.0, 50.0, resolution, obs);
}

DriveSimulator::DriveSimulator(const GridMap& world, const std::vector<Point2D>& waypoints, const LaserSpec& laser,
                               const OdometryNoise& noise, double speed, double turn_rate, unsigned seed)
    : world_(world),
      waypoints_(waypoints),
      laser_(laser),
      noise_(noise),
      speed_(speed),
      turn_rate_(turn_rate),
      rng_(seed)
{
  if (waypoints_.size() >= 2)
  {
    const double heading = std::atan2(waypoints_[1].y - waypoints_[0].y, waypoints_[1].x - waypoints_[0].x);
    truth_ = {waypoints_[0].x, waypoints_[0].y, heading};
  }
  else if (!waypoints_.empty())
  {
    truth_ = {waypoints_[0].x, waypoints_[0].y, 0.0};
  }
  odom_ = truth_;
}

double DriveSimulator::duration() const
{
  double t = 0.0, heading = truth_.theta;
  for (size_t i = 1; i < waypoints_.size(); ++i)
  {
    const double dx = waypoints_[i].x - waypoints_[i - 1].x, dy = waypoints_[i].y - waypoints_[i - 1].y;
    const double h = std::atan2(dy, dx);
    t += std::abs(normalizeAngle(h - heading)) / turn_rate_ + std::hypot(dx, dy) / speed_;
    heading = h;
  }
  return t;
}

std::vector<float> DriveSimulator::scan()
{
  std::vector<float> ranges =
      simulateScan(world_, truth_, laser_.angle_min, laser_.angleIncrement(), laser_.beams, laser_.range_max);
  std::normal_distribution<float> noise(0.0f, static_cast<float>(laser_.noise_sd));
  for (float& r : ranges)
    if (std::isfinite(r))
      r += noise(rng_);
  return ranges;
}

bool DriveSimulator::next(DriveSample& out, bool with_scan)
{
  if (target_ >= waypoints_.size())
    return false;
  const double dt = 1.0 / laser_.rate;
  const Point2D goal = waypoints_[target_];
  const double dx = goal.x - truth_.x, dy = goal.y - truth_.y;
  const double dist = std::hypot(dx, dy);
  const double heading_err = normalizeAngle(std::atan2(dy, dx) - truth_.theta);
  Pose2D step;  // motion in the robot frame over dt
  if (dist < 1e-6)
  {
    ++target_;
  }
  else if (std::abs(heading_err) > 1e-6)
  {
    step.theta = std::clamp(heading_err, -turn_rate_ * dt, turn_rate_ * dt);
  }
  else
  {
    step.x = std::min(dist, speed_ * dt);
    if (step.x >= dist)
      ++target_;
  }
  if (std::abs(heading_err) <= 1e-6 && dist >= 1e-6)
    truth_.theta = std::atan2(dy, dx);  // keep straight segments exact
  truth_ = compose(truth_, step);
  std::normal_distribution<double> n01(0.0, 1.0);
  Pose2D noisy = step;
  const double d = std::abs(step.x), r = std::abs(step.theta);
  noisy.x += n01(rng_) * noise_.alpha_trans * d;
  noisy.theta += n01(rng_) * (noise_.alpha_rot * r) + noise_.drift_rot * d;
  odom_ = compose(odom_, noisy);
  stamp_ += dt;
  out.stamp = stamp_;
  out.truth = truth_;
  out.odom = odom_;
  out.ranges.clear();
  if (with_scan)
    out.ranges = scan();
  return true;
}

}  // namespace mybot_navigation

#include <ctime>

namespace mybot_navigation
{
namespace
{
double cpuSeconds()
{
  timespec ts;
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
  return ts.tv_sec + 1e-9 * ts.tv_nsec;
}
}  // namespace

OfflineRun runSlamOnDrive(Slam& slam, DriveSimulator& drive, const LaserSpec& laser, double max_usable_range)
{
  OfflineRun run;
  DriveSample s;
  const ScanGeometry geometry;
  while (drive.next(s, false))
  {
    double t0 = cpuSeconds();
    const bool wanted = slam.wantsScan(s.stamp, s.odom);
    if (!wanted)
      slam.updateOdometry(s.odom);
    run.slam_cpu_seconds += cpuSeconds() - t0;
    ++run.scans;
    run.sim_seconds = s.stamp;
    if (!wanted)
      continue;
    s.ranges = drive.scan();
    t0 = cpuSeconds();
    const RangeScan scan = convertRanges(s.ranges, laser.angle_min, laser.angleIncrement(), laser.range_min,
                                         laser.range_max, max_usable_range, geometry);
    const ScanOutcome outcome = slam.addScan(s.stamp, s.odom, scan);
    run.slam_cpu_seconds += cpuSeconds() - t0;
    if (outcome == ScanOutcome::Processed)
    {
      run.truth.push_back(s.truth);
      run.odometry.push_back(s.odom);
    }
  }
  for (const Keyframe& k : slam.keyframes())
    run.estimate.push_back(k.pose);
  return run;
}

}  // namespace mybot_navigation
