// bench_nav: global planning time (A* and Dijkstra) on a 20 x 15 m map at 5 cm, costmap update,
// DWA control step, AMCL update and global localization cost, on the ROS-free libraries. Prints one
// Markdown section.
#include <algorithm>
#include <ctime>
#include <cmath>
#include <cstdio>
#include <random>
#include <vector>

#include "mybot_amcl/amcl.h"
#include "mybot_move_base/costmap.h"
#include "mybot_move_base/local_planner.h"
#include "mybot_move_base/planner.h"
#include "mybot_nav_common/ray_cast.h"
#include "synthetic_world.h"

using namespace mybot_navigation;

namespace
{

double median(std::vector<double> v)
{
  std::sort(v.begin(), v.end());
  return v.empty() ? 0.0 : v[v.size() / 2];
}

double cpuMs()
{
  timespec ts;
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
  return ts.tv_sec * 1e3 + ts.tv_nsec * 1e-6;
}

// CPU time of the calling thread: a loaded (shared) machine does not inflate it.
template <typename F>
double timeMs(F&& f)
{
  const double t0 = cpuMs();
  f();
  return cpuMs() - t0;
}

// 20 x 15 m warehouse: shelf rows with gaps and pillars, 5 cm cells (400 x 300).
GridMap warehouse()
{
  std::vector<Rect> obs;
  for (int row = 0; row < 4; ++row)
  {
    const double y = 2.5 + row * 3.0;
    obs.push_back({1.5, y, 8.5 + (row % 2) * 2.0, y + 0.8});
    obs.push_back({11.5 - (row % 2) * 1.0, y, 18.5, y + 0.8});
  }
  for (int i = 0; i < 6; ++i)
    obs.push_back({2.0 + 3.0 * i, 1.0, 2.3 + 3.0 * i, 1.3});
  return makeWorld(20.0, 15.0, 0.05, obs);
}

// AMCL's input for a 720-beam, 180-degree, 30 m laser at `pose` (no returns read as 30 m).
LaserScanData scanAt(const GridMap& map, const Pose2D& pose)
{
  const std::vector<float> r = simulateScan(map, pose, -M_PI / 2, M_PI / 719, 720, 30.0);
  LaserScanData s;
  for (int k = 0; k < 720; ++k)
    s.readings.push_back({std::isfinite(r[k]) ? r[k] : 30.0, -M_PI / 2 + M_PI / 719 * k});
  return s;
}

}  // namespace

int main()
{
  const GridMap map = warehouse();
  CostmapParams cp;
  cp.footprint = {{0.25, 0.18}, {0.25, -0.18}, {-0.21, -0.18}, {-0.21, 0.18}};
  cp.inflation_radius = 0.5;
  cp.cost_scaling_factor = 5.0;
  Costmap global(cp);
  global.setStaticMap(map);

  // Start/goal pairs across the map (fixed seed), all in free space.
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> ux(0.5, 19.5), uy(0.5, 14.5);
  std::vector<std::pair<Pose2D, Pose2D>> queries;
  while (queries.size() < 20)
  {
    const Pose2D a{ux(rng), uy(rng), 0.0}, b{ux(rng), uy(rng), 0.0};
    if (global.costAt(a.x, a.y) < 128 && global.costAt(b.x, b.y) < 128 && std::hypot(a.x - b.x, a.y - b.y) > 8.0)
      queries.push_back({a, b});
  }
  PlannerParams pp;
  pp.cost_factor = 0.8;
  pp.use_dijkstra = false;
  const GlobalPlanner astar(pp);
  pp.use_dijkstra = true;
  const GlobalPlanner dijkstra(pp);
  std::vector<double> t_astar, t_dijkstra, lengths;
  int ok = 0;
  for (int rep = 0; rep < 3; ++rep)
    for (const auto& q : queries)
    {
      PlanResult r;
      t_astar.push_back(timeMs([&] { r = astar.makePlan(global, q.first, q.second); }));
      if (rep == 0 && r.status == PlanStatus::Ok)
      {
        ++ok;
        lengths.push_back(r.length / std::hypot(q.first.x - q.second.x, q.first.y - q.second.y));
      }
      t_dijkstra.push_back(timeMs([&] { dijkstra.makePlan(global, q.first, q.second); }));
    }

  // Costmap: one laser scan marked/cleared, then the incremental re-inflation.
  std::vector<double> t_scan, t_full;
  {
    Costmap cm(cp);
    cm.setStaticMap(map);
    for (int i = 0; i < 20; ++i)
    {
      const Pose2D pose{3.0 + 0.5 * i, 2.0, 0.3 * i};
      const std::vector<float> r = simulateScan(map, pose, -M_PI / 2, M_PI / 719, 720, 30.0);
      std::vector<Point2D> hits, ends;
      for (int k = 0; k < 720; ++k)
      {
        const double a = pose.theta - M_PI / 2 + M_PI / 719 * k;
        const double d = std::isfinite(r[k]) ? r[k] : 3.0;
        (std::isfinite(r[k]) ? hits : ends).push_back({pose.x + d * std::cos(a), pose.y + d * std::sin(a)});
      }
      t_scan.push_back(timeMs(
          [&]
          {
            cm.updateWithScan({pose.x, pose.y}, hits, ends);
            cm.updateCosts();
          }));
    }
    t_full.push_back(timeMs([&] { cm.setStaticMap(map); }));
  }

  // DWA step (mybot's config: 10 x 20 samples, 1.5 s horizon) on a 4 m rolling window.
  std::vector<double> t_dwa;
  {
    CostmapParams lp_cm = cp;
    lp_cm.rolling_window = true;
    lp_cm.width = lp_cm.height = 4.0;
    Costmap local(lp_cm);
    local.setStaticMap(map);
    LocalPlannerParams lpp;
    lpp.max_vel_x = 0.5;
    lpp.min_vel_x = -0.1;
    lpp.max_vel_trans = 0.5;
    lpp.min_vel_trans = 0.05;
    lpp.max_vel_theta = 1.5;
    lpp.min_vel_theta = 0.3;
    lpp.vx_samples = 10;
    lpp.vth_samples = 20;
    lpp.sim_time = 1.5;
    lpp.controller_frequency = 10.0;
    LocalPlanner lp(lpp);
    const PlanResult plan = astar.makePlan(global, queries[0].first, queries[0].second);
    lp.setPlan(plan.path);
    for (size_t i = 0; i + 1 < std::min<size_t>(plan.path.size(), 40); ++i)
    {
      const Pose2D& p = plan.path[i * plan.path.size() / 40];
      local.updateOrigin(p.x, p.y);
      local.updateCosts();
      t_dwa.push_back(timeMs([&] { lp.computeVelocity(local, p, {0.3, 0.0, 0.0}); }));
    }
  }

  // AMCL: one filter update (motion + 60-beam likelihood + resample) with 500 and 5000 particles.
  std::vector<double> t_amcl_small, t_amcl_large;
  for (int particles : {500, 5000})
  {
    AmclParams ap;
    ap.odom_model = OdomModelType::DiffCorrected;
    ap.laser.max_beams = 60;
    ap.resample_interval = 1;
    ap.filter.min_particles = particles;
    ap.filter.max_particles = particles;
    ap.initial_pose = {3.0, 1.8, 0.0};
    Amcl amcl(ap);
    amcl.setMap(map);
    for (int i = 0; i < 15; ++i)
    {
      const Pose2D pose{3.0 + 0.25 * i, 1.8, 0.0};
      const LaserScanData s = scanAt(map, pose);
      const double t = timeMs([&] { amcl.processScan(pose, s); });
      if (i > 0)
        (particles == 500 ? t_amcl_small : t_amcl_large).push_back(t);
    }
  }

  // AMCL global localization (the global_localization service): the first scan after it is
  // searched over the whole map (every free cell at a 20 cm stride x 72 headings), the cloud seeded
  // around the best places, then weighed; amcl_global.test's 10000 particles. Whether the robot
  // is found is for the tests (amcl_global.test, Amcl.GlobalLocalizationInTheFactoryFindsTheRobot).
  std::vector<double> t_global;
  for (const Pose2D& truth : {Pose2D{5.0, 7.3, 0.4}, Pose2D{14.0, 4.3, -2.0}, Pose2D{10.0, 13.0, 1.2}})
  {
    AmclParams ap;
    ap.odom_model = OdomModelType::DiffCorrected;
    ap.laser.max_beams = 60;
    ap.filter.min_particles = 500;
    ap.filter.max_particles = 10000;
    Amcl amcl(ap);
    amcl.setMap(map);
    amcl.globalLocalization();
    const LaserScanData s = scanAt(map, truth);
    t_global.push_back(timeMs([&] { amcl.processScan(truth, s); }));
  }

  std::printf("### Navigation: planning, control and localization cost\n\n");
  std::printf(
      "Library calls on a 20 x 15 m warehouse map at 5 cm (400 x 300 cells), thread CPU time; "
      "medians of several runs. Target: global plan < 100 ms, control step well under 100 ms (10 Hz).\n\n");
  std::printf("| what | median | runs |\n|---|---|---|\n");
  std::printf("| global plan, A* (8-connected, smoothed), >= 8 m apart | %.1f ms | %zu |\n", median(t_astar),
              t_astar.size());
  std::printf("| global plan, Dijkstra (same queries) | %.1f ms (%.1fx A*) | %zu |\n", median(t_dijkstra),
              median(t_dijkstra) / std::max(1e-9, median(t_astar)), t_dijkstra.size());
  std::printf("| plans found / path length vs straight line | %d of %zu / %.2fx | |\n", ok, queries.size(),
              median(lengths));
  std::printf("| costmap: mark/clear one 720-beam scan + re-inflate the changed area | %.2f ms | %zu |\n",
              median(t_scan), t_scan.size());
  std::printf("| costmap: static layer + full inflation of the whole map | %.1f ms | %zu |\n", median(t_full),
              t_full.size());
  std::printf("| DWA control step (10 x 20 samples, 1.5 s horizon) | %.2f ms | %zu |\n", median(t_dwa), t_dwa.size());
  std::printf("| AMCL update, 500 particles (60 beams, resample) | %.2f ms | %zu |\n", median(t_amcl_small),
              t_amcl_small.size());
  std::printf("| AMCL update, 5000 particles | %.2f ms | %zu |\n", median(t_amcl_large), t_amcl_large.size());
  std::printf(
      "| AMCL global localization: the first scan after it (whole-map search, seeding, update; "
      "10000 particles) | %.0f ms (max %.0f ms; %.0fx a 5000-particle update) | %zu |\n",
      median(t_global), *std::max_element(t_global.begin(), t_global.end()),
      median(t_global) / std::max(1e-9, median(t_amcl_large)), t_global.size());
  return 0;
}
