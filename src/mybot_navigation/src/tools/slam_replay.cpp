// slam_replay: offline mapping from a bag, as slam_toolbox's offline mode or gmapping's
// slam_gmapping_replay: the same Slam as slam_node over every scan, at full speed, no roscore.
//
//   rosrun mybot_navigation slam_replay --bag FILE --out DIR [--params slam.yaml]
//        [--scan-topic /scan] [--odom-topic /odom] [--odom last|interpolate] [--quiet]
//
// Odometry at a scan: `last` (default) takes the pose of the last odometry message before the
// scan in bag order, which is what CARMEN logs embed in each FLASER (ACES, Intel); `interpolate`
// interpolates between the odometry messages around the scan's stamp (FR079, whose CARMEN
// odometry was interpolated). The laser's mounting comes from /tf_static (base -> the scan's frame).
//
// Writes, each file replaced atomically: DIR/map.pgm + map.yaml (map_server), DIR/map.png,
// DIR/trajectory.tum (every scan's pose, after the last optimisation, in the map frame: "stamp x y
// z qx qy qz qw" with the scan's own stamp; a scan between keyframes is placed by odometry from
// its keyframe), DIR/timing.json (scans, keyframes, loop closures, log span, CPU and wall time,
// peak memory).
#include <sys/resource.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <ctime>
#include <map>
#include <sstream>
#include <string>
#include <vector>

#include <nav_msgs/Odometry.h>
#include <opencv2/imgcodecs.hpp>
#include <rosbag/bag.h>
#include <rosbag/view.h>
#include <sensor_msgs/LaserScan.h>
#include <tf2_msgs/TFMessage.h>
#include <yaml-cpp/yaml.h>

#include "mybot_common/atomic_file.h"
#include "mybot_navigation/map_io.h"
#include "mybot_navigation/range_scan.h"
#include "mybot_navigation/ros/conversions.h"
#include "mybot_navigation/slam.h"
#include "mybot_navigation/slam_params.h"

using namespace mybot_navigation;

namespace
{
struct Options
{
  std::string bag, out, params, scan_topic = "/scan", odom_topic = "/odom", odom = "last";
  bool quiet = false;
};

[[noreturn]] void usage(const std::string& error)
{
  std::fprintf(stderr,
               "slam_replay: %s\nusage: slam_replay --bag FILE --out DIR [--params slam.yaml] [--scan-topic /scan] "
               "[--odom-topic /odom] [--odom last|interpolate] [--quiet]\n",
               error.c_str());
  std::exit(2);
}

Options parseArgs(int argc, char** argv)
{
  Options o;
  for (int i = 1; i < argc; ++i)
  {
    const std::string a = argv[i];
    auto value = [&]() -> std::string {
      if (i + 1 >= argc)
        usage(a + " needs a value");
      return argv[++i];
    };
    if (a == "--bag")
      o.bag = value();
    else if (a == "--out")
      o.out = value();
    else if (a == "--params")
      o.params = value();
    else if (a == "--scan-topic")
      o.scan_topic = value();
    else if (a == "--odom-topic")
      o.odom_topic = value();
    else if (a == "--odom")
      o.odom = value();
    else if (a == "--quiet")
      o.quiet = true;
    else
      usage("unknown argument " + a);
  }
  if (o.bag.empty() || o.out.empty())
    usage("--bag and --out are required");
  if (o.odom != "last" && o.odom != "interpolate")
    usage("--odom must be last or interpolate, got " + o.odom);
  return o;
}

// slam_node's parameters from a YAML file (the same names as its ROS parameters, e.g.
// config/slam.yaml); node-only settings (frames, rates) are skipped, anything else is an error.
SlamRunParams loadParams(const std::string& path)
{
  SlamRunParams run;
  if (path.empty())
    return run;
  YAML::Node doc;
  try
  {
    doc = YAML::LoadFile(path);
  }
  catch (const YAML::Exception& e)
  {
    throw std::runtime_error(path + ": " + e.what());
  }
  if (!doc.IsMap())
    throw std::runtime_error(path + ": expected a mapping of slam_node parameters");
  std::map<std::string, const SlamParamSpec*> by_name;
  for (const SlamParamSpec& s : slamParamSpecs())
    by_name[s.name] = &s;
  static const char* node_only[] = {"base_frame", "odom_frame", "map_frame", "map_update_interval",
                                    "transform_publish_period", "throttle_scans"};
  for (const auto& kv : doc)
  {
    const std::string name = kv.first.as<std::string>();
    auto it = by_name.find(name);
    if (it == by_name.end())
    {
      if (std::find(std::begin(node_only), std::end(node_only), name) != std::end(node_only))
        continue;
      throw std::runtime_error(path + ": unknown parameter '" + name + "'");
    }
    const SlamParamSpec& s = *it->second;
    try
    {
      if (s.type == SlamParamSpec::Type::Boolean)
        s.field_bool(run) = kv.second.as<bool>();
      else
      {
        const double v = kv.second.as<double>();
        if (!s.ok(v) || (s.type == SlamParamSpec::Type::Integer && v != std::floor(v)))
          throw std::runtime_error("");
        if (s.type == SlamParamSpec::Type::Integer)
          s.field_int(run) = static_cast<int>(v);
        else
          s.field_double(run) = v;
      }
    }
    catch (const std::exception&)
    {
      throw std::runtime_error(path + ": parameter '" + name + "' must be " + s.requirement);
    }
  }
  const std::string inconsistent = checkSlamRunParams(run);
  if (!inconsistent.empty())
    throw std::runtime_error(path + ": " + inconsistent);
  return run;
}

struct ScanRecord
{
  double stamp;
  Pose2D odom;
  int keyframe;  // the keyframe current after this scan (-1 before the first)
};

double cpuSeconds()
{
  rusage u;
  getrusage(RUSAGE_SELF, &u);
  return u.ru_utime.tv_sec + u.ru_stime.tv_sec + 1e-6 * (u.ru_utime.tv_usec + u.ru_stime.tv_usec);
}

Pose2D interpolate(const std::vector<std::pair<double, Pose2D>>& odom, double t)
{
  auto it = std::lower_bound(odom.begin(), odom.end(), t,
                             [](const std::pair<double, Pose2D>& a, double v) { return a.first < v; });
  if (it == odom.begin())
    return it->second;
  if (it == odom.end())
    return odom.back().second;
  const auto& [t1, b] = *it;
  const auto& [t0, a] = *(it - 1);
  const double f = t1 > t0 ? (t - t0) / (t1 - t0) : 0.0;
  const Pose2D d = between(a, b);
  return compose(a, {d.x * f, d.y * f, d.theta * f});
}
}  // namespace

int main(int argc, char** argv)
{
  const Options opt = parseArgs(argc, argv);
  SlamRunParams run;
  try
  {
    run = loadParams(opt.params);
  }
  catch (const std::exception& e)
  {
    std::fprintf(stderr, "slam_replay: %s\n", e.what());
    return 2;
  }
  const auto wall0 = std::chrono::steady_clock::now();
  const double cpu0 = cpuSeconds();
  rosbag::Bag bag;
  try
  {
    bag.open(opt.bag, rosbag::bagmode::Read);
  }
  catch (const rosbag::BagException& e)
  {
    std::fprintf(stderr, "slam_replay: %s: %s\n", opt.bag.c_str(), e.what());
    return 1;
  }

  // The laser's mounting, and (for --odom interpolate) every odometry pose by stamp.
  std::map<std::string, Pose2D> mount;  // child frame -> pose in its parent (the base)
  std::vector<std::pair<double, Pose2D>> odom_by_stamp;
  for (const rosbag::MessageInstance& m : rosbag::View(bag, rosbag::TopicQuery({"/tf_static", opt.odom_topic})))
  {
    if (auto tf = m.instantiate<tf2_msgs::TFMessage>())
      for (const auto& t : tf->transforms)
        mount[t.child_frame_id] = toPose2D(t.transform);
    else if (auto o = m.instantiate<nav_msgs::Odometry>())
      odom_by_stamp.push_back({o->header.stamp.toSec(), toPose2D(o->pose.pose)});
  }
  std::stable_sort(odom_by_stamp.begin(), odom_by_stamp.end(),
                   [](const auto& a, const auto& b) { return a.first < b.first; });

  rosbag::View view(bag, rosbag::TopicQuery({opt.scan_topic, opt.odom_topic}));
  const std::size_t total = view.size();
  Slam slam(run.slam);
  std::vector<ScanRecord> scans;
  bool have_odom = false;
  Pose2D last_odom;
  double first_stamp = NAN, last_stamp = NAN;
  std::size_t done = 0;
  int percent = -1;
  ScanConversionStats conversion;
  for (const rosbag::MessageInstance& m : view)
  {
    ++done;
    if (!opt.quiet && static_cast<int>(100 * done / total) != percent)
    {
      percent = static_cast<int>(100 * done / total);
      std::fprintf(stderr, "\rslam_replay: [%-50s] %3d %% %zu scans, %zu keyframes", std::string(percent / 2, '#').c_str(),
                   percent, scans.size(), slam.keyframes().size());
    }
    if (auto o = m.instantiate<nav_msgs::Odometry>())
    {
      last_odom = toPose2D(o->pose.pose);
      have_odom = true;
      continue;
    }
    auto scan = m.instantiate<sensor_msgs::LaserScan>();
    if (!scan || scan->ranges.empty() || !have_odom)
      continue;
    const double stamp = scan->header.stamp.toSec();
    first_stamp = std::isnan(first_stamp) ? stamp : std::min(first_stamp, stamp);
    last_stamp = std::isnan(last_stamp) ? stamp : std::max(last_stamp, stamp);
    const Pose2D odom = opt.odom == "last" ? last_odom : interpolate(odom_by_stamp, stamp);
    ScanGeometry g;
    auto mt = mount.find(scan->header.frame_id);
    if (mt != mount.end())
      g.sensor_in_base = mt->second;
    if (slam.wantsScan(stamp, odom))
    {
      const double range_max = run.max_range > 0.0 ? std::min<double>(run.max_range, scan->range_max) : scan->range_max;
      const RangeScan rs = convertRanges(scan->ranges, scan->angle_min, scan->angle_increment, scan->range_min,
                                         range_max, run.max_urange, g, &conversion);
      slam.addScan(stamp, odom, rs);
    }
    else
    {
      slam.updateOdometry(odom);
    }
    scans.push_back({stamp, odom, static_cast<int>(slam.keyframes().size()) - 1});
  }
  if (!opt.quiet)
    std::fprintf(stderr, "\n");
  bag.close();
  if (slam.keyframes().empty())
  {
    std::fprintf(stderr, "slam_replay: %s: no scans on %s with odometry on %s before them\n", opt.bag.c_str(),
                 opt.scan_topic.c_str(), opt.odom_topic.c_str());
    return 1;
  }

  // Every scan's pose after the last optimisation: its keyframe's, moved by the odometry since.
  std::ostringstream tum;
  tum.precision(9);
  const auto& kfs = slam.keyframes();
  for (const ScanRecord& s : scans)
  {
    if (s.keyframe < 0)
      continue;
    const Keyframe& k = kfs[static_cast<std::size_t>(s.keyframe)];
    const Pose2D p = compose(k.pose, between(k.odom, s.odom));
    tum << std::fixed << s.stamp << " " << p.x << " " << p.y << " 0 0 0 " << std::sin(p.theta / 2) << " "
        << std::cos(p.theta / 2) << "\n";
  }
  const double cpu = cpuSeconds() - cpu0;
  const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - wall0).count();
  rusage u;
  getrusage(RUSAGE_SELF, &u);
  char timing[1024];
  std::snprintf(timing, sizeof timing,
                "{\n  \"bag\": \"%s\",\n  \"scans\": %zu,\n  \"keyframes\": %zu,\n  \"loop_closures\": %d,\n"
                "  \"log_span_s\": %.3f,\n  \"cpu_s\": %.3f,\n  \"wall_s\": %.3f,\n  \"realtime_factor\": %.2f,\n"
                "  \"peak_rss_mb\": %.1f\n}\n",
                opt.bag.c_str(), scans.size(), kfs.size(), slam.stats().loop_closures, last_stamp - first_stamp, cpu,
                wall, cpu > 0 ? (last_stamp - first_stamp) / cpu : 0.0, u.ru_maxrss / 1024.0);
  try
  {
    const GridMap map = slam.map();
    saveMap(map, opt.out + "/map");
    cv::Mat img(map.info.height, map.info.width, CV_8UC1);
    for (int y = 0; y < map.info.height; ++y)
      for (int x = 0; x < map.info.width; ++x)
      {
        const int v = map.at(x, map.info.height - 1 - y);
        img.at<uint8_t>(y, x) = v < 0 ? 205 : (v >= 65 ? 0 : 254);
      }
    std::vector<uchar> png;
    cv::imencode(".png", img, png);
    mybot_common::writeFilesAtomically({{opt.out + "/map.png", std::string(png.begin(), png.end())},
                                        {opt.out + "/trajectory.tum", tum.str()},
                                        {opt.out + "/timing.json", timing}});
  }
  catch (const std::exception& e)
  {
    std::fprintf(stderr, "slam_replay: %s\n", e.what());
    return 1;
  }
  if (!opt.quiet)
    std::fprintf(stderr, "slam_replay: %zu scans, %zu keyframes, %d loop closures; %.1f s of log in %.1f s of CPU (%.0fx)\n",
                 scans.size(), kfs.size(), slam.stats().loop_closures, last_stamp - first_stamp, cpu,
                 cpu > 0 ? (last_stamp - first_stamp) / cpu : 0.0);
  return 0;
}
