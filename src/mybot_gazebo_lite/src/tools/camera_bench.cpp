// camera_bench: what a simulated camera frame costs (the ROS-free renderer and noise, one core).
// Prints Markdown table rows for bench/bench_camera: median and fastest of 9 runs of 20 frames,
// the camera turning through the world between frames.
//   camera_bench WORLDS_DIR
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "mybot_gazebo_lite/camera_model.h"
#include "mybot_gazebo_lite/parsing.h"

using namespace mybot_gazebo_lite;

namespace
{
constexpr int kRuns = 9, kFrames = 20;

// Median and fastest of kRuns runs, milliseconds a frame.
template <class F>
std::pair<double, double> time(F&& frame)
{
  std::vector<double> runs;
  for (int r = 0; r < kRuns; ++r)
  {
    const auto t0 = std::chrono::steady_clock::now();
    for (int i = 0; i < kFrames; ++i)
      frame(i);
    runs.push_back(1e3 * std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count() / kFrames);
  }
  std::sort(runs.begin(), runs.end());
  return {runs[kRuns / 2], runs[0]};
}

void row(const std::string& what, const std::pair<double, double>& t)
{
  std::printf("| %s | %.2f | %.2f |\n", what.c_str(), t.first, t.second);
}

// The camera's pose for frame i: turning in place near the middle of the world, 0.3 m up.
CameraPose pose(int i)
{
  return CameraPose{0.2 * (i % 5), 0.1 * (i % 3), 0.3, 0.31 * i};
}
}  // namespace

int main(int argc, char** argv)
{
  if (argc != 2)
  {
    std::fprintf(stderr, "usage: camera_bench WORLDS_DIR\n");
    return 2;
  }
  const std::string dir = argv[1];
  RenderSettings settings;
  settings.near = 0.02;
  settings.far = 300;
  const CameraIntrinsics big = gazeboIntrinsics(800, 800, 1.3962634), vga = gazeboIntrinsics(640, 480, 1.3962634);
  std::vector<uint8_t> rgb(800 * 800 * 3);
  std::vector<float> depth(800 * 800);
  for (const std::string name : {"mybot.world", "factory.world"})
  {
    const PrismScene scene(loadWorldFile(dir + "/" + name));
    row(name + ", 800 x 800, colour and depth",
        time([&](int i) { renderCamera(scene, big, pose(i), settings, rgb.data(), depth.data()); }));
    row(name + ", 800 x 800, depth only",
        time([&](int i) { renderCamera(scene, big, pose(i), settings, nullptr, depth.data()); }));
    row(name + ", 640 x 480, colour and depth",
        time([&](int i) { renderCamera(scene, vga, pose(i), settings, rgb.data(), depth.data()); }));
  }
  // Another robot in view, about mybot's worth of shapes (a chassis, two wheels on their sides,
  // two casters, a laser), placed anew every frame as the camera does, 1.5 m ahead of it.
  const PrismScene scene(loadWorldFile(dir + "/mybot.world"));
  std::vector<Shape> shapes(6);
  std::vector<btTransform> at(6, btTransform::getIdentity());
  shapes[0].size = btVector3(0.4, 0.2, 0.1);
  at[0].setOrigin(btVector3(0, 0, 0.1));
  for (int w = 1; w <= 2; ++w)
  {
    shapes[w].type = Shape::CYLINDER;
    shapes[w].radius = 0.1;
    shapes[w].length = 0.05;
    at[w] = makeTransform(btVector3(0, w == 1 ? 0.15 : -0.15, 0.1), btVector3(M_PI / 2, 0, 0));
  }
  for (int c = 3; c <= 4; ++c)
  {
    shapes[c].type = Shape::SPHERE;
    shapes[c].radius = 0.05;
    at[c].setOrigin(btVector3(c == 3 ? 0.15 : -0.15, 0, 0.05));
  }
  shapes[5].size = btVector3(0.05, 0.05, 0.05);
  at[5].setOrigin(btVector3(0.15, 0, 0.18));
  row("mybot.world, 800 x 800, colour and depth, another robot 1.5 m ahead",
      time(
          [&](int i)
          {
            const CameraPose p = pose(i);
            btTransform base = btTransform::getIdentity();
            base.setOrigin(btVector3(p.x + 1.5 * std::cos(p.yaw), p.y + 1.5 * std::sin(p.yaw), 0));
            std::vector<PlacedShape> placed(shapes.size());
            for (size_t s = 0; s < shapes.size(); ++s)
            {
              placed[s].shape = &shapes[s];
              placed[s].tf = base * at[s];
            }
            const PrismScene moving(placed);
            renderCamera(scene, &moving, big, p, settings, rgb.data(), depth.data());
          }));
  NoiseTable noise(1);
  row("noise on 800 x 800 colour bytes (stddev 0.007)",
      time([&](int) { noise.addToBytes(rgb.data(), rgb.size(), 0.0, 0.007); }));
  row("noise on 640 x 480 depths (stddev 0.005 m)",
      time([&](int) { noise.addToFloats(depth.data(), 640 * 480, 0.0, 0.005); }));
  return 0;
}
