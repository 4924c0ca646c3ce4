// Column renderer for the simulated cameras. The static world is treated as
// 2.5D: every static shape is a vertical prism (its cross-section at mid-height,
// extruded over its z-extent). One 2D ray per image column gives every prism
// the column crosses; each pixel of the column then takes the nearest prism
// face (side, top or bottom) its 3D ray meets, else the floor, else the sky.
// Exact for upright boxes and cylinders; spheres render as cylinders. Robots and
// dynamic bodies are sliced the same way, anew for each frame.
#pragma once

#include "mybot_gazebo_lite/model.h"
#include "mybot_gazebo_lite/raycast2d.h"

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

namespace mybot_gazebo_lite
{

// Pinhole intrinsics as gazebo_ros_camera_utils computes them (pixels).
struct CameraIntrinsics
{
  int width = 0, height = 0;
  double fx = 0, fy = 0, cx = 0, cy = 0;
};

// focal = width / (2 tan(hfov / 2)) and (cx, cy) = ((w + 1) / 2, (h + 1) / 2),
// each unless given non-zero (the plugin's <focalLength>, <Cx>, <Cy>).
CameraIntrinsics gazeboIntrinsics(int width, int height, double hfov, double focal = 0, double cx = 0, double cy = 0);

// A level camera: optical axis along yaw in the world's horizontal plane.
struct CameraPose
{
  double x = 0, y = 0, z = 0, yaw = 0;
};

class PrismScene
{
public:
  struct Prism
  {
    double zmin, zmax;
    float color[3];
  };
  // The world's static models (and its ground plane).
  explicit PrismScene(const WorldSpec& world, double cell = 0.5);
  // Shapes placed anywhere, no ground: the robots and dynamic bodies of one frame.
  explicit PrismScene(const std::vector<PlacedShape>& shapes, double cell = 0.5);
  const std::vector<Prism>& prisms() const { return prisms_; }
  bool ground() const { return ground_; }
  bool empty() const { return prisms_.empty(); }

  // The prism entered/exited by a horizontal ray, with the entry's 2D normal.
  struct ColumnHit
  {
    const Prism* prism;
    double t_in, t_out;  // along the unit 2D direction
    double nx, ny;
  };
  // Hits sorted by t_in; scratch is reused between calls.
  void column(double x, double y, double dx, double dy, double max_range, std::vector<ColumnHit>& out) const;
  // This scene's hits appended to `out`, unsorted (a column through several scenes).
  void appendColumn(double x, double y, double dx, double dy, double max_range, std::vector<ColumnHit>& out) const;

private:
  void addShape(const Shape& s, const btTransform& tf, const float color[3]);
  void index(double cell);
  std::vector<Prism> prisms_;
  std::vector<Segment2> segments_;
  std::vector<Circle2> circles_;
  std::vector<int> seg_prism_, circle_prism_;
  std::unique_ptr<RayCaster2D> caster_;
  bool ground_ = false;
  mutable std::vector<RayCaster2D::Crossing> crossings_;
};

struct RenderSettings
{
  double near = 0.1, far = 100.0;  // <clip>
};

// rgb: width*height*3 bytes (R, G, B, row-major, row 0 at the top) or nullptr;
// depth: width*height floats, distance along the optical axis in metres, +inf
// where nothing lies within [near, far] (the sky), or nullptr.
// Pixel (u, v) looks along ((u - cx) / fx, (v - cy) / fy, 1) in the optical
// frame (x right, y down, z forward), so the image agrees with its CameraInfo.
// `moving` (may be null): robots and dynamic bodies where they are at this frame, drawn with the
// static scene (whose ground plane counts).
void renderCamera(const PrismScene& scene, const PrismScene* moving, const CameraIntrinsics& k, const CameraPose& pose,
                  const RenderSettings& s, uint8_t* rgb, float* depth);
inline void renderCamera(const PrismScene& scene, const CameraIntrinsics& k, const CameraPose& pose,
                         const RenderSettings& s, uint8_t* rgb, float* depth)
{
  renderCamera(scene, nullptr, k, pose, s, rgb, depth);
}

// Cheap Gaussian noise for images: a table of N(0, 1) samples read from a
// random start with a random odd stride, so a 640x480 frame costs no Box-Muller.
// The point a depth pixel (u, v) at range along the optical axis `depth` sees, in the optical
// convention of ROS cameras (x right, y down, z forward): the pinhole model inverted. NaN depth
// gives NaN coordinates (no reading).
struct OpticalPoint
{
  float x, y, z;
};
inline OpticalPoint depthToPoint(const CameraIntrinsics& k, int u, int v, float depth)
{
  return {static_cast<float>((u - k.cx) * depth / k.fx), static_cast<float>((v - k.cy) * depth / k.fy), depth};
}

// The ROS image encoding gazebo_ros_camera_utils gives a Gazebo <image><format> (R8G8B8 -> rgb8,
// L16 -> mono16, BAYER_RGGB8 -> bayer_rggb8, ...); "" for a format it does not know.
std::string gazeboImageEncoding(const std::string& format);
// A rendered rgb8 image (width x height) in `encoding` (one gazeboImageEncoding gives): its
// bytes, `step` set to a row's. mono: the luma (0.299 R + 0.587 G + 0.114 B); 16-bit samples
// little-endian, 257 times the 8-bit value; bayer: each pixel the colour of its place in the
// 2 x 2 pattern the encoding names ("rggb": R G on even rows, G B on odd ones).
std::vector<uint8_t> encodeImage(const std::vector<uint8_t>& rgb, int width, int height, const std::string& encoding,
                                 uint32_t& step);

class NoiseTable
{
public:
  explicit NoiseTable(uint32_t seed, size_t size = 1 << 18);             // at least 8192
  void addToBytes(uint8_t* data, size_t n, double mean, double stddev);  // stddev in units of 255
  void addToFloats(float* data, size_t n, double mean, double stddev);   // only finite values
private:
  size_t start(size_t* stride);
  std::vector<float> table_;
  uint64_t state_;
  // Bytes take the sum of two small tables in 1/256 of a grey level, each holding half the
  // variance, for one (mean, stddev), made at the first frame that asks, both read in order from
  // random starts. Their sizes, 4096 and the prime 4093, give a sequence that repeats only after
  // 16.8 million bytes (a frame of 800x800 is 1.9 million), and both stay in the first-level
  // cache: walking the float table by a random stride in double precision cost an 800x800 frame
  // 8 ms, as much as rendering it.
  static constexpr size_t kBytesA = 4096, kBytesB = 4093;
  std::vector<int32_t> bytes_a_, bytes_b_;
  double bytes_mean_ = 0.0, bytes_stddev_ = -1.0;
};

}  // namespace mybot_gazebo_lite
