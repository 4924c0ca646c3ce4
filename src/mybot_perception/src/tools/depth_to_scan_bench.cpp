// depth_to_scan_bench: the conversion's cost per frame (median of 9 runs of 200 frames) for
// 32FC1 and 16UC1 images of the sizes given (default 640x480 and 320x240), scan_height 1 and 10.
// Prints Markdown table rows. No ROS.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <random>
#include <string>
#include <vector>

#include "mybot_perception/depth_to_scan.h"

using namespace mybot_perception;

namespace
{
template <typename T>
double usPerFrame(const std::vector<T>& img, const PinholeColumns& c, const DepthToScanParams& p)
{
  std::vector<double> runs;
  volatile float sink = 0.0f;
  for (int r = 0; r < 9; ++r)
  {
    const auto t0 = std::chrono::steady_clock::now();
    for (int k = 0; k < 200; ++k)
      sink = sink + depthToScan(img.data(), c.width, c, p).ranges[c.width / 2];
    runs.push_back(std::chrono::duration<double, std::micro>(std::chrono::steady_clock::now() - t0).count() / 200);
  }
  std::nth_element(runs.begin(), runs.begin() + 4, runs.end());
  return runs[4];
}
}  // namespace

int main(int argc, char** argv)
{
  std::vector<std::pair<int, int>> sizes = {{640, 480}, {320, 240}};
  if (argc > 1)
  {
    sizes.clear();
    for (int i = 1; i < argc; ++i)
    {
      int w = 0, h = 0;
      if (std::sscanf(argv[i], "%dx%d", &w, &h) != 2 || w < 2 || h < 1)
      {
        std::fprintf(stderr, "depth_to_scan_bench: size '%s' is not WIDTHxHEIGHT\n", argv[i]);
        return 1;
      }
      sizes.push_back({w, h});
    }
  }
  std::mt19937 rng(1);
  std::uniform_real_distribution<float> depth(0.3f, 12.0f);
  for (auto [w, h] : sizes)
  {
    const PinholeColumns c = pinholeFromFov(w, h, 1.5184);  // the D435i's 87 degrees
    std::vector<float> metres(static_cast<std::size_t>(w) * h);
    std::vector<std::uint16_t> mm(metres.size());
    for (std::size_t i = 0; i < metres.size(); ++i)
    {
      metres[i] = depth(rng);
      mm[i] = static_cast<std::uint16_t>(metres[i] * 1000);
    }
    for (int rows : {1, 10})
    {
      DepthToScanParams p;
      p.scan_height = rows;
      std::printf("| %d x %d | %d | %.1f | %.1f |\n", w, h, rows, usPerFrame(metres, c, p), usPerFrame(mm, c, p));
    }
  }
  return 0;
}
