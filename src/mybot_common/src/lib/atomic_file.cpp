#include "mybot_common/atomic_file.h"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>

namespace mybot_common
{

namespace
{
std::string folderOf(const std::string& path)
{
  const auto slash = path.find_last_of('/');
  if (slash == std::string::npos)
    return ".";
  return slash == 0 ? "/" : path.substr(0, slash);
}

[[noreturn]] void fail(const std::string& path, int err)
{
  throw AtomicFileError("cannot write " + path + ": " + std::strerror(err));
}

mode_t creationMode()
{
  const mode_t mask = ::umask(0);
  ::umask(mask);
  return 0666 & ~mask;
}

// Writes content to a new temporary beside path; returns the temporary's name.
std::string writeTemporary(const std::string& path, const std::string& content)
{
  struct stat st;
  if (::stat(path.c_str(), &st) == 0 && S_ISDIR(st.st_mode))
    fail(path, EISDIR);
  const auto slash = path.find_last_of('/');
  const std::string base = slash == std::string::npos ? path : path.substr(slash + 1);
  std::string tmp = folderOf(path) + "/." + base + ".tmp-XXXXXX";
  const int fd = ::mkstemp(tmp.data());
  if (fd < 0)
    fail(path, errno);
  auto abandon = [&](int err)
  {
    ::close(fd);
    ::unlink(tmp.c_str());
    fail(path, err);
  };
  // mkstemp makes the file 0600; give it what open(path, O_CREAT) would have.
  if (::fchmod(fd, creationMode()) != 0)
    abandon(errno);
  const char* p = content.data();
  std::size_t left = content.size();
  while (left > 0)
  {
    const ssize_t n = ::write(fd, p, left);
    if (n < 0)
    {
      if (errno == EINTR)
        continue;
      abandon(errno);
    }
    p += n;
    left -= static_cast<std::size_t>(n);
  }
  // On disk before the rename, or a power cut could leave the new name on an empty file.
  if (::fsync(fd) != 0)
    abandon(errno);
  if (::close(fd) != 0)
  {
    const int err = errno;
    ::unlink(tmp.c_str());
    fail(path, err);
  }
  return tmp;
}
}  // namespace

void writeFilesAtomically(const std::vector<std::pair<std::string, std::string>>& files)
{
  std::vector<std::string> temporaries;
  try
  {
    for (const auto& [path, content] : files)
      temporaries.push_back(writeTemporary(path, content));
  }
  catch (...)
  {
    for (const std::string& t : temporaries)
      ::unlink(t.c_str());
    throw;
  }
  for (std::size_t i = 0; i < files.size(); ++i)
    if (::rename(temporaries[i].c_str(), files[i].first.c_str()) != 0)
    {
      const int err = errno;
      for (std::size_t j = i; j < temporaries.size(); ++j)
        ::unlink(temporaries[j].c_str());
      fail(files[i].first, err);
    }
}

}  // namespace mybot_common
