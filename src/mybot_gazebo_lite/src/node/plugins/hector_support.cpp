// What hector_gazebo_plugins' GNSS, IMU, magnetometer and sonar read alike: the sensor error model,
// the update timer, the link and the frame.
#include "builtin.h"

#include "mybot_gazebo_lite/parsing.h"

#include <cctype>

namespace mybot_gazebo_lite
{

namespace
{
// hector's names: <offset>, <drift>, ... without a prefix; <accelOffset>, <accelDrift>, ... with one.
std::string errorTag(const std::string& prefix, const std::string& name)
{
  if (prefix.empty())
    return name;
  return prefix + static_cast<char>(std::toupper(name[0])) + name.substr(1);
}

const char* const kErrorNames[] = {"offset", "drift", "driftFrequency", "gaussianNoise", "scaleError"};

// A spread or a frequency below zero is refused, naming its tag.
void checkError(const PluginParams& p, const std::string& prefix, const SensorErrorParams& e)
{
  if (e.drift < 0)
    p.fail(errorTag(prefix, "drift"), "must be >= 0 (a standard deviation)");
  if (e.drift_frequency < 0)
    p.fail(errorTag(prefix, "driftFrequency"), "must be >= 0 (Hz)");
  if (e.gaussian_noise < 0)
    p.fail(errorTag(prefix, "gaussianNoise"), "must be >= 0 (a standard deviation)");
}
}  // namespace

std::set<std::string> hectorErrorTags(const std::string& prefix)
{
  std::set<std::string> tags;
  for (const char* n : kErrorNames)
    tags.insert(errorTag(prefix, n));
  return tags;
}

SensorErrorParams hectorError(const PluginParams& p, const std::string& prefix)
{
  SensorErrorParams e;
  double* fields[] = {&e.offset, &e.drift, &e.drift_frequency, &e.gaussian_noise, &e.scale};
  for (int i = 0; i < 5; ++i)
    *fields[i] = p.num(errorTag(prefix, kErrorNames[i]), *fields[i]);
  checkError(p, prefix, e);
  return e;
}

std::array<SensorErrorParams, 3> hectorError3(const PluginParams& p, const std::string& prefix)
{
  std::array<SensorErrorParams, 3> axes;
  for (int i = 0; i < 5; ++i)
  {
    const std::string tag = errorTag(prefix, kErrorNames[i]);
    if (!p.has(tag))
      continue;
    btVector3 v;
    try
    {
      v = parseVec3(p.str(tag, ""), "");
    }
    catch (const LoadError&)
    {
      p.fail(tag, "expected 3 numbers (x y z), got '" + p.str(tag, "") + "'");
    }
    for (int a = 0; a < 3; ++a)
    {
      double* fields[] = {&axes[a].offset, &axes[a].drift, &axes[a].drift_frequency, &axes[a].gaussian_noise,
                          &axes[a].scale};
      *fields[i] = v[a];
    }
  }
  for (const SensorErrorParams& e : axes)
    checkError(p, prefix, e);
  return axes;
}

Rate hectorUpdateRate(const PluginParams& p, double default_hz)
{
  double period = default_hz > 0 ? 1.0 / default_hz : 0.0;
  if (p.has("updateRate"))
  {
    const double hz = p.num("updateRate", 0.0);
    if (hz < 0)
      p.fail("updateRate", "must be >= 0 (Hz; 0 = every step)");
    period = hz > 0 ? 1.0 / hz : 0.0;
  }
  if (p.has("updatePeriod"))
  {
    period = p.num("updatePeriod", 0.0);
    if (period < 0)
      p.fail("updatePeriod", "must be >= 0 (s; 0 = every step)");
  }
  return Rate(period > 0 ? 1.0 / period : 0.0);
}

std::string hectorBody(const PluginContext& c, const PluginParams& p)
{
  // Without <bodyName>: the model's first link, as Model::GetLink() gives it.
  return p.link("bodyName", c.robot->spec().root);
}

std::string hectorFrame(const PluginParams& p, const std::string& def)
{
  // As written (hector applies no tf_prefix), without the leading '/' tf2 refuses.
  std::string f = p.str("frameId", def);
  while (!f.empty() && f[0] == '/')
    f.erase(0, 1);
  return f;
}

bool HectorTimer::due(double t, double& dt)
{
  if (!rate_.due(t))
    return false;
  dt = last_ >= 0 && t >= last_ ? t - last_ : 0.0;
  last_ = t;
  return true;
}

}  // namespace mybot_gazebo_lite
