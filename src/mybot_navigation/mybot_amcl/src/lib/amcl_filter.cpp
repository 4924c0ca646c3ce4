#include "mybot_amcl/amcl_filter.h"

#include <algorithm>
#include <cmath>
#include <numeric>
#include <unordered_map>

namespace mybot_navigation
{
namespace
{

struct BinKey
{
  int x, y, a;
  bool operator==(const BinKey& o) const { return x == o.x && y == o.y && a == o.a; }
};

struct BinKeyHash
{
  size_t operator()(const BinKey& k) const
  {
    return (static_cast<size_t>(static_cast<uint32_t>(k.x)) * 73856093u) ^
           (static_cast<size_t>(static_cast<uint32_t>(k.y)) * 19349663u) ^
           (static_cast<size_t>(static_cast<uint32_t>(k.a)) * 83492791u);
  }
};

BinKey binOf(const Pose2D& p, const std::array<double, 3>& size, int a_bins)
{
  // Heading bins are indexed 0..a_bins-1 from -pi so that neighbours wrap with a modulo.
  int a = cellIndex((wrapAngle(p.theta) + M_PI) / size[2]);
  a = ((a % a_bins) + a_bins) % a_bins;
  return {cellIndex(p.x / size[0]), cellIndex(p.y / size[1]), a};
}

int headingBins(const std::array<double, 3>& size)
{
  return std::max(1, static_cast<int>(std::ceil(2.0 * M_PI / size[2])));
}

}  // namespace

ParticleFilter::ParticleFilter(const FilterParams& params, unsigned seed) : params_(params), rng_(seed) {}

void ParticleFilter::initGaussian(const Pose2D& mean, double var_x, double var_y, double var_a)
{
  std::normal_distribution<double> n(0.0, 1.0);
  particles_.assign(static_cast<size_t>(params_.max_particles), Particle());
  const double w = 1.0 / params_.max_particles;
  for (Particle& p : particles_)
  {
    p.pose = {mean.x + std::sqrt(std::max(0.0, var_x)) * n(rng_), mean.y + std::sqrt(std::max(0.0, var_y)) * n(rng_),
              wrapAngle(mean.theta + std::sqrt(std::max(0.0, var_a)) * n(rng_))};
    p.weight = w;
  }
  have_averages_ = lost_ = false;
  accept_count_ = 0;
}

void ParticleFilter::initFromGenerator(const PoseGenerator& gen)
{
  particles_.assign(static_cast<size_t>(params_.max_particles), Particle());
  const double w = 1.0 / params_.max_particles;
  for (Particle& p : particles_)
  {
    p.pose = gen(rng_);
    p.weight = w;
  }
  have_averages_ = lost_ = false;
  accept_count_ = 0;
}

void ParticleFilter::predict(const MotionModel& model, const Pose2D& odom_old, const Pose2D& odom_new)
{
  std::vector<Pose2D*> poses;
  poses.reserve(particles_.size());
  for (Particle& p : particles_)
    poses.push_back(&p.pose);
  model.apply(odom_old, odom_new, poses, rng_);
}

bool ParticleFilter::correct(const std::function<double(const Pose2D&)>& likelihood, double floor, double ceiling)
{
  double total = 0.0, total_times_l = 0.0;
  for (Particle& p : particles_)
  {
    const double l = likelihood(p.pose);
    p.weight *= l;
    total += p.weight;
    total_times_l += p.weight * l;
  }
  if (!(total > 0.0) || !std::isfinite(total))
  {
    const double w = 1.0 / particles_.size();
    for (Particle& p : particles_)
      p.weight = w;
    return false;
  }
  for (Particle& p : particles_)
    p.weight /= total;
  // Recovery statistic: how well the posterior explains the measurement, as a share of the
  // way from `floor` to `ceiling`. amcl averages the raw weights instead (mean likelihood
  // divided by the particle count), which moves with the particle count and with how many
  // beams return, more than with being lost.
  const double fit = ceiling > floor ? std::clamp((total_times_l / total - floor) / (ceiling - floor), 0.0, 1.0) : 0.0;
  if (!have_averages_)
  {
    w_slow_ = w_fast_ = fit;
    have_averages_ = true;
    return true;
  }
  // w_slow holds the fit of a localized filter: it rises as fast as w_fast and decays at
  // alpha_slow. amcl's plain slow average starts from the unconverged filter and needs
  // ~1/alpha_slow updates to learn what "localized" looks like; a kidnapping before then
  // goes unnoticed.
  w_slow_ += (fit > w_slow_ ? params_.alpha_fast : params_.alpha_slow) * (fit - w_slow_);
  w_fast_ += params_.alpha_fast * (fit - w_fast_);
  return true;
}

int ParticleFilter::resampleLimit(int k) const
{
  if (k <= 1)
    return params_.max_particles;
  const double a = 1.0;
  const double b = 2.0 / (9.0 * (k - 1));
  const double c = std::sqrt(2.0 / (9.0 * (k - 1))) * params_.kld_z;
  const double x = a - b + c;
  const int n = static_cast<int>(std::ceil((k - 1) / (2.0 * params_.kld_err) * x * x * x));
  return std::clamp(n, params_.min_particles, params_.max_particles);
}

void ParticleFilter::resample(const PoseGenerator& random_pose, const ReleaseCheck& may_release)
{
  if (particles_.empty())
    return;
  // Random particles replace a share 1 - w_fast / w_slow of the cloud (amcl), but only while
  // lost: from when the fit drops below recovery_trigger_ratio of the localized one until it
  // is back above recovery_release_ratio. Smaller dips are the scene, and any random particle
  // spreads the cloud over new histogram bins, which drives the KLD sample count to
  // max_particles; a cloud that settled on a wrong place fitting half as well keeps searching.
  // A place that fits between recovery_accept_ratio and recovery_release_ratio is accepted only
  // after recovery_accept_updates updates in which the search found nothing better: in the
  // factory a rack 9.4 m from the robot fits 80-90 % as well as the true place (1 kidnap run in
  // 20 stopped there with the release at 0.8), while the scene where the robot really is may
  // fit less well than the one where it was localized (people, moved furniture).
  // Either way the place must pass `may_release`: in the factory the lookalike rack reached 95 %
  // in 1 kidnap run of 20, but from there a third of the beams would cross a wall.
  double w_diff = 0.0;
  release_vetoed_ = false;
  if (random_pose && w_slow_ > 0.0)
  {
    const double ratio = w_fast_ / w_slow_;
    bool release = false;
    if (ratio < params_.recovery_trigger_ratio)
      lost_ = true;
    else if (ratio >= params_.recovery_release_ratio)
      release = true;
    if (lost_ && ratio >= params_.recovery_accept_ratio)
    {
      if (++accept_count_ > params_.recovery_accept_updates)
        release = true;
    }
    else
      accept_count_ = 0;
    if (lost_ && release)
    {
      if (!may_release || may_release())
        lost_ = false;
      else
        release_vetoed_ = true;
    }
    // A vetoed place counts as fitting no better than recovery_accept_ratio: at 95 % and more,
    // 1 - ratio would add almost no random particles, and the search would stall there.
    if (lost_)
      w_diff = release_vetoed_ ? std::max(1.0 - ratio, 1.0 - params_.recovery_accept_ratio) : 1.0 - ratio;
  }
  else
    lost_ = false;

  // Cumulative weights for multinomial draws (amcl's pf_update_resample).
  std::vector<double> cumulative(particles_.size());
  double acc = 0.0;
  for (size_t i = 0; i < particles_.size(); ++i)
  {
    acc += particles_[i].weight;
    cumulative[i] = acc;
  }
  std::uniform_real_distribution<double> uni(0.0, 1.0);
  std::unordered_map<BinKey, int, BinKeyHash> bins;
  const int a_bins = headingBins(params_.bin_size);
  std::vector<Particle> next;
  next.reserve(static_cast<size_t>(params_.max_particles));
  while (static_cast<int>(next.size()) < params_.max_particles)
  {
    Particle p;
    if (w_diff > 0.0 && uni(rng_) < w_diff)
    {
      p.pose = random_pose(rng_);
    }
    else
    {
      const double r = uni(rng_) * acc;
      size_t i = static_cast<size_t>(std::lower_bound(cumulative.begin(), cumulative.end(), r) - cumulative.begin());
      i = std::min(i, particles_.size() - 1);
      p.pose = particles_[i].pose;
    }
    p.weight = 1.0;
    next.push_back(p);
    bins[binOf(p.pose, params_.bin_size, a_bins)]++;
    if (static_cast<int>(next.size()) > resampleLimit(static_cast<int>(bins.size())))
      break;
  }
  // Unlike amcl, the averages are not restarted after random particles were added: they keep
  // coming while the fit stays low, and stop once a particle has found the robot.
  const double w = 1.0 / next.size();
  for (Particle& p : next)
    p.weight = w;
  particles_.swap(next);
}

PoseEstimate ParticleFilter::estimate() const
{
  PoseEstimate est;
  if (particles_.empty())
    return est;

  // Cluster particles by connected occupied histogram bins (amcl's kd-tree clustering).
  std::unordered_map<BinKey, int, BinKeyHash> bin_cluster;
  const int a_bins = headingBins(params_.bin_size);
  for (const Particle& p : particles_)
    bin_cluster.emplace(binOf(p.pose, params_.bin_size, a_bins), -1);
  int clusters = 0;
  std::vector<BinKey> stack;
  for (auto& kv : bin_cluster)
  {
    if (kv.second >= 0)
      continue;
    kv.second = clusters;
    stack.push_back(kv.first);
    while (!stack.empty())
    {
      const BinKey k = stack.back();
      stack.pop_back();
      for (int dx = -1; dx <= 1; ++dx)
        for (int dy = -1; dy <= 1; ++dy)
          for (int da = -1; da <= 1; ++da)
          {
            const BinKey n{k.x + dx, k.y + dy, (k.a + da + a_bins) % a_bins};
            auto it = bin_cluster.find(n);
            if (it != bin_cluster.end() && it->second < 0)
            {
              it->second = clusters;
              stack.push_back(it->first);
            }
          }
    }
    ++clusters;
  }

  struct Acc
  {
    double w = 0, x = 0, y = 0, c = 0, s = 0;
  };
  std::vector<Acc> accs(static_cast<size_t>(clusters));
  double total = 0.0, mx = 0.0, my = 0.0, mc = 0.0, ms = 0.0, xx = 0.0, xy = 0.0, yy = 0.0;
  for (const Particle& p : particles_)
  {
    Acc& a = accs[static_cast<size_t>(bin_cluster[binOf(p.pose, params_.bin_size, a_bins)])];
    const double w = p.weight;
    a.w += w;
    a.x += w * p.pose.x;
    a.y += w * p.pose.y;
    a.c += w * std::cos(p.pose.theta);
    a.s += w * std::sin(p.pose.theta);
    total += w;
    mx += w * p.pose.x;
    my += w * p.pose.y;
    mc += w * std::cos(p.pose.theta);
    ms += w * std::sin(p.pose.theta);
    xx += w * p.pose.x * p.pose.x;
    xy += w * p.pose.x * p.pose.y;
    yy += w * p.pose.y * p.pose.y;
  }
  size_t best = 0;
  for (size_t i = 1; i < accs.size(); ++i)
    if (accs[i].w > accs[best].w)
      best = i;
  const Acc& b = accs[best];
  est.mean = {b.x / b.w, b.y / b.w, std::atan2(b.s, b.c)};
  est.weight = b.w / total;
  est.clusters = clusters;
  mx /= total;
  my /= total;
  mc /= total;
  ms /= total;
  est.cov = {xx / total - mx * mx,
             xy / total - mx * my,
             0.0,
             xy / total - mx * my,
             yy / total - my * my,
             0.0,
             0.0,
             0.0,
             -2.0 * std::log(std::max(1e-12, std::hypot(mc, ms)))};
  return est;
}

}  // namespace mybot_navigation
