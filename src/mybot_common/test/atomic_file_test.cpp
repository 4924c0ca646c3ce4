#include "mybot_common/atomic_file.h"
#include "mybot_common/temp_dir.h"

#include <dirent.h>
#include <gtest/gtest.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cstdlib>
#include <fstream>
#include <sstream>

using mybot_common::AtomicFileError;
using mybot_common::writeFileAtomically;
using mybot_common::writeFilesAtomically;

namespace
{
class AtomicFile : public ::testing::Test
{
protected:
  std::string path(const std::string& name) const { return tmp_.file(name); }
  static std::string read(const std::string& p)
  {
    std::ifstream f(p, std::ios::binary);
    std::stringstream s;
    s << f.rdbuf();
    return s.str();
  }
  int entries() const
  {
    int n = 0;
    DIR* d = ::opendir(dir_.c_str());
    while (dirent* e = ::readdir(d))
      n += std::string(e->d_name) != "." && std::string(e->d_name) != "..";
    ::closedir(d);
    return n;
  }
  const mybot_common::TempDir tmp_{"atomic_file_test"};
  const std::string& dir_ = tmp_.path();
};
}  // namespace

TEST_F(AtomicFile, WritesNewFiles)
{
  writeFilesAtomically({{path("m.pgm"), std::string("P5\n\0\1", 5)}, {path("m.yaml"), "image: m.pgm\n"}});
  EXPECT_EQ(read(path("m.pgm")), std::string("P5\n\0\1", 5));
  EXPECT_EQ(read(path("m.yaml")), "image: m.pgm\n");
  EXPECT_EQ(entries(), 2);  // no temporaries left behind
}

TEST_F(AtomicFile, ReplacesOldContent)
{
  writeFileAtomically(path("a"), "old old old");
  writeFileAtomically(path("a"), "new");
  EXPECT_EQ(read(path("a")), "new");
}

TEST_F(AtomicFile, PermissionsFollowTheUmask)
{
  const mode_t old = ::umask(022);
  writeFileAtomically(path("a"), "x");
  ::umask(old);
  struct stat st;
  ASSERT_EQ(::stat(path("a").c_str(), &st), 0);
  EXPECT_EQ(st.st_mode & 0777, 0644u);
}

// The map pair: the YAML path is a folder, so nothing is written, and the old PGM stays.
TEST_F(AtomicFile, SecondPathAFolderLeavesTheOldPairIntact)
{
  writeFileAtomically(path("m.pgm"), "old image");
  ASSERT_EQ(::mkdir(path("m.yaml").c_str(), 0755), 0);
  try
  {
    writeFilesAtomically({{path("m.pgm"), "new image"}, {path("m.yaml"), "new yaml"}});
    FAIL() << "expected AtomicFileError";
  }
  catch (const AtomicFileError& e)
  {
    EXPECT_NE(std::string(e.what()).find(path("m.yaml")), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("directory"), std::string::npos) << e.what();
  }
  EXPECT_EQ(read(path("m.pgm")), "old image");
  EXPECT_EQ(entries(), 2);  // m.pgm and the folder m.yaml; no temporaries
}

TEST_F(AtomicFile, MissingFolderNamesThePath)
{
  try
  {
    writeFileAtomically(path("no/such/folder/m.yaml"), "x");
    FAIL() << "expected AtomicFileError";
  }
  catch (const AtomicFileError& e)
  {
    EXPECT_NE(std::string(e.what()).find("no/such/folder/m.yaml"), std::string::npos) << e.what();
  }
}

// A folder that cannot hold files (here a plain file where the folder should be; root ignores
// read-only permissions, so that case would not test anything when run as root).
TEST_F(AtomicFile, ParentThatIsAFileLeavesTheOldFile)
{
  writeFileAtomically(path("a"), "old");
  EXPECT_THROW(writeFileAtomically(path("a/b"), "new"), AtomicFileError);
  EXPECT_EQ(read(path("a")), "old");
  EXPECT_EQ(entries(), 1);
}

TEST_F(AtomicFile, RelativePathUsesTheCurrentFolder)
{
  char cwd[4096];
  ASSERT_NE(::getcwd(cwd, sizeof cwd), nullptr);
  ASSERT_EQ(::chdir(dir_.c_str()), 0);
  writeFileAtomically("rel.txt", "here");
  ASSERT_EQ(::chdir(cwd), 0);
  EXPECT_EQ(read(path("rel.txt")), "here");
}
