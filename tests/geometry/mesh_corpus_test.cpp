// Robustness of mesh loading: every file of a corpus of truncated, bit-flipped and number-mangled
// meshes (tests/fixtures/make_mesh_corpus.py, generated into the build tree) must load as a valid
// mesh or be rejected with an InputError naming it; never crash, hang or abort.

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <iostream>
#include <map>
#include <string>
#include <vector>

#include <fmt/format.h>
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include "common/errors.h"
#include "geometry/convex_hull.h"
#include "geometry/mass_properties.h"
#include "geometry/mesh_bounds.h"
#include "geometry/mesh_io.h"
#include "geometry/mesh_topology.h"

namespace ecpsim::geometry {
namespace {

using ::testing::HasSubstr;

// s: the reader's time limit here. Each corpus file is ≤ 10 kB and reads in ~15 ms, but some
// truncated PLY headers make assimp 5.2 spin forever; LoadMesh's own 5 s floor would make this
// test last over a minute. A slow legitimate read that hits this limit still passes the test
// (a timeout is an InputError naming the file), so the value only trades time for coverage.
constexpr double kCorpusReadSeconds = 0.3;

// the outcome of one file, for the summary: "loaded" or the kind of rejection
std::string Outcome(const std::string& message) {
  for (const char* kind : {"crashed", "memory limit", "took longer", "malformed scene"}) {
    if (message.find(kind) != std::string::npos) return kind;
  }
  return "rejected";
}

// what every loaded mesh must be: indices in range, no degenerate triangle, finite coordinates
// within the supported size range
void ExpectValidMesh(const TriangleMesh& mesh, const std::string& path) {
  ASSERT_FALSE(mesh.triangles.empty()) << path;
  const int n = static_cast<int>(mesh.vertices.size());
  for (const Eigen::Vector3i& t : mesh.triangles) {
    ASSERT_TRUE(t.minCoeff() >= 0 && t.maxCoeff() < n) << path;
    ASSERT_TRUE(t[0] != t[1] && t[1] != t[2] && t[2] != t[0]) << path;
  }
  for (const Eigen::Vector3d& v : mesh.vertices) ASSERT_TRUE(v.allFinite()) << path;
  EXPECT_TRUE(IsInSupportedSizeRange(ComputeMeshBounds(mesh.vertices))) << path;
}

TEST(MeshCorpusTest, EveryCorruptFileLoadsAsAValidMeshOrIsRejectedNamingIt) {
  const std::filesystem::path corpus =
      std::filesystem::path(ECPSIM_BINARY_DIR) / "tests" / "mesh_corpus";
  const std::string command =
      fmt::format("'{}' '{}/tests/fixtures/make_mesh_corpus.py' '{}' > /dev/null", ECPSIM_PYTHON3,
                  ECPSIM_SOURCE_DIR, corpus.string());
  ASSERT_EQ(std::system(command.c_str()), 0) << command;
  std::vector<std::string> files;
  for (const auto& entry : std::filesystem::directory_iterator(corpus)) {
    files.push_back(entry.path().string());
  }
  std::sort(files.begin(), files.end());
  // 10 sources × (12 cuts + 24 flips) + 8 text sources × 8 numbers + 4 STL counts
  ASSERT_EQ(files.size(), 428u);

  std::map<std::string, int> outcomes;
  for (const std::string& path : files) {
    MeshReaderLimits limits = MeshReaderLimitsForFile(std::filesystem::file_size(path));
    limits.seconds = kCorpusReadSeconds;
    try {
      // what `ecpsim hull` does with a file: load, hull, mass properties of a solid
      const TriangleMesh mesh = LoadMesh(path, 1.0, limits);
      ExpectValidMesh(mesh, path);
      ++outcomes["loaded"];
      const MeshTopology topology = AnalyzeTopology(mesh);
      const ConvexHull hull = ComputeConvexHull(mesh.vertices, path);
      EXPECT_GE(hull.faces.size(), 4u) << path;
      if (topology.closed && topology.consistently_oriented) {
        const MassProperties p = ComputeMassProperties(mesh, 1000.0, path);
        EXPECT_TRUE(p.inertia.allFinite() && std::isfinite(p.mass) && p.mass > 0.0) << path;
        ++outcomes["solid"];
      }
    } catch (const InputError& e) {
      EXPECT_THAT(e.what(), HasSubstr(path));
      ++outcomes[Outcome(e.what())];
    } catch (const std::exception& e) {
      ADD_FAILURE() << path << ": not an InputError: " << e.what();
    }
  }
  std::string summary;
  for (const auto& [outcome, count] : outcomes) summary += fmt::format(" {} {},", outcome, count);
  std::cout << "corpus of " << files.size() << " files:" << summary << "\n";
}

}  // namespace
}  // namespace ecpsim::geometry
