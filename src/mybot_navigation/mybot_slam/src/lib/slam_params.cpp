#include "mybot_slam/slam_params.h"

#include <cmath>

namespace mybot_navigation
{

namespace
{
using T = SlamParamSpec::Type;
bool positive(double v)
{
  return std::isfinite(v) && v > 0.0;
}
bool nonNegative(double v)
{
  return std::isfinite(v) && v >= 0.0;
}
bool anyNumber(double v)
{
  return std::isfinite(v);
}
bool openUnit(double v)
{
  return v > 0.0 && v < 1.0;
}

SlamParamSpec number(const char* name, std::function<double&(SlamRunParams&)> f, bool (*ok)(double), const char* what)
{
  return {name, T::Number, std::move(f), nullptr, nullptr, ok, what};
}
SlamParamSpec integer(const char* name, std::function<int&(SlamRunParams&)> f, int min, const char* what)
{
  return {name, T::Integer, nullptr, std::move(f), nullptr, [min](double v) { return v >= min; }, what};
}
}  // namespace

const std::vector<SlamParamSpec>& slamParamSpecs()
{
  using P = SlamRunParams;
  static const std::vector<SlamParamSpec> specs = {
      number(
          "maxUrange", [](P& p) -> double& { return p.max_urange; }, positive, "a positive range (m)"),
      number(
          "maxRange", [](P& p) -> double& { return p.max_range; }, nonNegative,
          "a range >= 0 (m); 0 = the scan's range_max"),
      number(
          "delta", [](P& p) -> double& { return p.slam.grid.resolution; }, positive, "a positive cell size (m)"),
      number(
          "linearUpdate", [](P& p) -> double& { return p.slam.linear_update; }, nonNegative, "a distance >= 0 (m)"),
      number(
          "angularUpdate", [](P& p) -> double& { return p.slam.angular_update; }, nonNegative, "an angle >= 0 (rad)"),
      number(
          "temporalUpdate", [](P& p) -> double& { return p.slam.temporal_update; }, anyNumber,
          "a number (s; < 0 disables)"),
      number(
          "occ_thresh", [](P& p) -> double& { return p.slam.occ_thresh; }, openUnit, "a probability in (0, 1)"),
      number(
          "hit_probability", [](P& p) -> double& { return p.slam.grid.prob_hit; },
          [](double v) { return v > 0.5 && v < 1.0; }, "a probability in (0.5, 1)"),
      number(
          "miss_probability", [](P& p) -> double& { return p.slam.grid.prob_miss; },
          [](double v) { return v > 0.0 && v < 0.5; }, "a probability in (0, 0.5)"),
      integer(
          "local_map_scans", [](P& p) -> int& { return p.slam.local_map_scans; }, 2, "an integer >= 2"),
      integer(
          "match_min_points", [](P& p) -> int& { return p.slam.match_min_points; }, 0, "an integer >= 0"),
      number(
          "search_window_linear", [](P& p) -> double& { return p.slam.search_window_linear; }, nonNegative,
          "a distance >= 0 (m)"),
      number(
          "search_window_angular", [](P& p) -> double& { return p.slam.search_window_angular; }, nonNegative,
          "an angle >= 0 (rad)"),
      number(
          "search_window_motion_scale", [](P& p) -> double& { return p.slam.search_window_motion_scale; }, nonNegative,
          "a number >= 0 (multiple of the odometry's step)"),
      number(
          "search_window_motion_max", [](P& p) -> double& { return p.slam.search_window_motion_max; }, nonNegative,
          "a distance >= 0 (m)"),
      number(
          "match_translation_weight", [](P& p) -> double& { return p.slam.match_translation_weight; }, nonNegative,
          "a number >= 0 (score per m^2)"),
      number(
          "match_rotation_weight", [](P& p) -> double& { return p.slam.match_rotation_weight; }, nonNegative,
          "a number >= 0 (score per rad^2)"),
      number(
          "match_prior_cap", [](P& p) -> double& { return p.slam.match_prior_cap; }, nonNegative,
          "a distance >= 0 (m; 0 = never capped)"),
      number(
          "match_unobserved_weight", [](P& p) -> double& { return p.slam.match_unobserved_weight; },
          [](double v) { return v >= 0 && v <= 1; }, "in [0, 1]"),
      number(
          "odom_edge_sigma_xy", [](P& p) -> double& { return p.slam.odom_edge_sigma_xy; }, nonNegative,
          "a distance >= 0 (m per keyframe; 0 = no odometry edges)"),
      number(
          "odom_edge_sigma_theta", [](P& p) -> double& { return p.slam.odom_edge_sigma_theta; }, nonNegative,
          "an angle >= 0 (rad per keyframe; 0 = no odometry edges)"),
      number(
          "min_match_score", [](P& p) -> double& { return p.slam.min_match_score; },
          [](double v) { return v >= 0 && v < 1; }, "in [0, 1)"),
      number(
          "weak_match_min_score", [](P& p) -> double& { return p.slam.weak_match_min_score; },
          [](double v) { return v >= 0 && v < 1; }, "in [0, 1)"),
      number(
          "weak_match_window_linear", [](P& p) -> double& { return p.slam.weak_match_window_linear; }, nonNegative,
          "a distance >= 0 (m)"),
      number(
          "weak_match_window_angular", [](P& p) -> double& { return p.slam.weak_match_window_angular; }, nonNegative,
          "an angle >= 0 (rad)"),
      {"track_every_scan", T::Boolean, nullptr, nullptr, [](P& p) -> bool& { return p.slam.track_every_scan; },
       [](double) { return true; }, "a bool"},
      number(
          "track_min_gain", [](P& p) -> double& { return p.slam.track_min_gain; },
          [](double v) { return v >= 0 && v < 1; }, "in [0, 1)"),
      {"track_motion_fallback", T::Boolean, nullptr, nullptr,
       [](P& p) -> bool& { return p.slam.track_motion_fallback; }, [](double) { return true; }, "a bool"},
      {"track_undo_correction", T::Boolean, nullptr, nullptr,
       [](P& p) -> bool& { return p.slam.track_undo_correction; }, [](double) { return true; }, "a bool"},
      {"track_turn_fallback", T::Boolean, nullptr, nullptr, [](P& p) -> bool& { return p.slam.track_turn_fallback; },
       [](double) { return true; }, "a bool"},
      {"track_stall_search", T::Boolean, nullptr, nullptr, [](P& p) -> bool& { return p.slam.track_stall_search; },
       [](double) { return true; }, "a bool"},
      number(
          "track_stall_window_linear", [](P& p) -> double& { return p.slam.track_stall_window_linear; }, nonNegative,
          "a distance >= 0 (m)"),
      number(
          "track_stall_min_score", [](P& p) -> double& { return p.slam.track_stall_min_score; },
          [](double v) { return v > 0 && v < 1; }, "in (0, 1)"),
      number(
          "track_stall_unique_ratio", [](P& p) -> double& { return p.slam.track_stall_unique_ratio; },
          [](double v) { return v > 0 && v <= 1; }, "in (0, 1]"),
      number(
          "track_retry_window_angular", [](P& p) -> double& { return p.slam.track_retry_window_angular; },
          [](double v) { return v >= 0 && v <= M_PI; }, "an angle in [0, pi] (rad; 0 = never)"),
      {"weak_step_cauchy", T::Boolean, nullptr, nullptr, [](P& p) -> bool& { return p.slam.weak_step_cauchy; },
       [](double) { return true; }, "a bool"},
      {"keep_grazing_surfaces", T::Boolean, nullptr, nullptr,
       [](P& p) -> bool& { return p.slam.grid.keep_grazing_surfaces; }, [](double) { return true; }, "a bool"},
      {"loop_closure", T::Boolean, nullptr, nullptr, [](P& p) -> bool& { return p.slam.loop_closure; },
       [](double) { return true; }, "a bool"},
      number(
          "loop_search_radius", [](P& p) -> double& { return p.slam.loop_search_radius; }, positive,
          "a positive distance (m)"),
      number(
          "loop_min_travel", [](P& p) -> double& { return p.slam.loop_min_travel; }, positive,
          "a positive distance (m)"),
      number(
          "loop_window_linear", [](P& p) -> double& { return p.slam.loop_window_linear; }, positive,
          "a positive distance (m)"),
      number(
          "loop_window_linear_max", [](P& p) -> double& { return p.slam.loop_window_linear_max; }, positive,
          "a positive distance (m)"),
      number(
          "loop_window_angular", [](P& p) -> double& { return p.slam.loop_window_angular; }, positive,
          "a positive angle (rad)"),
      number(
          "loop_min_score", [](P& p) -> double& { return p.slam.loop_min_score; }, openUnit, "in (0, 1)"),
      number(
          "loop_max_correction", [](P& p) -> double& { return p.slam.loop_max_correction; }, nonNegative,
          "a distance >= 0 (m)"),
      number(
          "loop_max_correction_per_m", [](P& p) -> double& { return p.slam.loop_max_correction_per_m; }, nonNegative,
          "a number >= 0 (m per m travelled)"),
      number(
          "loop_min_score_gain", [](P& p) -> double& { return p.slam.loop_min_score_gain; },
          [](double v) { return std::isfinite(v) && v >= 1.0; }, "a ratio >= 1"),
      number(
          "loop_max_residual_sigma", [](P& p) -> double& { return p.slam.loop_max_residual_sigma; }, positive,
          "a positive number of standard deviations"),
      number(
          "loop_confirm_correction", [](P& p) -> double& { return p.slam.loop_confirm_correction; }, nonNegative,
          "a distance >= 0 (m; 0 applies every closure at once)"),
      number(
          "loop_large_correction", [](P& p) -> double& { return p.slam.loop_large_correction; }, positive,
          "a positive distance (m)"),
      number(
          "loop_min_score_large", [](P& p) -> double& { return p.slam.loop_min_score_large; }, openUnit, "in (0, 1)"),
      integer(
          "loop_weak_confirmations", [](P& p) -> int& { return p.slam.loop_weak_confirmations; }, 2, "an integer >= 2"),
      number(
          "loop_confirm_tolerance", [](P& p) -> double& { return p.slam.loop_confirm_tolerance; }, positive,
          "a positive distance (m)"),
      number(
          "loop_unique_ratio", [](P& p) -> double& { return p.slam.loop_unique_ratio; },
          [](double v) { return v >= 0 && v < 1; }, "in [0, 1) (0 = no uniqueness test)"),
      number(
          "loop_unique_separation", [](P& p) -> double& { return p.slam.loop_unique_separation; }, positive,
          "a positive distance (m)"),
      integer(
          "loop_confirm_attempts", [](P& p) -> int& { return p.slam.loop_confirm_attempts; }, 1, "an integer >= 1"),
      integer(
          "loop_max_candidates", [](P& p) -> int& { return p.slam.loop_max_candidates; }, 1, "an integer >= 1"),
      number(
          "loop_global_interval", [](P& p) -> double& { return p.slam.loop_global_interval; }, nonNegative,
          "a distance >= 0 (m; 0 turns the global search off)"),
      number(
          "loop_global_query_travel", [](P& p) -> double& { return p.slam.loop_global_query_travel; }, positive,
          "a positive distance (m)"),
      number(
          "loop_global_resolution", [](P& p) -> double& { return p.slam.loop_global_resolution; }, positive,
          "a positive cell size (m)"),
      number(
          "loop_global_window_linear", [](P& p) -> double& { return p.slam.loop_global_window_linear; }, positive,
          "a positive distance (m)"),
      number(
          "loop_global_window_angular", [](P& p) -> double& { return p.slam.loop_global_window_angular; }, positive,
          "a positive angle (rad)"),
      number(
          "loop_global_min_score", [](P& p) -> double& { return p.slam.loop_global_min_score; }, openUnit, "in (0, 1)"),
      number(
          "loop_global_max_correction_per_m", [](P& p) -> double& { return p.slam.loop_global_max_correction_per_m; },
          nonNegative, "a number >= 0 (m per m travelled)"),
      integer(
          "loop_global_confirmations", [](P& p) -> int& { return p.slam.loop_global_confirmations; }, 2,
          "an integer >= 2"),
      number(
          "final_match_radius", [](P& p) -> double& { return p.slam.final_match_radius; }, positive,
          "a positive distance (m)"),
      number(
          "final_window_linear", [](P& p) -> double& { return p.slam.final_window_linear; }, positive,
          "a positive distance (m)"),
      number(
          "final_window_angular", [](P& p) -> double& { return p.slam.final_window_angular; }, positive,
          "a positive angle (rad)"),
      integer(
          "final_scan_keyframes", [](P& p) -> int& { return p.slam.final_scan_keyframes; }, 0,
          "an integer >= 0 (0: scans stay where tracking put them)"),
      {"final_scan_point_to_line", T::Boolean, nullptr, nullptr,
       [](P& p) -> bool& { return p.slam.final_scan_point_to_line; }, [](double) { return true; }, "a bool"},
  };
  return specs;
}

std::string checkSlamRunParams(const SlamRunParams& p)
{
  if ((p.slam.odom_edge_sigma_xy > 0.0) != (p.slam.odom_edge_sigma_theta > 0.0))
    return "odom_edge_sigma_xy (" + std::to_string(p.slam.odom_edge_sigma_xy) + ") and odom_edge_sigma_theta (" +
           std::to_string(p.slam.odom_edge_sigma_theta) + ") must both be positive (odometry edges) or both 0 (none)";
  return "";
}

}  // namespace mybot_navigation
