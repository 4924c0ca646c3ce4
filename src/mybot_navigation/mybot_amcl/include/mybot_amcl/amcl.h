// Adaptive Monte Carlo localization: the decision logic of amcl's laser callback (update_min_d/a,
// resample_interval, forced updates, global localization, initial pose) around the particle
// filter and models, as a library with no ROS types. The node only converts messages and tf.
#pragma once

#include <string>
#include <vector>

#include "mybot_amcl/amcl_filter.h"
#include "mybot_amcl/amcl_models.h"

namespace mybot_navigation
{

struct AmclParams
{
  FilterParams filter;
  LaserModelParams laser;
  OdomModelType odom_model = OdomModelType::Diff;  // odom_model_type (amcl default "diff")
  MotionNoise odom_noise;                          // odom_alpha1..5
  double update_min_d = 0.2;                       // m
  double update_min_a = M_PI / 6.0;                // rad
  int resample_interval = 2;
  Pose2D initial_pose;  // initial_pose_x, _y, _a
  double initial_cov_xx = 0.5 * 0.5;
  double initial_cov_yy = 0.5 * 0.5;
  double initial_cov_aa = (M_PI / 12.0) * (M_PI / 12.0);
  unsigned seed = 0;
};

// Empty string when valid, else a message naming the first bad amcl parameter.
std::string validate(const AmclParams& p);

class Amcl
{
public:
  explicit Amcl(const AmclParams& params);

  // Sets the map; resets the filter to the initial pose (amcl does this on every new map).
  void setMap(const GridMap& map);
  bool hasMap() const { return field_.hasMap(); }

  // Re-initialises the filter around a pose (initialpose topic / initial_pose_* parameters).
  void setInitialPose(const Pose2D& pose, double var_x, double var_y, double var_a);
  // Starts over as at launch after time went backwards (a simulation reset sends the robot back
  // to its spawn pose and the odometry to zero; a bag played again, to its start): a cloud
  // around `pose` and no odometry reference, so the jump of the odometry is not taken for
  // motion.
  void restart(const Pose2D& pose, double var_x, double var_y, double var_a);
  // Spreads max_particles uniformly over the map's free space (global_localization service).
  void globalLocalization();
  // The next scan is processed even without motion (request_nomotion_update service).
  void requestNoMotionUpdate() { force_update_ = true; }

  // Processes one scan taken when the robot's odometry pose was `odom_pose` (base in odom).
  // Returns true when the filter ran a sensor update (a new estimate is available). An odometry
  // pose that is broken (poseError: not finite, or beyond kMaxCoordinate) is no motion: the scan
  // is not used and the cloud is kept (a jump of 1e308 m turned it to NaN).
  bool processScan(const Pose2D& odom_pose, const LaserScanData& scan);

  const PoseEstimate& estimate() const { return estimate_; }
  // map -> odom correction implied by the estimate and the odometry pose it was computed at.
  Pose2D mapToOdom() const { return compose(estimate_.mean, inverse(estimate_odom_pose_)); }
  bool hasEstimate() const { return has_estimate_; }
  const std::vector<Particle>& particles() const { return filter_.particles(); }
  const ParticleFilter& filter() const { return filter_; }
  const AmclParams& params() const { return params_; }
  int updates() const { return updates_; }
  int resamples() const { return resamples_; }

  // A uniformly random pose in the map's free space.
  Pose2D randomFreePose(Rng& rng) const;

  // Whether recovery may stop at `pose` for this scan: some pose within 0.1 m and 2.3 degrees of
  // it (the cloud's mean is that far off while it settles) sends at most
  // recovery_max_see_through of the beams through a mapped wall.
  bool plausible(const Pose2D& pose, const LaserScanData& scan);
  // The smallest see-through share plausible() found at its last call.
  double lastSeeThrough() const { return last_see_through_; }
  // Whether the next sensor update weighs particles with the search's wider field (sigma_hit at
  // least 0.2 m): after global localization, until one cluster holds 90 % of the weight.
  bool searching() const { return searching_; }

private:
  // Global localization's first step: the best places for this scan over the whole map (an
  // exhaustive correlative search, Olson 2009, at one resolution), refined with the tracking field.
  std::vector<Pose2D> candidatePlaces(const LaserScanData& scan) const;
  // Places max_particles around the candidate places, a tenth of them uniformly.
  void seedFromScan(const LaserScanData& scan);

  AmclParams params_;
  MotionModel motion_;
  LikelihoodField field_;
  LikelihoodField search_field_;  // the same with a wider sigma_hit, for the search
  ParticleFilter filter_;
  MapInfo map_info_;
  std::vector<int> free_cells_;  // indices of free map cells for random poses
  bool odom_initialized_ = false;
  bool force_update_ = false;
  Pose2D last_odom_;  // odometry pose at the last filter update
  int resample_count_ = 0;
  PoseEstimate estimate_;
  Pose2D estimate_odom_pose_;
  bool has_estimate_ = false;
  int updates_ = 0, resamples_ = 0;
  double last_see_through_ = 0.0;
  bool searching_ = false;
  bool seed_from_next_scan_ = false;
};

}  // namespace mybot_navigation
