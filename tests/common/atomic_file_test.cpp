// Atomic replacement of output files: only regular files (or nothing) are replaced, temporaries
// follow the one naming scheme and do not outlive their writer.

#include "common/atomic_file.h"

#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include <fmt/format.h>
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include "common/errors.h"

namespace ecpsim {
namespace {

namespace fs = std::filesystem;
using ::testing::AllOf;
using ::testing::HasSubstr;

class AtomicFileTest : public ::testing::Test {
 protected:
  void SetUp() override {
    const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
    dir_ = fs::temp_directory_path() / fmt::format("ecpsim_atomic_{}_{}", getpid(), info->name());
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }

  static std::string Read(const fs::path& path) {
    std::ifstream in(path, std::ios::binary);
    std::stringstream text;
    text << in.rdbuf();
    return text.str();
  }

  // the names in the test folder other than `except`
  int CountOthers(const std::string& except) const {
    int count = 0;
    for (const auto& entry : fs::directory_iterator(dir_)) {
      if (entry.path().filename() != except) ++count;
    }
    return count;
  }

  // the error of writing `path`, expecting one
  static std::string WriteError(const fs::path& path) {
    try {
      WriteFileAtomically(path.string(), "new");
    } catch (const InputError& e) {
      return e.what();
    }
    ADD_FAILURE() << "writing " << path << " did not throw";
    return "";
  }

  fs::path dir_;
};

TEST_F(AtomicFileTest, CreatesANewFileAndReplacesARegularOne) {
  const fs::path path = dir_ / "out.txt";
  WriteFileAtomically(path.string(), "first");
  EXPECT_EQ(Read(path), "first");
  WriteFileAtomically(path.string(), "second, longer");
  EXPECT_EQ(Read(path), "second, longer");
  EXPECT_EQ(CountOthers("out.txt"), 0);  // no temporary left
}

TEST_F(AtomicFileTest, RefusesAFifoAndLeavesItThere) {
  const fs::path fifo = dir_ / "summary.json";
  ASSERT_EQ(::mkfifo(fifo.c_str(), 0600), 0);
  EXPECT_THAT(WriteError(fifo), AllOf(HasSubstr(fifo.string()), HasSubstr("FIFO"),
                                      HasSubstr("expected a regular file or nothing")));
  EXPECT_TRUE(fs::is_fifo(fs::symlink_status(fifo)));
  EXPECT_EQ(CountOthers("summary.json"), 0);
}

TEST_F(AtomicFileTest, RefusesASymlinkAndLeavesItAndItsTargetAlone) {
  const fs::path target = dir_ / "target.txt", link = dir_ / "link.txt";
  std::ofstream(target) << "keep";
  fs::create_symlink(target, link);
  EXPECT_THAT(WriteError(link),
              AllOf(HasSubstr(link.string()), HasSubstr("symbolic link (to " + target.string()),
                    HasSubstr("expected a regular file or nothing")));
  EXPECT_TRUE(fs::is_symlink(link));
  EXPECT_EQ(Read(target), "keep");
  EXPECT_EQ(CountOthers("link.txt"), 1);  // the target only
}

TEST_F(AtomicFileTest, RefusesAFolderAndLeavesItsContents) {
  const fs::path folder = dir_ / "trajectory.csv";
  fs::create_directories(folder);
  std::ofstream(folder / "inside.txt") << "keep";
  EXPECT_THAT(WriteError(folder),
              AllOf(HasSubstr(folder.string()), HasSubstr("a folder is there")));
  EXPECT_EQ(Read(folder / "inside.txt"), "keep");
  EXPECT_EQ(CountOthers("trajectory.csv"), 0);
}

TEST_F(AtomicFileTest, RefusesADeviceNode) {
  // /dev/null is a character device on every Linux system; nothing is created next to it
  EXPECT_THAT(WriteError("/dev/null"), HasSubstr("a character device is there"));
}

TEST_F(AtomicFileTest, AMissingFolderIsAnErrorNamingThePath) {
  EXPECT_THAT(WriteError(dir_ / "missing" / "out.txt"),
              AllOf(HasSubstr("missing/out.txt"), HasSubstr("No such file")));
}

TEST_F(AtomicFileTest, AnUncommittedFileLeavesNothing) {
  const fs::path path = dir_ / "video.mp4";
  std::ofstream(path) << "old";
  {
    AtomicFile file(path.string());
    std::FILE* out = file.Create();
    std::fputs("half", out);
    std::fclose(out);
    EXPECT_TRUE(fs::exists(file.temp_path()));
  }
  EXPECT_EQ(Read(path), "old");
  EXPECT_EQ(CountOthers("video.mp4"), 0);
}

TEST_F(AtomicFileTest, CommitRefusesADestinationThatBecameAFifo) {
  const fs::path path = dir_ / "out.png";
  AtomicFile file(path.string());
  std::fclose(file.Create());
  ASSERT_EQ(::mkfifo(path.c_str(), 0600), 0);
  EXPECT_THROW(file.Commit(), InputError);
  EXPECT_TRUE(fs::is_fifo(fs::symlink_status(path)));
  EXPECT_EQ(CountOthers("out.png"), 0);  // the temporary is removed
}

TEST_F(AtomicFileTest, TemporariesFollowTheNamingScheme) {
  AtomicFile file((dir_ / "frame_000001.png").string());
  const std::string name = fs::path(file.temp_path()).filename().string();
  EXPECT_EQ(name.rfind(fmt::format("frame_000001.png.tmp-{}-", getpid()), 0), 0u) << name;
  EXPECT_TRUE(IsTemporaryName(name));
  EXPECT_FALSE(IsTemporaryName("frame_000001.png"));
  EXPECT_FALSE(IsTemporaryName("notes.tmp-draft"));
}

TEST_F(AtomicFileTest, RemovesOnlyTheTemporariesOfDeadProcesses) {
  // a process that has exited: its PID is not running once it is reaped
  const pid_t child = ::fork();
  if (child == 0) ::_exit(0);
  int status = 0;
  ASSERT_EQ(::waitpid(child, &status, 0), child);
  const std::string dead = fmt::format("trajectory.csv.tmp-{}-0", child);
  const std::string alive = fmt::format("summary.json.tmp-{}-3", getpid());
  for (const std::string& name : {dead, alive, std::string("trajectory.csv")}) {
    std::ofstream(dir_ / name) << "x";
  }
  EXPECT_EQ(RemoveStaleTemporaries(dir_.string()), 1);
  EXPECT_FALSE(fs::exists(dir_ / dead));
  EXPECT_TRUE(fs::exists(dir_ / alive));
  EXPECT_TRUE(fs::exists(dir_ / "trajectory.csv"));
  EXPECT_EQ(RemoveStaleTemporaries((dir_ / "missing").string()), 0);
}

}  // namespace
}  // namespace ecpsim
