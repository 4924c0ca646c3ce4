// The core of slam_replay: a bag's scans and odometry through a Slam, at full speed, no roscore
// (rosbag's C++ API). Shared by the tool and its gtest.
#pragma once

#include <functional>
#include <string>
#include <vector>

#include "mybot_slam/evaluation.h"
#include "mybot_slam/slam.h"
#include "mybot_slam/slam_params.h"

namespace mybot_navigation
{

struct BagReplayOptions
{
  std::string bag, scan_topic = "/scan", odom_topic = "/odom";
  // Odometry at a scan: "last" = the last odometry message before it in bag order (what CARMEN
  // logs embed in each FLASER); "interpolate" = between the messages around its stamp.
  std::string odom = "last";
  // Non-empty: the odometry is tf's odom_frame -> base_frame at the scan's stamp, from the bag's
  // /tf and /tf_static, looked up as slam_node does (for bags of a robot, which carry tf and not
  // always an odometry topic); odom_topic and `odom` then do not apply, and the laser's mounting
  // is tf's base_frame -> the scan's frame. A scan before the first odometry is skipped.
  std::string odom_frame;
  std::string base_frame = "base_link";
  double max_log_seconds = 0.0;  // > 0: stop after this much log from the first scan
  // The final optimisation at the end of the log (Slam::runFinalOptimization); off, the result is
  // the map and trajectory an online node has before finish_trajectory is called.
  bool final_optimization = true;
  // The laser's pose in the base frame, for every scan, instead of /tf_static's (a log whose
  // recorded mounting is known to be wrong, or that has none).
  bool override_mount = false;
  Pose2D mount;
  // Scans whose angles are the ones the shared datasets' converter derived for a CARMEN FLASER
  // record (carmenFlaserStep) get CARMEN's own: -90 deg + i * 180 / n deg. The first scan must
  // have them (else std::runtime_error: the option does not apply to this bag).
  bool carmen_angles = false;
};

// A CARMEN FLASER record carries n ranges and no angles; CARMEN and GMapping read beam i at
// -90 deg + i * 180 / n deg (1 deg steps for 180 beams, 0.5 for 360: a SICK's 181 or 361 readings
// less the last). The shared datasets' converter wrote -90 deg and 180 / (n - 1) deg steps, which
// stretch the scan by 1 / (n - 1): 0.5 deg at the last of 180 beams, 9 cm at 10 m. Returns
// CARMEN's step (rad) where a scan of 180 or 360 beams declares that converter's angle_min and
// angle_increment (to 1e-6 rad), 0 otherwise (181 or 361 readings at 180/(n-1) deg are right).
double carmenFlaserStep(double angle_min, double angle_increment, std::size_t n);

struct BagReplayResult
{
  std::vector<StampedPose> trajectory;      // every scan, after the last optimisation, map frame
  std::vector<StampedPose> odometry;        // every scan's odometry pose (the raw estimate)
  std::vector<LoopClosureRecord> closures;  // every closure matched, held, dropped or rejected, in order
  std::size_t scans = 0;
  std::size_t scans_without_odometry = 0;  // odom_frame: no transform at their stamp, skipped
  std::size_t scans_refused = 0;           // contradicting their angles or range limits, skipped as slam_node does
  std::string first_refusal;               // what was wrong with the first of them
  std::size_t scans_reangled = 0;          // carmen_angles: scans given CARMEN's beam angles
  std::size_t scans_converter_angles = 0;  // without it: scans that have a converter's derived angles
  double first_stamp = 0.0, last_stamp = 0.0;
};

// Throws std::runtime_error naming the bag. `progress(done, total)` is called per message.
BagReplayResult replayBag(const BagReplayOptions& options, Slam& slam, const SlamRunParams& params,
                          const std::function<void(std::size_t, std::size_t)>& progress = nullptr);

// slam_node's parameters from a YAML file (config/slam.yaml); node-only settings are skipped,
// anything unknown or out of range throws naming the file and parameter.
SlamRunParams loadSlamParams(const std::string& path);

}  // namespace mybot_navigation
