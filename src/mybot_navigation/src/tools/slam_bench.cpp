// SLAM benchmark on synthetic data: a scripted ~200 m drive through the 50 x 50 m factory world
// with a 720-beam, 40 Hz laser and noisy odometry. Prints one Markdown section (medians of runs).
//   slam_bench [--runs N] [--quick]
#include <sys/resource.h>

#include <algorithm>
#include <cstdio>
#include <cstring>
#include <string>
#include <vector>

#include "mybot_navigation/evaluation.h"
#include "mybot_navigation/synthetic_world.h"

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

Row runOnce(const GridMap& world, bool loop_closure, unsigned seed, bool quick)
{
  LaserSpec laser;
  OdometryNoise noise;
  noise.alpha_trans = 0.05;
  noise.alpha_rot = 0.05;
  noise.drift_rot = 0.01;
  std::vector<Point2D> route = kRoute;
  if (quick)
    route.resize(5);
  DriveSimulator drive(world, route, laser, noise, 0.5, 1.0, seed);
  SlamParams p;
  p.linear_update = 0.25;
  p.angular_update = 0.25;
  p.loop_closure = loop_closure;
  Slam slam(p);
  const OfflineRun run = runSlamOnDrive(slam, drive, laser, 30.0);
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
}  // namespace

int main(int argc, char** argv)
{
  int runs = 3;
  bool quick = false;
  for (int i = 1; i < argc; ++i)
  {
    if (!std::strcmp(argv[i], "--runs") && i + 1 < argc)
      runs = std::max(1, std::atoi(argv[++i]));
    else if (!std::strcmp(argv[i], "--quick"))
      quick = true;
  }
  const GridMap world = factoryWorld(0.05);
  std::printf("### SLAM (synthetic factory world)\n\n");
  std::printf("Scripted %s drive through a synthetic 50 x 50 m factory (shelf rows, pillars, partition), laser "
              "720 beams / 40 Hz / 30 m / sd 1 cm, odometry noise 5%% + 0.01 rad/m heading drift, "
              "linearUpdate = angularUpdate = 0.25; medians of %d runs (seeds differ). Real-time factor = simulated "
              "time / SLAM CPU time on one core (ray casting of the synthetic laser excluded). Synthetic data, not the "
              "simulator.\n\n",
              quick ? "short" : "~200 m", runs);
  std::printf("| variant | occ. precision | occ. recall | ATE RMS (m) | RPE 1 m (m / rad) | odometry ATE (m) | "
              "real-time x | keyframes | closures | SLAM data (MB) |\n");
  std::printf("|---|---|---|---|---|---|---|---|---|---|\n");
  for (bool closure : {true, false})
  {
    std::vector<Row> rows;
    for (int i = 0; i < runs; ++i)
      rows.push_back(runOnce(world, closure, 100 + static_cast<unsigned>(i), quick));
    auto med = [&](double Row::*f) {
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
    std::printf("| %s | %.3f | %.3f | %.3f | %.3f / %.4f | %.2f | %.0f | %.0f | %.0f | %.1f |\n",
                closure ? "graph SLAM (loop closure on)" : "scan-to-map only (closure off)", med(&Row::precision),
                med(&Row::recall), med(&Row::ate), med(&Row::rpe_t), med(&Row::rpe_r), med(&Row::odom_ate),
                med(&Row::rtf), median(kf), median(cl), med(&Row::slam_mb));
  }
  rusage ru;
  getrusage(RUSAGE_SELF, &ru);
  std::printf("\nPeak resident memory of the whole benchmark process (truth world + SLAM): %.0f MB (target < 300 MB for "
              "a 50 x 50 m map).\n",
              ru.ru_maxrss / 1024.0);
  return 0;
}
