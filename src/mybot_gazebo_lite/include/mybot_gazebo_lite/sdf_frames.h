// SDFormat 1.7's pose frame semantics (sdformat.org, "Pose frame semantics"), as far as a loader
// needs them: where each frame of one scope starts, in the scope's own frame.
#pragma once

#include <LinearMath/btTransform.h>

#include <map>
#include <string>
#include <vector>

namespace mybot_gazebo_lite
{

// The frames of one scope: a model's (its frame is `__model__`) or a world's (`world`). Every
// link, joint, nested model and explicit <frame> of the scope is a frame, and each one's <pose>
// may be written relative_to any other frame of the same scope by name; without relative_to it
// is relative to the element's default (a link's and a <frame>'s is the scope's frame, a joint's
// its child link, a <frame attached_to=X>'s X). SDF 1.6 and older files have no relative_to and
// come out as they always did.
//
// A frame is placed by following its chain of relative_to to the scope's frame. A name that no
// frame of the scope has, one that several have (SDF 1.6 let a link and a joint share a name;
// such a name can be used, just not as a relative_to), and a chain that comes back on itself are
// refused, naming the element that wrote it.
class SdfFrames
{
public:
  // `source` prefixes errors (the file); `scope` is "__model__" or "world".
  SdfFrames(std::string source, std::string scope);

  static constexpr int kScope = 0;  // the scope's own frame

  // A frame `name` whose pose, written at `where`, is `pose` in the frame named `relative_to`,
  // or in frame `fallback` (an id from add) where relative_to is "". Returns its id. Names are
  // looked up when a pose is resolved, so a frame may be written relative to one added later.
  int add(const std::string& name, const std::string& relative_to, int fallback, const btTransform& pose,
          const std::string& where);
  // The id of the one frame called `name` (the scope's frame by its name), for a reference
  // written at `where`; throws LoadError when there is none or more than one.
  int find(const std::string& name, const std::string& where) const;
  // -1 when no frame is called `name`, else the first one's id.
  int first(const std::string& name) const;
  // Frame `id`'s pose in the scope's frame.
  btTransform resolve(int id) const;
  // A pose written at `where` relative_to `relative_to` (or, where that is "", in frame
  // `fallback`), expressed in frame `in` instead.
  btTransform express(const btTransform& pose, const std::string& relative_to, int fallback, int in,
                      const std::string& where) const;

private:
  struct Frame
  {
    std::string name, relative_to, where;
    int fallback = kScope;
    btTransform pose = btTransform::getIdentity();
  };
  std::string source_;
  std::vector<Frame> frames_;
  std::multimap<std::string, int> by_name_;
  mutable std::map<int, btTransform> resolved_;
};

}  // namespace mybot_gazebo_lite
