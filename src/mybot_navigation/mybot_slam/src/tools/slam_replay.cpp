// slam_replay: offline mapping from a bag, as slam_toolbox's offline mode or gmapping's
// slam_gmapping_replay: the same Slam as slam_node over every scan, at full speed, no roscore.
//
//   rosrun mybot_slam slam_replay --bag FILE --out DIR [--params FILE]
//        [--scan-topic /scan] [--odom-topic /odom] [--odom last|interpolate]
//        [--odom-frame odom [--base-frame base_link]] [--laser-pose X,Y,YAW] [--carmen-angles]
//        [--no-final-optimization] [--quiet]
//
// Parameters: --params FILE (slam_node's parameter names, gmapping's where gmapping has one), by
// default the package's config/slam.yaml, what slam_node's launch files load and every figure in
// BENCHMARKS.md was measured with: without it, the library's defaults are gmapping's (keyframes every
// metre) with this package's later remedies off, and a bare replay would not be the mapper the
// README describes. The file used is named on stderr.
// Odometry at a scan: `last` (default) takes the pose of the last odometry message before the
// scan in bag order, which is what CARMEN logs embed in each FLASER (ACES, Intel); `interpolate`
// interpolates between the odometry messages around the scan's stamp (FR079, whose CARMEN
// odometry was interpolated). The laser's mounting comes from /tf_static (base -> the scan's frame),
// or from --laser-pose (m, m, rad in the base frame) where the log's is known to be wrong.
// --carmen-angles: for bags converted from CARMEN FLASER records with derived angles (-90 deg,
// 180/(n-1) deg steps, as ../shared's Intel, ACES and FR079), each beam at CARMEN's -90 + i*180/n
// deg instead (carmenFlaserStep); an error if the first scan does not have the derived angles.
// --odom-frame takes the odometry from the bag's tf instead, as slam_node does: odom -> base frame
// at each scan's stamp (a robot's bag often has /tf and no odometry topic), and the mounting from tf.
// --no-final-optimization leaves out the last step (slam_node's finish_trajectory): the result is
// then what the online node has while it still maps.
//
// Writes, each file replaced atomically: DIR/map.pgm + map.yaml (map_server), DIR/map.png,
// DIR/trajectory.tum (every scan's pose, after the last optimisation, in the map frame: "stamp x y
// z qx qy qz qw" with the scan's own stamp; a scan between keyframes is matched against the
// keyframes around it, Slam::placeScans, else kept where it was tracked), DIR/odometry.tum (the raw
// odometry at each scan, the same way: what the mapper is measured against), DIR/timing.json (scans, keyframes, loop
// closures, log span, CPU and wall time, peak memory), DIR/loop_closures.tsv (every loop closure
// matched, and whether it was accepted, held, rejected or dropped, as slam_node logs them).
#include <sys/resource.h>

#include <chrono>
#include <filesystem>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <sstream>
#include <string>
#include <vector>

#include <opencv2/imgcodecs.hpp>

#include <ros/package.h>

#include "mybot_common/atomic_file.h"
#include "mybot_nav_common/map_io.h"
#include "mybot_slam/ros/bag_replay.h"

using namespace mybot_navigation;

namespace
{
struct Options
{
  std::string bag, out, params, scan_topic = "/scan", odom_topic = "/odom", odom = "last";
  std::string odom_frame, base_frame = "base_link";
  bool odom_given = false;
  bool quiet = false;
  bool final_optimization = true;
  bool override_mount = false;
  mybot_navigation::Pose2D mount;
  bool carmen_angles = false;
};

const char* const kUsage =
    "usage: slam_replay --bag FILE --out DIR [--params FILE (default: mybot_slam's config/slam.yaml)] "
    "[--scan-topic /scan] [--odom-topic /odom] [--odom last|interpolate] [--odom-frame odom [--base-frame "
    "base_link]] [--laser-pose X,Y,YAW] [--carmen-angles] [--no-final-optimization] [--quiet]\n";

// `text` as a JSON string literal: quoted, with quotes, backslashes and control characters escaped.
std::string jsonString(const std::string& text)
{
  std::string out = "\"";
  for (const unsigned char c : text)
  {
    if (c == '"' || c == '\\')
      out += std::string("\\") + static_cast<char>(c);
    else if (c < 0x20)
    {
      char code[8];
      std::snprintf(code, sizeof code, "\\u%04x", c);
      out += code;
    }
    else
      out += static_cast<char>(c);
  }
  return out + "\"";
}

// A usage error: what is wrong, then the usage, on stderr, and exit status 2.
[[noreturn]] void usage(const std::string& error)
{
  std::fprintf(stderr, "slam_replay: %s\n%s", error.c_str(), kUsage);
  std::exit(2);
}

Options parseArgs(int argc, char** argv)
{
  Options o;
  for (int i = 1; i < argc; ++i)
  {
    const std::string a = argv[i];
    auto value = [&]() -> std::string
    {
      if (i + 1 >= argc)
        usage(a + " needs a value");
      return argv[++i];
    };
    if (a == "--help" || a == "-h")
    {
      std::fputs(kUsage, stdout);
      std::exit(0);
    }
    else if (a == "--bag")
      o.bag = value();
    else if (a == "--out")
      o.out = value();
    else if (a == "--params")
      o.params = value();
    else if (a == "--scan-topic")
      o.scan_topic = value();
    else if (a == "--odom-topic")
    {
      o.odom_topic = value();
      o.odom_given = true;
    }
    else if (a == "--odom")
    {
      o.odom = value();
      o.odom_given = true;
    }
    else if (a == "--odom-frame")
      o.odom_frame = value();
    else if (a == "--base-frame")
      o.base_frame = value();
    else if (a == "--laser-pose")
    {
      const std::string v = value();
      char rest = 0;
      if (std::sscanf(v.c_str(), "%lf,%lf,%lf%c", &o.mount.x, &o.mount.y, &o.mount.theta, &rest) != 3 ||
          !std::isfinite(o.mount.x) || !std::isfinite(o.mount.y) || !std::isfinite(o.mount.theta))
        usage("--laser-pose must be X,Y,YAW (m, m, rad), got " + v);
      o.override_mount = true;
    }
    else if (a == "--carmen-angles")
      o.carmen_angles = true;
    else if (a == "--quiet")
      o.quiet = true;
    else if (a == "--no-final-optimization")
      o.final_optimization = false;
    else
      usage("unknown argument " + a);
  }
  if (o.bag.empty() || o.out.empty())
    usage("--bag and --out are required");
  if (o.odom != "last" && o.odom != "interpolate")
    usage("--odom must be last or interpolate, got " + o.odom);
  if (!o.odom_frame.empty() && o.odom_given)
    usage("--odom-frame takes the odometry from tf at each scan's stamp: --odom-topic and --odom do not apply");
  if (o.odom_frame.empty() && o.base_frame != "base_link")
    usage("--base-frame goes with --odom-frame");
  return o;
}

double cpuSeconds()
{
  rusage u;
  getrusage(RUSAGE_SELF, &u);
  return u.ru_utime.tv_sec + u.ru_stime.tv_sec + 1e-6 * (u.ru_utime.tv_usec + u.ru_stime.tv_usec);
}

}  // namespace

int main(int argc, char** argv)
{
  const Options opt = parseArgs(argc, argv);
  std::string params = opt.params;
  if (params.empty())
  {
    // Without ROS_PACKAGE_PATH rospack would only add its own error lines to ours.
    const char* path = std::getenv("ROS_PACKAGE_PATH");
    const std::string package = path && *path ? ros::package::getPath("mybot_slam") : std::string();
    if (package.empty())
    {
      std::fprintf(stderr,
                   "slam_replay: no --params given and the package mybot_slam is not on ROS_PACKAGE_PATH "
                   "to take its config/slam.yaml from: source the workspace's setup.bash or pass --params FILE\n");
      return 2;
    }
    params = package + "/config/slam.yaml";
  }
  std::fprintf(stderr, "slam_replay: parameters from %s\n", params.c_str());
  SlamRunParams run;
  try
  {
    run = loadSlamParams(params);
  }
  catch (const std::exception& e)
  {
    std::fprintf(stderr, "slam_replay: %s\n", e.what());
    return 2;
  }
  // Before the run, not after it: a long replay must not end on an output folder it cannot write.
  // Made one folder at a time along --out as given (through any "..", as the system resolves
  // it), each one that did not exist remembered.
  std::error_code ec;
  std::vector<std::filesystem::path> created;
  std::filesystem::path walked;
  for (const std::filesystem::path& part : std::filesystem::absolute(opt.out, ec))
  {
    walked /= part;
    if (part.empty() || ec || std::filesystem::exists(walked, ec))
      continue;
    if (!std::filesystem::create_directory(walked, ec))
      break;
    created.push_back(walked);
  }
  // A run that fails (an unreadable bag, no scans) leaves none of the folders it created behind,
  // last made first (only while empty); a folder it was given stays, with whatever it held.
  auto remove_created = [created]
  {
    std::error_code ignored;
    for (auto it = created.rbegin(); it != created.rend(); ++it)
      std::filesystem::remove(*it, ignored);
  };
  if (ec || !std::filesystem::is_directory(opt.out))
  {
    std::fprintf(stderr, "slam_replay: --out %s: cannot create the folder (%s)\n", opt.out.c_str(),
                 ec ? ec.message().c_str() : "a file of that name exists");
    remove_created();
    return 2;
  }
  auto failed = [&remove_created]
  {
    remove_created();
    return 1;
  };
  const auto wall0 = std::chrono::steady_clock::now();
  const double cpu0 = cpuSeconds();
  Slam slam(run.slam);
  BagReplayOptions ro;
  ro.bag = opt.bag;
  ro.scan_topic = opt.scan_topic;
  ro.odom_topic = opt.odom_topic;
  ro.odom = opt.odom;
  ro.odom_frame = opt.odom_frame;
  ro.base_frame = opt.base_frame;
  ro.override_mount = opt.override_mount;
  ro.mount = opt.mount;
  ro.carmen_angles = opt.carmen_angles;
  ro.final_optimization = opt.final_optimization;
  int percent = -1;
  BagReplayResult r;
  try
  {
    r = replayBag(ro, slam, run,
                  [&](std::size_t done, std::size_t total)
                  {
                    const int p = static_cast<int>(100 * done / std::max<std::size_t>(total, 1));
                    if (opt.quiet || p == percent)
                      return;
                    percent = p;
                    std::fprintf(stderr, "\rslam_replay: [%-50s] %3d %% %zu keyframes", std::string(p / 2, '#').c_str(),
                                 p, slam.keyframes().size());
                  });
  }
  catch (const std::exception& e)
  {
    std::fprintf(stderr, "\nslam_replay: %s\n", e.what());
    return failed();
  }
  if (!opt.quiet)
    std::fprintf(stderr, "\n");
  if (slam.keyframes().empty())
  {
    if (r.scans_refused > 0 && r.scans == 0)
      std::fprintf(stderr, "slam_replay: %s: all %zu scans on %s contradict themselves: %s\n", opt.bag.c_str(),
                   r.scans_refused, opt.scan_topic.c_str(), r.first_refusal.c_str());
    else if (opt.odom_frame.empty())
      std::fprintf(stderr, "slam_replay: %s: no scans on %s with odometry on %s before them\n", opt.bag.c_str(),
                   opt.scan_topic.c_str(), opt.odom_topic.c_str());
    else
      std::fprintf(stderr, "slam_replay: %s: no scans on %s with tf %s -> %s at their stamps\n", opt.bag.c_str(),
                   opt.scan_topic.c_str(), opt.odom_frame.c_str(), opt.base_frame.c_str());
    return failed();
  }
  if (r.scans_without_odometry > 0)
    std::fprintf(stderr,
                 "slam_replay: %zu scans on %s had no tf %s -> %s at their stamp (or no laser mounting): skipped\n",
                 r.scans_without_odometry, opt.scan_topic.c_str(), opt.odom_frame.c_str(), opt.base_frame.c_str());
  if (r.scans_refused > 0)
    std::fprintf(stderr, "slam_replay: %zu scans on %s were skipped, as slam_node drops them: %s\n", r.scans_refused,
                 opt.scan_topic.c_str(), r.first_refusal.c_str());
  // Not acted on, only said: a bag may declare such angles and mean them.
  if (r.scans_converter_angles > 0)
    std::fprintf(stderr,
                 "slam_replay: %zu of %zu scans on %s declare -90 deg and 180/(n-1) deg steps, the angles a CARMEN "
                 "FLASER converter derives; if this bag came from a CARMEN log, --carmen-angles reads them as CARMEN "
                 "does (-90 + i*180/n deg)\n",
                 r.scans_converter_angles, r.scans, opt.scan_topic.c_str());
  auto toTum = [](const std::vector<StampedPose>& poses)
  {
    std::ostringstream tum;
    tum.precision(9);
    for (const StampedPose& s : poses)
      tum << std::fixed << s.stamp << " " << s.pose.x << " " << s.pose.y << " 0 0 0 " << std::sin(s.pose.theta / 2)
          << " " << std::cos(s.pose.theta / 2) << "\n";
    return tum.str();
  };
  const double cpu = cpuSeconds() - cpu0;
  const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - wall0).count();
  const double span = r.last_stamp - r.first_stamp;
  // slam_node logs the same events: keyframe stamps, so they line up with trajectory.tum.
  std::ostringstream closures;
  closures << "# stamp\tkeyframe\tcandidate\toutcome\tscore\tscore_at_estimate\tconstraint_ratio\t"
              "correction_x\tcorrection_y\tcorrection_theta\n";
  for (const LoopClosureRecord& c : r.closures)
  {
    char line[512];
    std::snprintf(line, sizeof line, "%.6f\t%d\t%d\t%s\t%.3f\t%.3f\t%.3f\t%.4f\t%.4f\t%.4f\n",
                  slam.keyframes()[static_cast<size_t>(c.to)].stamp, c.to, c.from, c.reason, c.score,
                  c.score_at_estimate, c.ratio, c.correction.x, c.correction.y, c.correction.theta);
    closures << line;
  }
  rusage u;
  getrusage(RUSAGE_SELF, &u);
  // The bag's path as a JSON string (any path a user gives), then the figures, which fit the buffer.
  char figures[1024];
  std::snprintf(figures, sizeof figures,
                "  \"scans\": %zu,\n  \"keyframes\": %zu,\n  \"loop_closures\": %d,\n"
                "  \"global_searches\": %d,\n  \"global_matches\": %d,\n  \"global_closures\": %d,\n"
                "  \"weak_matches\": %d,\n  \"motion_fallbacks\": %d,\n  \"corrections_undone\": %d,\n"
                "  \"turn_fallbacks\": %d,\n  \"stall_searches\": %d,\n  \"stall_matches\": %d,\n"
                "  \"retry_searches\": %d,\n  \"retry_matches\": %d,\n"
                "  \"scans_reangled\": %zu,\n"
                "  \"log_span_s\": %.3f,\n  \"cpu_s\": %.3f,\n  \"wall_s\": %.3f,\n  \"realtime_factor\": %.2f,\n"
                "  \"peak_rss_mb\": %.1f\n}\n",
                r.scans, slam.keyframes().size(), slam.stats().loop_closures, slam.stats().loop_global_attempts,
                slam.stats().loop_global_matches, slam.stats().loop_global_closures, slam.stats().weak_matches,
                slam.stats().motion_fallbacks, slam.stats().corrections_undone, slam.stats().turn_fallbacks,
                slam.stats().stall_searches, slam.stats().stall_matches, slam.stats().retry_searches,
                slam.stats().retry_matches, r.scans_reangled, span, cpu, wall, cpu > 0 ? span / cpu : 0.0,
                u.ru_maxrss / 1024.0);
  const std::string timing = "{\n  \"bag\": " + jsonString(opt.bag) + ",\n" + figures;
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
                                        {opt.out + "/trajectory.tum", toTum(r.trajectory)},
                                        {opt.out + "/odometry.tum", toTum(r.odometry)},
                                        {opt.out + "/loop_closures.tsv", closures.str()},
                                        {opt.out + "/timing.json", timing}});
  }
  catch (const std::exception& e)
  {
    std::fprintf(stderr, "slam_replay: %s\n", e.what());
    return failed();
  }
  if (!opt.quiet)
    std::fprintf(stderr,
                 "slam_replay: %zu scans, %zu keyframes, %d loop closures (%d of them found by %d global searches), "
                 "%d revisit edges in the final "
                 "optimisation (%d dropped; map consistency %.3f -> %.3f); %.1f s of log in %.1f s of CPU "
                 "(%.0fx)\n",
                 r.scans, slam.keyframes().size(), slam.stats().loop_closures, slam.stats().loop_global_closures,
                 slam.stats().loop_global_attempts, slam.stats().final_edges, slam.stats().final_edges_dropped,
                 slam.stats().final_consistency_before, slam.stats().final_consistency_after, span, cpu,
                 cpu > 0 ? span / cpu : 0.0);
  return 0;
}
