// SDFormat 1.7's frame graph: chains of relative_to placed in the scope's frame, and the errors.
#include "mybot_gazebo_lite/model.h"
#include "mybot_gazebo_lite/parsing.h"
#include "load_error.h"
#include "mybot_gazebo_lite/sdf_frames.h"

#include <gtest/gtest.h>

#include <cmath>

using namespace mybot_gazebo_lite;

namespace
{
btTransform at(double x, double y, double yaw)
{
  return makeTransform(btVector3(x, y, 0), btVector3(0, 0, yaw));
}

void expectPose(const btTransform& t, double x, double y, double yaw)
{
  EXPECT_NEAR(t.getOrigin().x(), x, 1e-12);
  EXPECT_NEAR(t.getOrigin().y(), y, 1e-12);
  EXPECT_NEAR(t.getOrigin().z(), 0, 1e-12);
  btScalar yz, py, rx;
  t.getBasis().getEulerZYX(yz, py, rx);
  EXPECT_NEAR(std::remainder(yz - yaw, 2 * M_PI), 0, 1e-12);
}

}  // namespace

// Each pose is composed onto the frame it is written in, up to the scope's; a frame may be
// written relative to one that comes later in the file.
TEST(SdfFrames, AChainOfRelativeToIsComposedUpToTheScope)
{
  SdfFrames f("m.sdf", "__model__");
  const int c = f.add("c", "b", SdfFrames::kScope, at(0, 2, 0), "<frame name='c'>");
  const int a = f.add("a", "", SdfFrames::kScope, at(1, 0, M_PI / 2), "<link name='a'>");
  const int b = f.add("b", "a", SdfFrames::kScope, at(1, 0, 0), "<link name='b'>");
  const int d = f.add("d", "__model__", a, at(3, 0, 0), "<joint name='d'>");
  const int e = f.add("e", "", a, at(0, 0, M_PI), "<joint name='e'>");  // no relative_to: in its fallback
  expectPose(f.resolve(a), 1, 0, M_PI / 2);
  expectPose(f.resolve(b), 1, 1, M_PI / 2);  // a's x is the model's y
  expectPose(f.resolve(c), -1, 1, M_PI / 2);
  expectPose(f.resolve(d), 3, 0, 0);
  expectPose(f.resolve(e), 1, 0, -M_PI / 2);
  expectPose(f.resolve(SdfFrames::kScope), 0, 0, 0);
  // The same pose expressed in another frame: c's pose in b's frame is what was written.
  expectPose(f.express(at(0, 2, 0), "b", SdfFrames::kScope, b, "here"), 0, 2, 0);
  expectPose(f.express(at(0, 2, 0), "", b, SdfFrames::kScope, "here"), -1, 1, M_PI / 2);
  EXPECT_EQ(f.find("b", "here"), b);
  EXPECT_EQ(f.find("__model__", "here"), SdfFrames::kScope);
}

TEST(SdfFrames, UnknownSharedAndLoopingNamesAreRefusedNamingTheElement)
{
  SdfFrames f("m.sdf", "__model__");
  const int loose = f.add("loose", "nowhere", SdfFrames::kScope, at(0, 0, 0), "<link name='loose'>");
  EXPECT_EQ(loadErrorOf([&] { f.resolve(loose); }),
            "m.sdf: <link name='loose'> <pose relative_to>: 'nowhere': no frame of that name in this model");
  // A link and a joint of one name (SDF 1.6 allows it): each is placed, but the name is no reference.
  const int wheel_link = f.add("wheel", "", SdfFrames::kScope, at(1, 0, 0), "<link name='wheel'>");
  const int wheel_joint = f.add("wheel", "", wheel_link, at(1, 0, 0), "<joint name='wheel'>");
  expectPose(f.resolve(wheel_joint), 2, 0, 0);
  const int rim = f.add("rim", "wheel", SdfFrames::kScope, at(0, 0, 0), "<frame name='rim'>");
  EXPECT_EQ(loadErrorOf([&] { f.resolve(rim); }),
            "m.sdf: <frame name='rim'> <pose relative_to>: 'wheel': names several frames of this model (links, "
            "joints, models or <frame>s)");
  const int p = f.add("p", "q", SdfFrames::kScope, at(0, 0, 0), "<link name='p'>");
  f.add("q", "r", SdfFrames::kScope, at(0, 0, 0), "<joint name='q'>");
  f.add("r", "p", SdfFrames::kScope, at(0, 0, 0), "<frame name='r'>");
  EXPECT_EQ(loadErrorOf([&] { f.resolve(p); }), "m.sdf: <link name='p'>: relative_to makes a loop: p -> q -> r -> p");
  SdfFrames w("w.world", "world");
  EXPECT_EQ(loadErrorOf([&] { w.find("__model__", "<model name='m'> <pose relative_to>"); }),
            "w.world: <model name='m'> <pose relative_to>: '__model__': no frame of that name in this world");
}
