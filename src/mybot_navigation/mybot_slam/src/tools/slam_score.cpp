// Scores a SLAM map against a ground-truth map (both map_server YAML files) and optionally a
// trajectory against ground truth (text files: "stamp x y yaw" per line, matched by line).
//   slam_score --map MAP.yaml --truth TRUTH.yaml [--traj EST.txt --truth-traj GT.txt] [--tolerance 1]
//              [--align-first N]   (align map and trajectory on the first N poses only)
//   slam_score --relations FILE --tum TRAJ.tum [--local-max-dt 2]
//              Kuemmerle et al.'s metric of a trajectory (TUM: "stamp x y z qx qy qz qw", e.g.
//              slam_replay's) on a relations file: translational (m) and rotational (deg) error,
//              absolute and squared, mean, std and max; all, local (t2 - t1 <= 2 s) and the rest.
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <algorithm>
#include <cstring>
#include <fstream>
#include <sstream>
#include <string>

#include "mybot_slam/evaluation.h"
#include "mybot_nav_common/map_io.h"

using namespace mybot_navigation;

namespace
{
std::vector<Pose2D> readTrajectory(const std::string& path)
{
  std::ifstream in(path);
  if (!in)
    throw std::runtime_error("cannot open trajectory file " + path);
  std::vector<Pose2D> out;
  std::string line;
  while (std::getline(in, line))
  {
    if (line.empty() || line[0] == '#')
      continue;
    std::istringstream ss(line);
    double t;
    Pose2D p;
    if (!(ss >> t >> p.x >> p.y >> p.theta))
      throw std::runtime_error(path + ": bad line '" + line + "' (expected: stamp x y yaw)");
    out.push_back(p);
  }
  return out;
}
std::vector<StampedPose> readTum(const std::string& path)
{
  std::ifstream in(path);
  if (!in)
    throw std::runtime_error("cannot open trajectory file " + path);
  std::vector<StampedPose> out;
  std::string line;
  while (std::getline(in, line))
  {
    if (line.empty() || line[0] == '#')
      continue;
    std::istringstream ss(line);
    StampedPose p;
    double z, qx, qy, qz, qw;
    if (!(ss >> p.stamp >> p.pose.x >> p.pose.y >> z >> qx >> qy >> qz >> qw))
      throw std::runtime_error(path + ": bad line '" + line + "' (expected: stamp x y z qx qy qz qw)");
    p.pose.theta = std::atan2(2.0 * (qw * qz + qx * qy), 1.0 - 2.0 * (qy * qy + qz * qz));
    out.push_back(p);
  }
  return out;
}

void printStats(const char* name, const ErrorStats& e)
{
  std::printf("%s_count %d\n%s_mean %.4f\n%s_std %.4f\n%s_max %.4f\n%s_squared_mean %.5f\n%s_squared_std %.5f\n", name,
              e.count, name, e.mean, name, e.std, name, e.max, name, e.squared_mean, name, e.squared_std);
}

int scoreRelationsFile(const std::string& relations, const std::string& tum, double local_max_dt)
{
  try
  {
    const RelationScore s = scoreRelations(readTum(tum), readRelations(relations), local_max_dt);
    printStats("translation_m", s.translation);
    printStats("rotation_deg", s.rotation_deg);
    printStats("local_translation_m", s.local_translation);
    printStats("local_rotation_deg", s.local_rotation_deg);
    printStats("loop_translation_m", s.loop_translation);
    printStats("loop_rotation_deg", s.loop_rotation_deg);
    std::printf("missing_relations %d\n", s.missing);
  }
  catch (const std::exception& e)
  {
    std::fprintf(stderr, "slam_score: %s\n", e.what());
    return 1;
  }
  return 0;
}

const char* const kUsage =
    "usage: slam_score --map MAP.yaml --truth TRUTH.yaml [--traj EST.txt --truth-traj GT.txt] "
    "[--tolerance CELLS] [--align-first N]\n"
    "       slam_score --relations FILE --tum TRAJ.tum [--local-max-dt 2]\n";

// A number on the command line (all of the text, in range, a whole number where counted), or exit 2
// naming the option: std::stoi would end the tool with an uncaught exception.
double parseNumber(const std::string& option, const std::string& text, double min, double max, bool whole)
{
  char* end = nullptr;
  const double v = std::strtod(text.c_str(), &end);
  if (text.empty() || *end != '\0' || !std::isfinite(v) || v < min || v > max || (whole && v != std::floor(v)))
  {
    std::fprintf(stderr, "slam_score: %s must be %s in [%g, %g], got '%s'\n", option.c_str(),
                 whole ? "a whole number" : "a number", min, max, text.c_str());
    std::exit(2);
  }
  return v;
}
}  // namespace

int main(int argc, char** argv)
{
  std::string map, truth, traj, truth_traj, relations, tum;
  double local_max_dt = 2.0;
  int tolerance = 1;
  int align_first = 0;  // 0: least squares over the whole trajectory
  for (int i = 1; i < argc; ++i)
  {
    const std::string a = argv[i];
    auto value = [&]() -> std::string
    {
      if (i + 1 >= argc)
      {
        std::fprintf(stderr, "slam_score: %s needs a value\n", a.c_str());
        std::exit(2);
      }
      return argv[++i];
    };
    if (a == "--help" || a == "-h")
    {
      std::fputs(kUsage, stdout);
      return 0;
    }
    else if (a == "--map")
      map = value();
    else if (a == "--truth")
      truth = value();
    else if (a == "--traj")
      traj = value();
    else if (a == "--truth-traj")
      truth_traj = value();
    else if (a == "--tolerance")
      tolerance = static_cast<int>(parseNumber(a, value(), 0, 1000, true));
    else if (a == "--align-first")
      align_first = static_cast<int>(parseNumber(a, value(), 0, 1e9, true));
    else if (a == "--relations")
      relations = value();
    else if (a == "--tum")
      tum = value();
    else if (a == "--local-max-dt")
      local_max_dt = parseNumber(a, value(), 0, 1e9, false);
    else
    {
      std::fprintf(stderr, "slam_score: unknown argument %s\n%s", a.c_str(), kUsage);
      return 2;
    }
  }
  if (!relations.empty() || !tum.empty())
  {
    if (relations.empty() || tum.empty())
    {
      std::fprintf(stderr, "slam_score: --relations and --tum go together\n");
      return 2;
    }
    return scoreRelationsFile(relations, tum, local_max_dt);
  }
  if (map.empty() || truth.empty())
  {
    std::fprintf(stderr, "slam_score: --map and --truth are required\n");
    return 2;
  }
  try
  {
    Pose2D align;
    if (!traj.empty())
    {
      const auto est = readTrajectory(traj), gt = readTrajectory(truth_traj);
      if (align_first > 0)
      {
        // The map frame is fixed by the start pose: aligning on the first poses keeps later drift
        // of an online estimate out of the map score.
        const size_t n = std::min({static_cast<size_t>(align_first), est.size(), gt.size()});
        align = alignTrajectories(std::vector<Pose2D>(est.begin(), est.begin() + n),
                                  std::vector<Pose2D>(gt.begin(), gt.begin() + n));
      }
      else
      {
        align = alignTrajectories(est, gt);
      }
      const RelativePoseError rpe = relativePoseError(est, gt, 1);
      std::printf("ate_rmse_m %.4f\nrpe_translation_rms_m %.4f\nrpe_rotation_rms_rad %.4f\n",
                  absoluteTrajectoryRmse(est, gt, align), rpe.translation_rms, rpe.rotation_rms);
      // The fit itself: where the estimate's frame lies in the ground truth's.
      std::printf("align_x_m %.4f\nalign_y_m %.4f\nalign_yaw_rad %.5f\n", align.x, align.y, align.theta);
    }
    const MapScore s = scoreMap(loadMap(map), loadMap(truth), align, tolerance);
    std::printf("precision %.4f\nrecall %.4f\n", s.precision, s.recall);
  }
  catch (const std::exception& e)
  {
    std::fprintf(stderr, "slam_score: %s\n", e.what());
    return 1;
  }
  return 0;
}
