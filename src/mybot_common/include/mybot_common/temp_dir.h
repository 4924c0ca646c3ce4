// A fresh directory under the system's temporary directory for one test's files, removed with
// everything in it when the object goes: a unique name, so that two runs of the suites side by
// side (a gate beside a soak) never share a file, and nothing left behind after thousands of runs.
#pragma once

#include <filesystem>
#include <stdexcept>
#include <string>
#include <system_error>

#include <stdlib.h>  // mkdtemp (POSIX)

namespace mybot_common
{
class TempDir
{
public:
  explicit TempDir(const std::string& prefix = "mybot")
  {
    std::string name = (std::filesystem::temp_directory_path() / (prefix + ".XXXXXX")).string();
    if (::mkdtemp(name.data()) == nullptr)
      throw std::runtime_error("cannot create a temporary directory " + name);
    path_ = name;
  }
  ~TempDir()
  {
    std::error_code ignored;
    std::filesystem::remove_all(path_, ignored);
  }
  TempDir(const TempDir&) = delete;
  TempDir& operator=(const TempDir&) = delete;

  const std::string& path() const { return path_; }
  // The path of `name` inside the directory.
  std::string file(const std::string& name) const { return path_ + "/" + name; }

private:
  std::string path_;
};
}  // namespace mybot_common
