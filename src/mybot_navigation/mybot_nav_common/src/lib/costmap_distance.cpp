#include "mybot_nav_common/costmap_distance.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace mybot_navigation
{
namespace
{

// 1D squared-distance transform of f (lower envelope of parabolas).
void transform1d(const float* f, int n, float* d, int* v, float* z)
{
  constexpr float kInf = std::numeric_limits<float>::infinity();
  int first = 0;
  while (first < n && f[first] == kInf)
    ++first;
  if (first == n)
  {
    for (int q = 0; q < n; ++q)
      d[q] = kInf;
    return;
  }
  auto intersect = [&](int q, int p)
  { return ((f[q] + static_cast<float>(q) * q) - (f[p] + static_cast<float>(p) * p)) / (2.0f * (q - p)); };
  int k = 0;
  v[0] = first;
  z[0] = -kInf;
  z[1] = kInf;
  for (int q = first + 1; q < n; ++q)
  {
    if (f[q] == kInf)
      continue;
    float s = intersect(q, v[k]);
    while (s <= z[k])
    {
      --k;
      s = intersect(q, v[k]);
    }
    ++k;
    v[k] = q;
    z[k] = s;
    z[k + 1] = kInf;
  }
  k = 0;
  for (int q = 0; q < n; ++q)
  {
    while (z[k + 1] < q)
      ++k;
    const float dq = static_cast<float>(q - v[k]);
    d[q] = dq * dq + f[v[k]];
  }
}

}  // namespace

std::vector<float> distanceTransform(const std::vector<uint8_t>& seed, int width, int height)
{
  constexpr float kInf = std::numeric_limits<float>::infinity();
  const size_t cells = static_cast<size_t>(width) * height;
  std::vector<float> g(cells);
  for (size_t i = 0; i < cells; ++i)
    g[i] = seed[i] ? 0.0f : kInf;
  const int n = std::max(width, height);
  std::vector<float> f(n), d(n), z(n + 1);
  std::vector<int> v(n);
  for (int x = 0; x < width; ++x)  // columns
  {
    for (int y = 0; y < height; ++y)
      f[y] = g[static_cast<size_t>(y) * width + x];
    transform1d(f.data(), height, d.data(), v.data(), z.data());
    for (int y = 0; y < height; ++y)
      g[static_cast<size_t>(y) * width + x] = d[y];
  }
  for (int y = 0; y < height; ++y)  // rows
  {
    float* row = &g[static_cast<size_t>(y) * width];
    transform1d(row, width, d.data(), v.data(), z.data());
    for (int x = 0; x < width; ++x)
      row[x] = d[x] == kInf ? std::numeric_limits<float>::max() : std::sqrt(d[x]);
  }
  return g;
}

}  // namespace mybot_navigation
