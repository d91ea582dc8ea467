#include "engine/scene_io/parts_cache.h"

#include <fstream>
#include <optional>
#include <sstream>

#include <fmt/format.h>

#include "common/atomic_file.h"
#include "common/errors.h"
#include "common/fnv1a.h"

namespace ecpsim::engine {
namespace {

// the first line of a cache file; a new decomposition (its merging or seam growth changed)
// takes a new version, and so a new fingerprint
constexpr const char* kHeader = "ecpsim convex parts 2";

// the parts' vertex lists in the file at `path`, or nothing where it is missing or not one
std::optional<std::vector<std::vector<Eigen::Vector3d>>> ReadCache(const std::string& path) {
  std::ifstream in(path);
  std::string line;
  if (!in || !std::getline(in, line) || line != kHeader) return std::nullopt;
  std::vector<std::vector<Eigen::Vector3d>> parts;
  while (std::getline(in, line)) {
    std::istringstream words(line);
    std::string word;
    std::size_t count = 0;
    if (!(words >> word >> count) || word != "part" || count < 4) return std::nullopt;
    std::vector<Eigen::Vector3d>& vertices = parts.emplace_back();
    for (std::size_t i = 0; i < count; ++i) {
      Eigen::Vector3d v;
      if (!(in >> v.x() >> v.y() >> v.z()) || !v.allFinite()) return std::nullopt;
      vertices.push_back(v);
    }
    std::getline(in, line);  // the rest of the last vertex's line
  }
  if (parts.empty()) return std::nullopt;
  return parts;
}

std::string CacheText(const std::vector<geometry::ConvexHull>& parts) {
  std::string text = std::string(kHeader) + "\n";
  for (const geometry::ConvexHull& part : parts) {
    text += fmt::format("part {}\n", part.vertices.size());
    for (const Eigen::Vector3d& v : part.vertices)
      text += fmt::format("{} {} {}\n", v.x(), v.y(), v.z());
  }
  return text;
}

}  // namespace

std::string DecompositionCachePath(const std::string& mesh_file, const geometry::TriangleMesh& mesh,
                                   double tolerance) {
  Fnv1a fingerprint;
  fingerprint.Add(kHeader, std::char_traits<char>::length(kHeader));
  fingerprint.Add(&tolerance, sizeof(tolerance));
  for (const Eigen::Vector3d& v : mesh.vertices) fingerprint.Add(v.data(), 3 * sizeof(double));
  for (const Eigen::Vector3i& t : mesh.triangles) fingerprint.Add(t.data(), 3 * sizeof(int));
  return mesh_file + ".parts-" + fingerprint.Hex() + ".txt";
}

std::vector<geometry::ConvexHull> CachedDecomposition(
    const std::string& mesh_file, const geometry::TriangleMesh& mesh, double tolerance,
    const std::function<std::vector<geometry::ConvexHull>()>& decompose,
    std::vector<std::string>& warnings) {
  const std::string path = DecompositionCachePath(mesh_file, mesh, tolerance);
  if (const auto cached = ReadCache(path)) {
    std::vector<geometry::ConvexHull> parts;
    try {
      for (const std::vector<Eigen::Vector3d>& vertices : *cached)
        parts.push_back(geometry::ComputeConvexHull(vertices, path));
      return parts;
    } catch (const InputError&) {
      // not a decomposition this version wrote: computed again below, and rewritten
    }
  }
  std::vector<geometry::ConvexHull> parts = decompose();
  // each part as a load from the cache makes it, from its corners alone (their hull can differ
  // from the decomposition's in its faces' order and round-off), so that a run does not depend on
  // whether the parts were cached
  for (geometry::ConvexHull& part : parts) part = geometry::ComputeConvexHull(part.vertices, path);
  try {
    WriteFileAtomically(path, CacheText(parts));
  } catch (const InputError& e) {
    warnings.push_back(
        fmt::format("{}: its convex parts are not cached ({}); they are computed again at each "
                    "load",
                    mesh_file, e.what()));
  }
  return parts;
}

}  // namespace ecpsim::engine
