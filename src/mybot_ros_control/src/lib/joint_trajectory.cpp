#include "mybot_ros_control/joint_trajectory.h"

#include <algorithm>
#include <cmath>

namespace mybot_ros_control
{

JointTrajectory JointTrajectory::hold(double t, const std::vector<double>& positions)
{
  JointTrajectory tr;
  tr.addKnot({t, positions, {}, {}});
  return tr;
}

void JointTrajectory::addKnot(const Knot& k)
{
  if (!knots_.empty())
  {
    const Knot& a = knots_.back();
    const double T = k.time - a.time;
    const bool velocities = !a.velocities.empty() && !k.velocities.empty();
    const bool accelerations = velocities && !a.accelerations.empty() && !k.accelerations.empty();
    std::vector<Poly> polys(a.positions.size());
    for (size_t j = 0; j < polys.size(); ++j)
    {
      const double p0 = a.positions[j], p1 = k.positions[j];
      Poly& c = polys[j];
      c.fill(0.0);
      c[0] = p0;
      if (!velocities)  // a straight line
      {
        c[1] = (p1 - p0) / T;
        continue;
      }
      const double v0 = a.velocities[j], v1 = k.velocities[j];
      c[1] = v0;
      if (!accelerations)  // the cubic with these end positions and velocities
      {
        c[2] = (3.0 * (p1 - p0) / T - 2.0 * v0 - v1) / T;
        c[3] = (2.0 * (p0 - p1) / T + v0 + v1) / (T * T);
        continue;
      }
      // The quintic that also meets both accelerations.
      const double a0 = a.accelerations[j], a1 = k.accelerations[j], T2 = T * T;
      c[2] = 0.5 * a0;
      c[3] = (20.0 * (p1 - p0) - (8.0 * v1 + 12.0 * v0) * T - (3.0 * a0 - a1) * T2) / (2.0 * T2 * T);
      c[4] = (30.0 * (p0 - p1) + (14.0 * v1 + 16.0 * v0) * T + (3.0 * a0 - 2.0 * a1) * T2) / (2.0 * T2 * T2);
      c[5] = (12.0 * (p1 - p0) - 6.0 * (v1 + v0) * T + (a1 - a0) * T2) / (2.0 * T2 * T2 * T);
    }
    segments_.push_back(std::move(polys));
  }
  knots_.push_back(k);
}

TrajectorySample JointTrajectory::evaluate(const std::vector<Poly>& polys, double tau)
{
  TrajectorySample s;
  for (const Poly& c : polys)
  {
    double p = 0.0, v = 0.0, a = 0.0;
    for (int i = 5; i >= 0; --i)  // Horner, each derivative from its own coefficients
      p = p * tau + c[static_cast<size_t>(i)];
    for (int i = 5; i >= 1; --i)
      v = v * tau + i * c[static_cast<size_t>(i)];
    for (int i = 5; i >= 2; --i)
      a = a * tau + i * (i - 1) * c[static_cast<size_t>(i)];
    s.positions.push_back(p);
    s.velocities.push_back(v);
    s.accelerations.push_back(a);
  }
  return s;
}

TrajectorySample JointTrajectory::sample(double t) const
{
  TrajectorySample s;
  if (knots_.empty())
    return s;
  if (segments_.empty() || t >= knots_.back().time)
  {
    s.positions = knots_.back().positions;
    s.velocities.assign(s.positions.size(), 0.0);
    s.accelerations.assign(s.positions.size(), 0.0);
    return s;
  }
  // The segment whose start is the last knot at or before t (the first one before the start).
  const auto after =
      std::upper_bound(knots_.begin(), knots_.end(), t, [](double v, const Knot& k) { return v < k.time; });
  const size_t i = after == knots_.begin() ? 0 : static_cast<size_t>(after - knots_.begin()) - 1;
  return evaluate(segments_[i], std::max(0.0, t - knots_[i].time));
}

JointTrajectory JointTrajectory::splice(double t, const std::vector<TrajectoryPoint>& points,
                                        const std::vector<bool>& wrap) const
{
  const TrajectorySample now = sample(t);
  // Until t this trajectory, its own segments: the one t falls in is kept whole and ends at the
  // knot at t (its polynomial is in the time since its start, so it stays the same curve), or,
  // past the last knot, rest there.
  JointTrajectory tr;
  size_t kept = 0;
  while (kept < knots_.size() && knots_[kept].time < t)
    ++kept;
  tr.knots_.assign(knots_.begin(), knots_.begin() + static_cast<std::ptrdiff_t>(kept));
  if (kept > 0)
  {
    tr.segments_.assign(segments_.begin(), segments_.begin() + static_cast<std::ptrdiff_t>(kept - 1));
    if (kept - 1 < segments_.size())
      tr.segments_.push_back(segments_[kept - 1]);
    else
    {
      std::vector<Poly> rest(now.positions.size());
      for (size_t j = 0; j < rest.size(); ++j)
      {
        rest[j].fill(0.0);
        rest[j][0] = now.positions[j];
      }
      tr.segments_.push_back(rest);
    }
  }
  tr.knots_.push_back({t, now.positions, now.velocities, now.accelerations});
  std::vector<double> offset(now.positions.size(), 0.0);
  bool first = true;
  for (const TrajectoryPoint& p : points)
  {
    if (p.time <= t)
      continue;
    if (first)
    {
      for (size_t j = 0; j < offset.size() && j < wrap.size(); ++j)
        if (wrap[j])
          offset[j] = 2.0 * M_PI * std::round((now.positions[j] - p.positions[j]) / (2.0 * M_PI));
      first = false;
    }
    Knot k{p.time, p.positions, p.velocities, p.accelerations};
    for (size_t j = 0; j < offset.size(); ++j)
      k.positions[j] += offset[j];
    tr.addKnot(k);
  }
  return tr;
}

void JointTrajectory::forgetBefore(double t)
{
  // The last knot at or before t starts the segment t is in: everything before it goes.
  size_t first = 0;
  while (first + 1 < knots_.size() && knots_[first + 1].time <= t)
    ++first;
  knots_.erase(knots_.begin(), knots_.begin() + static_cast<std::ptrdiff_t>(first));
  segments_.erase(segments_.begin(), segments_.begin() + static_cast<std::ptrdiff_t>(first));
}

JointTrajectory JointTrajectory::stopAt(double t, double duration) const
{
  return stopFrom(t, sample(t), duration);
}

JointTrajectory JointTrajectory::stopFrom(double t, const TrajectorySample& state, double duration)
{
  if (duration <= 0.0)
    return hold(t, state.positions);
  // Velocity falling to 0 over the duration (the quintic from the current acceleration to 0):
  // the joint travels half its speed times the duration further.
  std::vector<double> rest = state.positions, zero(state.positions.size(), 0.0);
  std::vector<double> accelerations = state.accelerations;
  accelerations.resize(rest.size(), 0.0);
  for (size_t j = 0; j < rest.size(); ++j)
    rest[j] += 0.5 * state.velocities[j] * duration;
  JointTrajectory tr;
  tr.addKnot({t, state.positions, state.velocities, accelerations});
  tr.addKnot({t + duration, rest, zero, zero});
  return tr;
}

}  // namespace mybot_ros_control
