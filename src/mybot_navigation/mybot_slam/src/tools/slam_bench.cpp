// SLAM benchmark on synthetic sensor data: a scripted drive through a ground-truth map (default: a
// synthetic 50 x 50 m factory; or any map_server map, e.g. the simulator's factory.world rendered
// by world_to_map) with a 720-beam 40 Hz laser and noisy odometry. Prints one Markdown table row;
// bench/bench_slam assembles the section.
#include <sys/resource.h>

#include <algorithm>
#include <cstdio>
#include <cstring>
#include <string>
#include <vector>

#include <sstream>
#include <stdexcept>

#include "mybot_slam/evaluation.h"
#include "mybot_nav_common/map_io.h"
#include "slam_run.h"

using namespace mybot_navigation;

namespace
{
struct Row
{
  double precision, recall, ate, rpe_t, rpe_r, rtf, odom_ate;
  int keyframes, closures;
  double slam_mb;
};

double median(std::vector<double> v)
{
  std::sort(v.begin(), v.end());
  return v.empty() ? 0.0 : (v.size() % 2 ? v[v.size() / 2] : 0.5 * (v[v.size() / 2 - 1] + v[v.size() / 2]));
}

const std::vector<Point2D> kRoute{{2, 3},   {23, 3},  {23, 10}, {2, 10},  {2, 17},  {23, 17}, {23, 24}, {47, 24},
                                  {47, 17}, {27, 17}, {27, 24}, {23, 24}, {23, 31}, {23, 3},  {2, 3}};

struct Setup
{
  bool loop_closure = true;
  double usable_range = 30.0;  // m (the node's maxUrange)
  int local_map_scans = SlamParams().local_map_scans;
  OdometryNoise noise{0.05, 0.05, 0.01};
  double translation_weight = SlamParams().match_translation_weight;
  double rotation_weight = SlamParams().match_rotation_weight;
};

Row runOnce(const GridMap& world, const std::vector<Point2D>& route, const Setup& setup, unsigned seed)
{
  LaserSpec laser;
  DriveSimulator drive(world, route, laser, setup.noise, 0.5, 1.0, seed);
  SlamParams p;
  p.linear_update = 0.25;
  p.angular_update = 0.25;
  p.loop_closure = setup.loop_closure;
  p.local_map_scans = setup.local_map_scans;
  p.match_translation_weight = setup.translation_weight;
  p.match_rotation_weight = setup.rotation_weight;
  Slam slam(p);
  const OfflineRun run = runSlamOnDrive(slam, drive, laser, setup.usable_range);
  const Pose2D align = alignTrajectories(run.estimate, run.truth);
  const MapScore ms = scoreMap(slam.map(), world, align, 1);
  const RelativePoseError rpe = relativePoseError(run.estimate, run.truth, 4);  // ~1 m apart
  Row r;
  r.precision = ms.precision;
  r.recall = ms.recall;
  r.ate = absoluteTrajectoryRmse(run.estimate, run.truth, align);
  r.rpe_t = rpe.translation_rms;
  r.rpe_r = rpe.rotation_rms;
  r.rtf = run.sim_seconds / std::max(run.slam_cpu_seconds, 1e-9);
  r.odom_ate = absoluteTrajectoryRmse(run.odometry, run.truth, alignTrajectories(run.odometry, run.truth));
  r.keyframes = slam.stats().keyframes;
  r.closures = slam.stats().loop_closures;
  r.slam_mb = slam.memoryBytes() / 1e6;
  return r;
}

std::vector<Point2D> parseRoute(const std::string& text)
{
  // "x,y x,y ..." in map coordinates.
  std::vector<Point2D> route;
  std::istringstream ss(text);
  std::string tok;
  while (ss >> tok)
  {
    const auto comma = tok.find(',');
    if (comma == std::string::npos)
      throw std::runtime_error("bad route point '" + tok + "' (expected x,y)");
    route.push_back({std::stod(tok.substr(0, comma)), std::stod(tok.substr(comma + 1))});
  }
  if (route.size() < 2)
    throw std::runtime_error("a route needs at least two points");
  return route;
}
}  // namespace

int main(int argc, char** argv)
{
  int runs = 3;
  bool quick = false;
  Setup setup;
  std::string map_file, route_text, label = "synthetic 50 x 50 m factory";
  for (int i = 1; i < argc; ++i)
  {
    const std::string a = argv[i];
    const bool has_value = i + 1 < argc;
    if (a == "--runs" && has_value)
      runs = std::max(1, std::atoi(argv[++i]));
    else if (a == "--closure" && has_value)
      setup.loop_closure = std::atoi(argv[++i]) != 0;
    else if (a == "--range" && has_value)
      setup.usable_range = std::atof(argv[++i]);
    else if (a == "--local-scans" && has_value)
      setup.local_map_scans = std::max(2, std::atoi(argv[++i]));
    else if (a == "--noise" && has_value)
      setup.noise.alpha_trans = setup.noise.alpha_rot = std::atof(argv[++i]);
    else if (a == "--translation-weight" && has_value)
      setup.translation_weight = std::atof(argv[++i]);
    else if (a == "--rotation-weight" && has_value)
      setup.rotation_weight = std::atof(argv[++i]);
    else if (a == "--drift" && has_value)
      setup.noise.drift_rot = std::atof(argv[++i]);
    else if (a == "--map" && has_value)
      map_file = argv[++i];
    else if (a == "--route" && has_value)
      route_text = argv[++i];
    else if (a == "--label" && has_value)
      label = argv[++i];
    else if (a == "--quick")
      quick = true;
    else
    {
      std::fprintf(stderr,
                   "usage: slam_bench [--map TRUTH.yaml --route \"x,y x,y ...\"] [--label L] [--closure 0|1] "
                   "[--range M] [--local-scans N] [--noise ALPHA] [--drift RAD_PER_M] "
                   "[--translation-weight W] [--rotation-weight W] [--runs N] [--quick]\nprints one Markdown table row "
                   "(medians over runs)\n");
      return 2;
    }
  }
  GridMap world;
  std::vector<Point2D> route = kRoute;
  try
  {
    world = map_file.empty() ? factoryWorld(0.05) : loadMap(map_file);
    if (!route_text.empty())
      route = parseRoute(route_text);
  }
  catch (const std::exception& e)
  {
    std::fprintf(stderr, "slam_bench: %s\n", e.what());
    return 1;
  }
  if (quick)
    route.resize(std::min<size_t>(route.size(), 3));
  std::vector<Row> rows;
  double length = 0.0;
  for (size_t i = 1; i < route.size(); ++i)
    length += std::hypot(route[i].x - route[i - 1].x, route[i].y - route[i - 1].y);
  for (int i = 0; i < runs; ++i)
    rows.push_back(runOnce(world, route, setup, 100 + static_cast<unsigned>(i)));
  auto med = [&](double Row::*f)
  {
    std::vector<double> v;
    for (const Row& r : rows)
      v.push_back(r.*f);
    return median(v);
  };
  std::vector<double> kf, cl;
  for (const Row& r : rows)
  {
    kf.push_back(r.keyframes);
    cl.push_back(r.closures);
  }
  rusage ru;
  getrusage(RUSAGE_SELF, &ru);
  std::printf("| %s, %.0f m | %s | %.3f | %.3f | %.3f | %.3f / %.4f | %.2f | %.0f | %.0f | %.0f | %.0f |\n",
              label.c_str(), length, setup.loop_closure ? "on" : "off", med(&Row::precision), med(&Row::recall),
              med(&Row::ate), med(&Row::rpe_t), med(&Row::rpe_r), med(&Row::odom_ate), med(&Row::rtf), median(kf),
              median(cl), ru.ru_maxrss / 1024.0);
  return 0;
}
