#include "mybot_amcl/amcl_models.h"

#include <algorithm>
#include <cmath>

#include "mybot_nav_common/costmap_distance.h"
#include "mybot_nav_common/ray_cast.h"

namespace mybot_navigation
{

bool parseOdomModelType(const std::string& name, OdomModelType& type)
{
  if (name == "diff")
    type = OdomModelType::Diff;
  else if (name == "omni")
    type = OdomModelType::Omni;
  else if (name == "diff-corrected")
    type = OdomModelType::DiffCorrected;
  else if (name == "omni-corrected")
    type = OdomModelType::OmniCorrected;
  else
    return false;
  return true;
}

namespace
{

double angleDiff(double a, double b)
{
  return wrapAngle(a - b);
}

double gaussian(Rng& rng, double sd)
{
  if (!(sd > 0.0))
    return 0.0;
  return std::normal_distribution<double>(0.0, sd)(rng);
}

}  // namespace

void MotionModel::apply(const Pose2D& odom_old, const Pose2D& odom_new, std::vector<Pose2D*>& poses, Rng& rng) const
{
  const double dx = odom_new.x - odom_old.x, dy = odom_new.y - odom_old.y;
  const double dtheta = angleDiff(odom_new.theta, odom_old.theta);
  const MotionNoise& a = noise_;
  const bool corrected = type_ == OdomModelType::DiffCorrected || type_ == OdomModelType::OmniCorrected;
  // amcl's uncorrected models pass the variance expression as the standard deviation.
  auto sd = [corrected](double variance) { return corrected ? std::sqrt(std::max(0.0, variance)) : variance; };

  if (type_ == OdomModelType::Diff || type_ == OdomModelType::DiffCorrected)
  {
    const double trans = std::hypot(dx, dy);
    // Rotation before a (near) pure spin is meaningless: amcl's 1 cm threshold.
    const double rot1 = trans < 0.01 ? 0.0 : angleDiff(std::atan2(dy, dx), odom_old.theta);
    const double rot2 = angleDiff(dtheta, rot1);
    // Driving backwards is not a half turn: take the smaller of forward/backward rotation.
    const double rot1_noise = std::min(std::abs(angleDiff(rot1, 0.0)), std::abs(angleDiff(rot1, M_PI)));
    const double rot2_noise = std::min(std::abs(angleDiff(rot2, 0.0)), std::abs(angleDiff(rot2, M_PI)));
    const double sd_rot1 = sd(a.alpha1 * rot1_noise * rot1_noise + a.alpha2 * trans * trans);
    const double sd_trans =
        sd(a.alpha3 * trans * trans + a.alpha4 * rot1_noise * rot1_noise + a.alpha4 * rot2_noise * rot2_noise);
    const double sd_rot2 = sd(a.alpha1 * rot2_noise * rot2_noise + a.alpha2 * trans * trans);
    for (Pose2D* p : poses)
    {
      const double rot1_hat = angleDiff(rot1, gaussian(rng, sd_rot1));
      const double trans_hat = trans - gaussian(rng, sd_trans);
      const double rot2_hat = angleDiff(rot2, gaussian(rng, sd_rot2));
      p->x += trans_hat * std::cos(p->theta + rot1_hat);
      p->y += trans_hat * std::sin(p->theta + rot1_hat);
      p->theta = wrapAngle(p->theta + rot1_hat + rot2_hat);
    }
    return;
  }

  const double trans = std::hypot(dx, dy), rot = dtheta;
  double sd_trans, sd_rot, sd_strafe;
  if (corrected)
  {
    sd_trans = std::sqrt(a.alpha3 * trans * trans + a.alpha1 * rot * rot);
    sd_rot = std::sqrt(a.alpha4 * trans * trans + a.alpha2 * rot * rot);
    sd_strafe = std::sqrt(a.alpha1 * rot * rot + a.alpha5 * trans * trans);
  }
  else
  {
    sd_trans = a.alpha3 * trans + a.alpha1 * std::abs(rot);
    sd_rot = a.alpha4 * std::abs(rot) + a.alpha2 * trans;
    sd_strafe = a.alpha1 * std::abs(rot) + a.alpha5 * trans;
  }
  const double bearing_in_odom = trans > 0.0 ? angleDiff(std::atan2(dy, dx), odom_old.theta) : 0.0;
  for (Pose2D* p : poses)
  {
    const double bearing = bearing_in_odom + p->theta;
    const double c = std::cos(bearing), s = std::sin(bearing);
    const double trans_hat = trans + gaussian(rng, sd_trans);
    const double rot_hat = rot + gaussian(rng, sd_rot);
    const double strafe_hat = gaussian(rng, sd_strafe);
    p->x += trans_hat * c + strafe_hat * s;
    p->y += trans_hat * s - strafe_hat * c;
    p->theta = wrapAngle(p->theta + rot_hat);
  }
}

Pose2D MotionModel::sample(const Pose2D& pose, const Pose2D& odom_old, const Pose2D& odom_new, Rng& rng) const
{
  Pose2D p = pose;
  std::vector<Pose2D*> one{&p};
  apply(odom_old, odom_new, one, rng);
  return p;
}

void LikelihoodField::setMap(const GridMap& map)
{
  info_ = map.info;
  inverse_origin_ = inverse(map.info.origin);
  const size_t n = map.data.size();
  std::vector<uint8_t> seed(n);
  known_.resize(n);
  for (size_t i = 0; i < n; ++i)
  {
    seed[i] = map.data[i] >= params_.occupied_threshold ? 1 : 0;
    known_[i] = map.data[i] != GridMap::kUnknown ? 1 : 0;
  }
  occupied_ = seed;
  dist_ = distanceTransform(seed, info_.width, info_.height);
  gauss_.resize(n);
  const double max_d = params_.likelihood_max_dist;
  const double denom = 2.0 * params_.sigma_hit * params_.sigma_hit;
  for (size_t i = 0; i < n; ++i)
  {
    // Centre-to-centre distance minus half a cell approximates the distance to the obstacle's
    // surface (amcl's plain cell distance biases poses by half a cell). Cells inside obstacles
    // read 0 here; weight() scores their end points by gaussBehindSurface.
    const double centres = static_cast<double>(dist_[i]) * info_.resolution;
    const double d = seed[i] ? 0.0 : std::min(std::max(0.0, centres - 0.5 * info_.resolution), max_d);
    dist_[i] = static_cast<float>(d);
    gauss_[i] = static_cast<float>(std::exp(-d * d / denom));
  }
  gauss_off_map_ = static_cast<float>(std::exp(-max_d * max_d / denom));
  // Below 4 sigma the Gaussian is < 4e-4 of a hit: no need to walk further.
  depth_cap_cells_ = std::min(4.0 * params_.sigma_hit, max_d) / info_.resolution;
}

double LikelihoodField::gaussBehindSurface(double x, double y, double angle) const
{
  // Walk the cells back along the beam until one is outside the obstacle: the depth is where the
  // beam crossed into the last obstacle cell. Beyond the cap the Gaussian is ~0 anyway.
  const double cap = depth_cap_cells_;
  double depth = cap;
  traceSegmentEntries(x, y, x - cap * std::cos(angle), y - cap * std::sin(angle),
                      [&](int cx, int cy, double t)
                      {
                        if (t == 0.0)
                          return true;  // the end point's own cell
                        if (cx < 0 || cy < 0 || cx >= info_.width || cy >= info_.height ||
                            !occupied_[static_cast<size_t>(cy) * info_.width + cx])
                        {
                          depth = t * cap;
                          return false;
                        }
                        return true;
                      });
  const double d = depth * info_.resolution;
  return std::exp(-d * d / (2.0 * params_.sigma_hit * params_.sigma_hit));
}

LaserScanData laserScanData(const std::vector<float>& ranges, double angle_min, double angle_increment,
                            double range_min, double range_max, double laser_min_range, double laser_max_range,
                            const Pose2D& sensor_in_base, bool upside_down)
{
  LaserScanData data;
  data.sensor_in_base = sensor_in_base;
  data.range_max = laser_max_range > 0.0 ? std::min(laser_max_range, range_max) : range_max;
  const double usable_min = laser_min_range > 0.0 ? std::max(laser_min_range, range_min) : range_min;
  const double sign = upside_down ? -1.0 : 1.0;
  data.readings.reserve(ranges.size());
  for (size_t i = 0; i < ranges.size(); ++i)
  {
    double r = ranges[i];
    if (!(r > usable_min) || !std::isfinite(r))
      r = data.range_max;
    data.readings.push_back({r, sign * (angle_min + angle_increment * static_cast<double>(i))});
  }
  return data;
}

double LikelihoodField::distance(double x, double y) const
{
  const Point2D local = transformPoint(inverse_origin_, {x, y});
  const int cx = cellIndex(local.x / info_.resolution);
  const int cy = cellIndex(local.y / info_.resolution);
  if (cx < 0 || cy < 0 || cx >= info_.width || cy >= info_.height)
    return params_.likelihood_max_dist;
  return dist_[static_cast<size_t>(cy) * info_.width + cx];
}

namespace
{
// amcl: step = (range_count - 1) / (max_beams - 1), integer division, at least 1.
size_t beamStep(size_t count, int max_beams)
{
  const size_t step = max_beams > 1 ? (count - 1) / static_cast<size_t>(max_beams - 1) : count;
  return std::max<size_t>(step, 1);
}
}  // namespace

std::vector<size_t> LikelihoodField::beamIndices(size_t count) const
{
  std::vector<size_t> out;
  if (count == 0)
    return out;
  const size_t step = beamStep(count, params_.max_beams);
  for (size_t i = 0; i < count; i += step)
    out.push_back(i);
  return out;
}

double LikelihoodField::maxWeight(const LaserScanData& scan) const
{
  const double pz = params_.z_hit + params_.z_rand / scan.range_max;
  double p = 1.0;
  for (size_t i : beamIndices(scan.readings.size()))  // the beams weight() uses
    if (scan.readings[i].range < scan.range_max)
      p += pz * pz * pz;
  return p;
}

long LikelihoodField::endCell(const Pose2D& sensor, double inv_res, const LaserReading& r, double* x, double* y) const
{
  const double a = sensor.theta + r.bearing;
  const double ex = (sensor.x + r.range * std::cos(a)) * inv_res, ey = (sensor.y + r.range * std::sin(a)) * inv_res;
  if (x && y)
    *x = ex, *y = ey;
  const int cx = cellIndex(ex), cy = cellIndex(ey);
  if (cx < 0 || cy < 0 || cx >= info_.width || cy >= info_.height)
    return -1;
  return static_cast<long>(cy) * info_.width + cx;
}

double LikelihoodField::maxWeightSeenFrom(const Pose2D& robot, const LaserScanData& scan) const
{
  const Pose2D s = compose(inverse_origin_, compose(robot, scan.sensor_in_base));
  const double inv_res = 1.0 / info_.resolution;
  const double pz = params_.z_hit + params_.z_rand / scan.range_max;
  int used = 0, known = 0;
  for (size_t i : beamIndices(scan.readings.size()))
  {
    const LaserReading& r = scan.readings[i];
    if (!(r.range < scan.range_max))
      continue;
    ++used;
    const long cell = endCell(s, inv_res, r);
    if (cell >= 0 && known_[static_cast<size_t>(cell)])
      ++known;
  }
  return 1.0 + std::max(known, (used + 3) / 4) * pz * pz * pz;
}

double LikelihoodField::seeThroughShare(const Pose2D& robot, const LaserScanData& scan, double margin) const
{
  // In cell units, relative to the map's origin, as traceSegment wants them.
  const Pose2D s = compose(inverse_origin_, compose(robot, scan.sensor_in_base));
  const double inv_res = 1.0 / info_.resolution;
  int used = 0, through = 0;
  for (size_t i : beamIndices(scan.readings.size()))
  {
    const LaserReading& r = scan.readings[i];
    if (!(r.range < scan.range_max))
      continue;
    ++used;
    const double free_length = r.range - margin;
    if (free_length <= 0.0)
      continue;
    const double a = s.theta + r.bearing;
    bool blocked = false;
    traceSegment(s.x * inv_res, s.y * inv_res, (s.x + free_length * std::cos(a)) * inv_res,
                 (s.y + free_length * std::sin(a)) * inv_res,
                 [&](int cx, int cy)
                 {
                   if (cx < 0 || cy < 0 || cx >= info_.width || cy >= info_.height)
                     return false;  // off the map: nothing more to cross
                   blocked = occupied_[static_cast<size_t>(cy) * info_.width + cx] != 0;
                   return !blocked;
                 });
    if (blocked)
      ++through;
  }
  return used > 0 ? static_cast<double>(through) / used : 0.0;
}

double LikelihoodField::weight(const Pose2D& robot, const LaserScanData& scan) const
{
  const Pose2D sensor = compose(robot, scan.sensor_in_base);
  // Work in map-cell coordinates so the inner loop is a multiply-add and a lookup.
  const Pose2D s = compose(inverse_origin_, sensor);
  const double inv_res = 1.0 / info_.resolution;
  const double z_rand_term = params_.z_rand / scan.range_max;
  double p = 1.0;
  const size_t count = scan.readings.size();
  const size_t step = beamStep(count, params_.max_beams);
  for (size_t i = 0; i < count; i += step)
  {
    const LaserReading& r = scan.readings[i];
    if (!(r.range < scan.range_max))  // also skips NaN
      continue;
    double ex, ey;
    const long cell = endCell(s, inv_res, r, &ex, &ey);
    const double g = cell < 0                               ? gauss_off_map_
                     : occupied_[static_cast<size_t>(cell)] ? gaussBehindSurface(ex, ey, s.theta + r.bearing)
                                                            : gauss_[static_cast<size_t>(cell)];
    const double pz = params_.z_hit * g + z_rand_term;
    p += pz * pz * pz;
  }
  return p;
}

}  // namespace mybot_navigation
