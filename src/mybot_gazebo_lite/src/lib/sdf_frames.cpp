#include "mybot_gazebo_lite/sdf_frames.h"

#include "mybot_gazebo_lite/model.h"

#include <set>
#include <utility>

namespace mybot_gazebo_lite
{

namespace
{
std::string trimmed(const std::string& where)  // a model file's model is at the top: " <model ..."
{
  return where.rfind(' ', 0) == 0 ? where.substr(1) : where;
}
}  // namespace

SdfFrames::SdfFrames(std::string source, std::string scope) : source_(std::move(source))
{
  Frame root;
  root.name = std::move(scope);
  frames_.push_back(root);
  by_name_.emplace(frames_[0].name, kScope);
}

int SdfFrames::add(const std::string& name, const std::string& relative_to, int fallback, const btTransform& pose,
                   const std::string& where)
{
  Frame f;
  f.name = name;
  f.relative_to = relative_to;
  f.fallback = fallback;
  f.pose = pose;
  f.where = where;
  frames_.push_back(f);
  const int id = static_cast<int>(frames_.size()) - 1;
  by_name_.emplace(name, id);
  resolved_.clear();
  return id;
}

int SdfFrames::first(const std::string& name) const
{
  auto it = by_name_.find(name);
  return it == by_name_.end() ? -1 : it->second;
}

int SdfFrames::find(const std::string& name, const std::string& where) const
{
  const auto n = by_name_.count(name);
  if (n == 1)
    return by_name_.find(name)->second;
  const std::string scope = frames_[0].name == "world" ? "world" : "model";
  throw LoadError(source_ + ": " + trimmed(where) + ": '" + name + "': " +
                  (n == 0 ? "no frame of that name in this " + scope
                          : "names several frames of this " + scope + " (links, joints, models or <frame>s)"));
}

btTransform SdfFrames::resolve(int id) const
{
  // Up the chain of relative_to to the first frame already placed (the scope's, at worst), then
  // back down it. A frame met twice on the way up is a loop.
  std::vector<int> chain;
  std::set<int> seen;
  btTransform base = btTransform::getIdentity();
  for (int at = id; at != kScope;)
  {
    if (auto it = resolved_.find(at); it != resolved_.end())
    {
      base = it->second;
      break;
    }
    if (!seen.insert(at).second)
    {
      std::string loop;
      for (int c : chain)
        loop += (loop.empty() ? "" : " -> ") + frames_[c].name;
      throw LoadError(source_ + ": " + trimmed(frames_[at].where) + ": relative_to makes a loop: " + loop + " -> " +
                      frames_[at].name);
    }
    chain.push_back(at);
    const Frame& f = frames_[at];
    at = f.relative_to.empty() ? f.fallback : find(f.relative_to, f.where + " <pose relative_to>");
  }
  for (auto c = chain.rbegin(); c != chain.rend(); ++c)
  {
    base = base * frames_[*c].pose;
    resolved_[*c] = base;
  }
  return id == kScope ? btTransform::getIdentity() : base;
}

btTransform SdfFrames::express(const btTransform& pose, const std::string& relative_to, int fallback, int in,
                               const std::string& where) const
{
  const int of = relative_to.empty() ? fallback : find(relative_to, where);
  if (of == in)
    return pose;
  return resolve(in).inverse() * resolve(of) * pose;
}

}  // namespace mybot_gazebo_lite
