// AMCL's odometry motion models and likelihood-field laser model, with amcl's parameter names,
// defaults and formulas (Thrun et al., Probabilistic Robotics, ch. 5 and 6). No ROS types.
#pragma once

#include <random>
#include <string>
#include <vector>

#include "mybot_nav_common/grid_map.h"

namespace mybot_navigation
{

using Rng = std::mt19937;

// amcl's `odom_model_type`: "diff" and "omni" keep amcl's historical noise scaling (variance
// passed where a standard deviation belongs); the "-corrected" variants fix it.
enum class OdomModelType
{
  Diff,
  Omni,
  DiffCorrected,
  OmniCorrected
};

// False for an unknown name.
bool parseOdomModelType(const std::string& name, OdomModelType& type);

struct MotionNoise
{
  double alpha1 = 0.2;  // rotation noise from rotation
  double alpha2 = 0.2;  // rotation noise from translation
  double alpha3 = 0.2;  // translation noise from translation
  double alpha4 = 0.2;  // translation noise from rotation
  double alpha5 = 0.2;  // strafe noise from translation (omni only)
};

class MotionModel
{
public:
  MotionModel(OdomModelType type = OdomModelType::DiffCorrected, const MotionNoise& noise = MotionNoise())
      : type_(type), noise_(noise)
  {
  }

  // Moves every pose by the odometry motion odom_old -> odom_new with sampled noise.
  void apply(const Pose2D& odom_old, const Pose2D& odom_new, std::vector<Pose2D*>& poses, Rng& rng) const;
  // Convenience for one pose.
  Pose2D sample(const Pose2D& pose, const Pose2D& odom_old, const Pose2D& odom_new, Rng& rng) const;

  OdomModelType type() const { return type_; }
  const MotionNoise& noise() const { return noise_; }

private:
  OdomModelType type_;
  MotionNoise noise_;
};

// amcl's laser_* parameters for the likelihood field model.
struct LaserModelParams
{
  int max_beams = 30;                // laser_max_beams
  double z_hit = 0.95;               // laser_z_hit
  double z_rand = 0.05;              // laser_z_rand
  double sigma_hit = 0.2;            // laser_sigma_hit, m
  double likelihood_max_dist = 2.0;  // laser_likelihood_max_dist, m
  int occupied_threshold = 65;       // map value counted as an obstacle (map_server's 0.65)
};

// One laser reading in the base frame: range and bearing relative to the sensor.
struct LaserReading
{
  double range;
  double bearing;
};

struct LaserScanData
{
  Pose2D sensor_in_base;               // 2D pose of the laser in the robot's base frame
  double range_max = 30.0;             // readings >= this are skipped (no return)
  std::vector<LaserReading> readings;  // all beams, in order; the model subsamples max_beams
};

// A LaserScan's ranges as amcl_node takes them: range_max and range_min are the scan's, narrowed by
// laser_max_range / laser_min_range where those are positive (amcl's -1: the scan's own); a reading
// at or below range_min, or not finite, counts as max range (no information); beam i's bearing is
// angle_min + i * angle_increment, mirrored for a laser mounted upside down.
LaserScanData laserScanData(const std::vector<float>& ranges, double angle_min, double angle_increment,
                            double range_min, double range_max, double laser_min_range, double laser_max_range,
                            const Pose2D& sensor_in_base, bool upside_down);

// Likelihood field (amcl's LikelihoodFieldModel): p = 1 + sum over beams of
// (z_hit * exp(-d^2 / 2 sigma_hit^2) + z_rand / range_max)^3, d = distance from the beam end
// point to the nearest obstacle (capped at likelihood_max_dist; off-map end points use the cap).
// An end point inside an obstacle is d below the surface the beam entered by, measured back along
// the beam: the laser stops at that surface, so a pose that pushes end points into a wall ahead
// is as wrong as one that leaves them short of it. (amcl scores every point inside as a hit; the
// depth to the nearest surface, whichever side, is at most half a wall's thickness and let the
// pose lead the robot along its travel by 1-3 cm with a forward-facing laser.)
class LikelihoodField
{
public:
  explicit LikelihoodField(const LaserModelParams& params = LaserModelParams()) : params_(params) {}

  void setMap(const GridMap& map);
  bool hasMap() const { return !gauss_.empty(); }
  const LaserModelParams& params() const { return params_; }

  // Distance (m) from a map-frame point to the nearest obstacle, capped.
  double distance(double x, double y) const;
  // amcl's (unnormalised) weight factor of one robot pose for the scan.
  double weight(const Pose2D& robot, const LaserScanData& scan) const;
  // The weight of a pose that explains every beam the model uses (all end points on obstacles).
  double maxWeight(const LaserScanData& scan) const;
  // The same, counting only the beams whose end points, seen from `robot`, fall on cells the
  // map knows (free or occupied; at least a quarter of the beams). A beam that ends in unknown
  // space, such as a shelf face SLAM never saw, says nothing about whether `robot` is right.
  double maxWeightSeenFrom(const Pose2D& robot, const LaserScanData& scan) const;
  // Share of the beams the model uses that, seen from `robot`, cross a mapped obstacle more than
  // `margin` metres before their end point: beams that would have to pass through a wall. The
  // likelihood field only looks at end points, so a wrong place whose walls happen to lie where
  // the beams end scores well however many walls stand in between; a laser does not see through
  // walls (Thrun et al. 6.4 name this blindness as the field's price for its smoothness).
  double seeThroughShare(const Pose2D& robot, const LaserScanData& scan, double margin) const;
  // Indices of the beams the model uses (amcl's integer step).
  std::vector<size_t> beamIndices(size_t count) const;

private:
  // The map cell index of a beam's end point (sensor pose relative to the map origin), -1 off the
  // map; `x`, `y` (if given) receive the end point in cell units.
  long endCell(const Pose2D& sensor, double inv_res, const LaserReading& r, double* x = nullptr,
               double* y = nullptr) const;
  // exp(-d^2 / 2 sigma^2) for an end point at cell coordinates (x, y) inside an obstacle, d its
  // depth back along the beam (bearing `angle`) to the first cell outside the obstacle.
  double gaussBehindSurface(double x, double y, double angle) const;

  LaserModelParams params_;
  MapInfo info_;
  Pose2D inverse_origin_;
  std::vector<float> dist_;        // capped distance per cell
  std::vector<float> gauss_;       // exp(-d^2 / 2 sigma^2) per cell
  std::vector<uint8_t> known_;     // 1 where the map is not unknown
  std::vector<uint8_t> occupied_;  // 1 where the map holds an obstacle
  float gauss_off_map_ = 0.0f;
  double depth_cap_cells_ = 0.0;  // depth (cells) beyond which gaussBehindSurface is ~0
};

}  // namespace mybot_navigation
