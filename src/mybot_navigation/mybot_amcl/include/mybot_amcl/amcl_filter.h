// Particle filter with KLD-adaptive resampling and random-particle recovery, after amcl's pf.c
// (Fox 2003; Thrun et al. ch. 8.3). No ROS types.
#pragma once

#include <array>
#include <functional>
#include <vector>

#include "mybot_amcl/amcl_models.h"

namespace mybot_navigation
{

struct Particle
{
  Pose2D pose;
  double weight = 0.0;
};

struct FilterParams
{
  int min_particles = 100;               // min_particles
  int max_particles = 5000;              // max_particles
  double kld_err = 0.01;                 // kld_err
  double kld_z = 0.99;                   // kld_z (upper standard normal quantile 1 - delta)
  double alpha_slow = 0.0;               // recovery_alpha_slow (0 disables recovery)
  double alpha_fast = 0.0;               // recovery_alpha_fast
  double recovery_trigger_ratio = 0.5;   // ours: lost (random particles) once w_fast < this * w_slow
  double recovery_release_ratio = 0.95;  // ours: ... until w_fast >= this * w_slow again,
  double recovery_accept_ratio = 0.8;    // ours: or until w_fast has stayed >= this * w_slow
  int recovery_accept_updates = 250;     // ours: for this many sensor updates
  // ours: recovery stops only at a place from which at most this share of the beams would pass
  // through a mapped wall (1 turns the check off); see Amcl::plausible.
  double recovery_max_see_through = 0.15;
  // amcl's kd-tree histogram bin size used to count occupied bins for the KLD bound.
  std::array<double, 3> bin_size{{0.5, 0.5, 10.0 * M_PI / 180.0}};
};

// 3x3 covariance of (x, y, theta), row-major.
using Cov3 = std::array<double, 9>;

struct PoseEstimate
{
  Pose2D mean;
  Cov3 cov{};           // of the whole set; cov[8] is the circular variance of theta
  double weight = 0.0;  // weight of the best cluster
  int clusters = 0;
};

class ParticleFilter
{
public:
  using PoseGenerator = std::function<Pose2D(Rng&)>;

  explicit ParticleFilter(const FilterParams& params = FilterParams(), unsigned seed = 0);

  // Sets max_particles samples from a Gaussian (diagonal cov: var x, var y, var theta).
  void initGaussian(const Pose2D& mean, double var_x, double var_y, double var_a);
  // Sets max_particles samples from a generator (global localization).
  void initFromGenerator(const PoseGenerator& gen);

  // Motion update: moves every particle.
  void predict(const MotionModel& model, const Pose2D& odom_old, const Pose2D& odom_new);
  // Sensor update: multiplies weights by the likelihood, normalises, tracks w_slow/w_fast.
  // Returns false if every weight vanished (weights are then reset to uniform).
  // `floor` and `ceiling` bound the likelihood for this measurement (a pose that explains
  // nothing / everything): the recovery averages track where the posterior sits between them.
  bool correct(const std::function<double(const Pose2D&)>& likelihood, double floor = 0.0, double ceiling = 1.0);
  // Asked before recovery stops at the current cloud; false keeps it searching.
  using ReleaseCheck = std::function<bool()>;

  // KLD resampling; `random_pose` supplies recovery particles (may be empty: no recovery).
  // `may_release` (may be empty: always) vetoes stopping the recovery at the current cloud.
  void resample(const PoseGenerator& random_pose, const ReleaseCheck& may_release = ReleaseCheck());

  PoseEstimate estimate() const;

  const std::vector<Particle>& particles() const { return particles_; }
  std::vector<Particle>& particles() { return particles_; }
  const FilterParams& params() const { return params_; }
  double wSlow() const { return w_slow_; }
  double wFast() const { return w_fast_; }
  // Recovery is adding random particles (the fit fell below recovery_trigger_ratio).
  bool lost() const { return lost_; }
  // The last resample would have stopped the recovery, but `may_release` said no.
  bool releaseVetoed() const { return release_vetoed_; }
  Rng& rng() { return rng_; }

  // amcl's pf_resample_limit: samples needed for `k` occupied bins.
  int resampleLimit(int k) const;

private:
  FilterParams params_;
  Rng rng_;
  std::vector<Particle> particles_;
  double w_slow_ = 0.0, w_fast_ = 0.0;
  bool have_averages_ = false;
  bool lost_ = false;
  bool release_vetoed_ = false;
  int accept_count_ = 0;  // updates since the lost filter last fitted recovery_accept_ratio or worse
};

}  // namespace mybot_navigation
