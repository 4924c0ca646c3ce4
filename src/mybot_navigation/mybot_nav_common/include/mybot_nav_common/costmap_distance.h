// Exact Euclidean distance transform on a grid (Felzenszwalb & Huttenlocher 2012), shared by
// AMCL's likelihood field and the costmap's inflation layer. No ROS types.
#pragma once

#include <cstdint>
#include <vector>

namespace mybot_navigation
{

// For a width x height row-major grid where seed[i] != 0 marks an obstacle, returns the
// distance in cells from every cell to the nearest obstacle cell centre (a huge value if there
// is no obstacle at all).
std::vector<float> distanceTransform(const std::vector<uint8_t>& seed, int width, int height);

}  // namespace mybot_navigation
