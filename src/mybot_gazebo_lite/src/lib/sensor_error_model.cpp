#include "mybot_gazebo_lite/sensor_error_model.h"

#include <algorithm>
#include <cmath>

namespace mybot_gazebo_lite
{

void SensorError::reset(std::mt19937& rng)
{
  drift_ = p_.drift > 0 ? p_.drift * normal_(rng) : 0.0;
}

double SensorError::measure(double truth, double dt, std::mt19937& rng)
{
  if (p_.drift > 0 && dt > 0)
  {
    // Exact for any dt: the variance lost to forgetting, 1 - a^2, is what the new draw adds back.
    const double a = std::exp(-p_.drift_frequency * dt);
    drift_ = a * drift_ + p_.drift * std::sqrt(std::max(0.0, 1.0 - a * a)) * normal_(rng);
  }
  const double white = p_.gaussian_noise > 0 ? p_.gaussian_noise * normal_(rng) : 0.0;
  return p_.scale * truth + bias() + white;
}

}  // namespace mybot_gazebo_lite
