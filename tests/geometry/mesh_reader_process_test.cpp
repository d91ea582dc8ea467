#include "geometry/mesh_reader_process.h"

#include <sys/stat.h>
#include <sys/types.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <stdexcept>
#include <string>
#include <thread>
#include <vector>

#include <fmt/format.h>
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include "common/errors.h"
#include "geometry/mesh_stream.h"
#include "tests/geometry/test_meshes.h"

namespace ecpsim::geometry {
namespace {

using ::testing::AllOf;
using testing::FixturePath;
using ::testing::HasSubstr;
using ::testing::ThrowsMessage;

// the limits of the tests that do not probe a limit: those LoadMesh gives a small file
const MeshReaderLimits kSmallFileLimits = MeshReaderLimitsForFile(1000);

// true if this process has no child left, running or zombie (every reader was reaped)
bool NoChildLeft() { return ::waitpid(-1, nullptr, WNOHANG) < 0 && errno == ECHILD; }

// a temporary folder per test, removed afterwards
class ReaderTest : public ::testing::Test {
 protected:
  void SetUp() override {
    folder_ = std::filesystem::temp_directory_path() /
              ("ecpsim_reader_test_" + std::to_string(::getpid()));
    std::filesystem::create_directories(folder_);
  }
  void TearDown() override {
    ::unsetenv("ECPSIM_MESH_READER");
    std::filesystem::remove_all(folder_);
  }

  // replaces the reader by a shell script (ECPSIM_MESH_READER) for this test
  void UseFakeReader(const std::string& body) {
    const std::filesystem::path script = folder_ / "fake-reader.sh";
    std::ofstream(script) << "#!/bin/sh\n" << body << "\n";
    ::chmod(script.c_str(), 0755);
    ::setenv("ECPSIM_MESH_READER", script.c_str(), 1);
  }

  std::filesystem::path folder_;
};

TEST(MeshReaderLimitsTest, FloorsPlusMultiplesOfTheFileSize) {
  // the documented values: 1 GiB and 5 s for a small file; a 1M-triangle binary STL (50 MB)
  // gets 1 GiB + 16 × 50 MB and 5 s + 50 MB / (10 MB/s)
  const MeshReaderLimits small = MeshReaderLimitsForFile(300);
  EXPECT_EQ(small.memory_bytes, (std::uint64_t{1} << 30) + 16 * 300);
  EXPECT_DOUBLE_EQ(small.seconds, 5.0 + 300e-7);
  const MeshReaderLimits large = MeshReaderLimitsForFile(50'000'000);
  EXPECT_EQ(large.memory_bytes, (std::uint64_t{1} << 30) + 800'000'000);
  EXPECT_DOUBLE_EQ(large.seconds, 10.0);
  // no overflow for absurd sizes
  EXPECT_EQ(MeshReaderLimitsForFile(~std::uint64_t{0}).memory_bytes, ~std::uint64_t{0});
}

TEST_F(ReaderTest, StreamsTheTrianglesOfAFile) {
  const ImportedMesh imported = ReadMeshInReaderProcess(FixturePath("box.obj"), kSmallFileLimits);
  // OBJ: assimp keeps one vertex per face corner (6 quads → 12 triangles, 24 corners)
  EXPECT_EQ(imported.mesh.triangles.size(), 12u);
  EXPECT_EQ(imported.mesh.vertices.size(), 24u);
  EXPECT_EQ(imported.num_meshes, 1u);
  EXPECT_EQ(imported.other_faces, 0u);
  for (const Eigen::Vector3d& v : imported.mesh.vertices) {
    EXPECT_TRUE(v.x() == 0.0 || v.x() == 1.0);
    EXPECT_TRUE(v.y() == 0.0 || v.y() == 2.0);
    EXPECT_TRUE(v.z() == 0.0 || v.z() == 3.0);
  }
  EXPECT_TRUE(NoChildLeft());
}

TEST_F(ReaderTest, AssimpErrorComesBackAsItsMessage) {
  const std::string path = FixturePath("random_bytes.stl");
  EXPECT_THAT([&] { ReadMeshInReaderProcess(path, kSmallFileLimits); },
              ThrowsMessage<InputError>(
                  AllOf(HasSubstr(path + ": cannot read the mesh: "), HasSubstr("STL"))));
  EXPECT_TRUE(NoChildLeft());
}

TEST_F(ReaderTest, AssimpAbortIsAnInputError) {
  // assimp 5.2 aborts on an internal assertion when an OFF declares more faces than it has
  const std::string path = FixturePath("assert_counts.off");
  EXPECT_THAT([&] { ReadMeshInReaderProcess(path, kSmallFileLimits); },
              ThrowsMessage<InputError>(
                  AllOf(HasSubstr(path + ": cannot read the mesh: "), HasSubstr("crashed"))));
  EXPECT_TRUE(NoChildLeft());
}

TEST_F(ReaderTest, MalformedSceneIsAnInputError) {
  // assimp's RAW importer leaves a null child node for a file with two groups (a segfault
  // when it was walked in-process)
  const std::string path = FixturePath("two_groups.raw");
  EXPECT_THAT([&] { ReadMeshInReaderProcess(path, kSmallFileLimits); },
              ThrowsMessage<InputError>(
                  AllOf(HasSubstr(path), HasSubstr("malformed scene"), HasSubstr("missing"))));
}

TEST_F(ReaderTest, RunawayAllocationStopsAtTheMemoryLimit) {
  // the header declares 10⁹ vertices and faces: assimp would allocate tens of GB
  const std::string path = FixturePath("huge_counts.off");
  EXPECT_THAT([&] { ReadMeshInReaderProcess(path, kSmallFileLimits); },
              ThrowsMessage<InputError>(AllOf(HasSubstr(path), HasSubstr("memory limit"))));
  // a limit below what the reader itself needs fails the same way, for any file
  MeshReaderLimits tiny = kSmallFileLimits;
  tiny.memory_bytes = 1 << 20;
  EXPECT_THAT([&] { ReadMeshInReaderProcess(FixturePath("box.obj"), tiny); },
              ThrowsMessage<InputError>(HasSubstr("memory limit")));
  EXPECT_TRUE(NoChildLeft());
}

TEST_F(ReaderTest, HangStopsAtTheTimeLimit) {
  // a reader opening a FIFO nobody writes to blocks forever; 0.3 s is the limit here
  const std::string fifo = (folder_ / "mesh.obj").string();
  ASSERT_EQ(::mkfifo(fifo.c_str(), 0600), 0);
  MeshReaderLimits limits = kSmallFileLimits;
  limits.seconds = 0.3;
  EXPECT_THAT([&] { ReadMeshInReaderProcess(fifo, limits); },
              ThrowsMessage<InputError>(AllOf(HasSubstr(fifo), HasSubstr("0.3 s limit"))));
  EXPECT_TRUE(NoChildLeft());
}

TEST_F(ReaderTest, ReaderKilledBySignalIsNamed) {
  UseFakeReader("ulimit -c 0; kill -SEGV $$");
  EXPECT_THAT([&] { ReadMeshInReaderProcess("part.obj", kSmallFileLimits); },
              ThrowsMessage<InputError>(
                  AllOf(HasSubstr("part.obj: cannot read the mesh: "), HasSubstr("SIGSEGV"))));
  EXPECT_TRUE(NoChildLeft());
}

TEST_F(ReaderTest, ReaderExitingSilentlyIsNamed) {
  UseFakeReader("exit 7");
  EXPECT_THAT([&] { ReadMeshInReaderProcess("part.obj", kSmallFileLimits); },
              ThrowsMessage<InputError>(AllOf(HasSubstr("part.obj"), HasSubstr("status 7"))));
  EXPECT_TRUE(NoChildLeft());
}

TEST_F(ReaderTest, ForeignOutputIsAnInternalError) {
  // fd 3 is the stream: another program's output there is not a mesh
  UseFakeReader("printf 'not a mesh stream but a line of text long enough for a header' >&3");
  EXPECT_THAT([&] { ReadMeshInReaderProcess("part.obj", kSmallFileLimits); },
              ThrowsMessage<std::runtime_error>(HasSubstr("not an ecpsim mesh stream")));
  EXPECT_TRUE(NoChildLeft());
}

TEST_F(ReaderTest, HugeDeclaredCountsAreRefusedBeforeAllocating) {
  // a header claiming 2⁴⁰ vertices (24 TB), written by printf with octal escapes: refused from
  // the counts, nothing allocated, the writer killed
  mesh_stream::Header header;
  std::memcpy(header.magic, mesh_stream::kMagic, sizeof(header.magic));
  header.kind = mesh_stream::Kind::kMesh;
  header.num_vertices = std::uint64_t{1} << 40;
  std::string escaped;
  const auto* bytes = reinterpret_cast<const unsigned char*>(&header);
  for (std::size_t i = 0; i < sizeof(header); ++i) escaped += fmt::format("\\{:03o}", bytes[i]);
  UseFakeReader("printf '" + escaped + "' >&3; exec sleep 5");
  EXPECT_THAT([&] { ReadMeshInReaderProcess("part.obj", kSmallFileLimits); },
              ThrowsMessage<InputError>(AllOf(HasSubstr("part.obj"), HasSubstr("expands to"))));
  EXPECT_TRUE(NoChildLeft());
}

TEST_F(ReaderTest, MissingReaderIsAnInstallationError) {
  ::setenv("ECPSIM_MESH_READER", "/nonexistent/ecpsim-mesh-reader", 1);
  EXPECT_THAT([&] { ReadMeshInReaderProcess(FixturePath("box.obj"), kSmallFileLimits); },
              ThrowsMessage<std::runtime_error>(
                  AllOf(HasSubstr("cannot start the mesh reader"), HasSubstr("/nonexistent"))));
}

TEST_F(ReaderTest, ThreadsReadConcurrently) {
  // each thread's pipe is close-on-exec, so no reader inherits another's write end (which
  // would hold that load until the other reader ends)
  constexpr int kThreads = 4;
  constexpr int kLoadsPerThread = 3;
  std::vector<std::size_t> triangles(kThreads * kLoadsPerThread, 0);
  std::vector<std::thread> threads;
  for (int t = 0; t < kThreads; ++t) {
    threads.emplace_back([&, t] {
      for (int i = 0; i < kLoadsPerThread; ++i) {
        triangles[t * kLoadsPerThread + i] =
            ReadMeshInReaderProcess(FixturePath("box_binary.stl"), kSmallFileLimits)
                .mesh.triangles.size();
      }
    });
  }
  for (std::thread& thread : threads) thread.join();
  for (std::size_t n : triangles) EXPECT_EQ(n, 12u);
  EXPECT_TRUE(NoChildLeft());
}

}  // namespace
}  // namespace ecpsim::geometry
