// Files replaced atomically: a reader, a crash or a kill -9 sees the old content or the new,
// never a part. A map is two files (NAME.pgm and NAME.yaml): both are written to temporaries in
// their own folders and renamed into place only once both are complete, so a failure before
// that leaves the old pair untouched. No ROS.
#pragma once

#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

namespace mybot_common
{

// The message names the file and what went wrong ("cannot write /x/map.yaml: Is a directory").
struct AtomicFileError : std::runtime_error
{
  using std::runtime_error::runtime_error;
};

// (path, content) pairs. Each content goes to a temporary file beside its path, is flushed to
// disk, then all temporaries are renamed over their paths in the order given. Throws
// AtomicFileError, with every temporary removed and every path untouched, if any file cannot be
// written: a path that is a folder, a folder that does not exist or is not writable, a full disk.
// The new files get the permissions a plain open() would give (0666 less the umask).
void writeFilesAtomically(const std::vector<std::pair<std::string, std::string>>& files);

inline void writeFileAtomically(const std::string& path, const std::string& content)
{
  writeFilesAtomically({{path, content}});
}

}  // namespace mybot_common
