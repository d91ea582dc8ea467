// Load + convex hull + mass properties of generated 10k- and 1M-triangle meshes (binary STL).
//
// Run: build/bench/ecpsim_bench_geometry (medians of 3 repetitions). The meshes are generated
// once per process into a temporary folder, so file reading is part of the Load timings.

#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <map>
#include <string>
#include <system_error>

#include <benchmark/benchmark.h>

#include "geometry/convex_hull.h"
#include "geometry/mass_properties.h"
#include "geometry/mesh_io.h"
#include "geometry/triangle_mesh.h"

namespace ecpsim::geometry {
namespace {

constexpr double kPi = 3.14159265358979323846;

// a UV sphere with `stacks` latitude bands and 2 × stacks longitudes, radius r(θ, φ)
// (θ polar, φ azimuth): 4 stacks² − 4 stacks triangles, closed and outward-wound
template <typename Radius>
TriangleMesh MakeUvSphere(int stacks, Radius radius) {
  const int slices = 2 * stacks;
  TriangleMesh mesh;
  auto point = [&](double theta, double phi) {
    const double r = radius(theta, phi);
    return Eigen::Vector3d(r * std::sin(theta) * std::cos(phi), r * std::sin(theta) * std::sin(phi),
                           r * std::cos(theta));
  };
  mesh.vertices.push_back(point(0.0, 0.0));  // north pole
  for (int i = 1; i < stacks; ++i) {
    for (int j = 0; j < slices; ++j) {
      mesh.vertices.push_back(point(kPi * i / stacks, 2 * kPi * j / slices));
    }
  }
  const int south = static_cast<int>(mesh.vertices.size());
  mesh.vertices.push_back(point(kPi, 0.0));
  auto ring = [&](int i, int j) { return 1 + (i - 1) * slices + (j % slices); };
  for (int j = 0; j < slices; ++j) {
    mesh.triangles.emplace_back(0, ring(1, j), ring(1, j + 1));
    mesh.triangles.emplace_back(south, ring(stacks - 1, j + 1), ring(stacks - 1, j));
  }
  for (int i = 1; i + 1 < stacks; ++i) {
    for (int j = 0; j < slices; ++j) {
      mesh.triangles.emplace_back(ring(i, j), ring(i + 1, j), ring(i + 1, j + 1));
      mesh.triangles.emplace_back(ring(i, j), ring(i + 1, j + 1), ring(i, j + 1));
    }
  }
  return mesh;
}

// the benchmark meshes by name: a round sphere (every vertex on the hull) and a bumpy,
// non-convex sphere (most vertices inside the hull), each at ~10k and ~1M triangles
TriangleMesh MakeNamedMesh(const std::string& name) {
  const int stacks = name.find("1M") != std::string::npos ? 500 : 50;
  if (name.rfind("bumpy", 0) == 0) {
    return MakeUvSphere(stacks, [](double theta, double phi) {
      return 1.0 + 0.15 * std::sin(6 * theta) * std::sin(5 * phi);
    });
  }
  return MakeUvSphere(stacks, [](double, double) { return 1.0; });
}

// a per-process temporary folder, removed at exit
struct TempFolder {
  TempFolder()
      : path(std::filesystem::temp_directory_path() /
             ("ecpsim_bench_geometry_" + std::to_string(::getpid()))) {
    std::filesystem::create_directories(path);
  }
  ~TempFolder() {
    std::error_code ignored;
    std::filesystem::remove_all(path, ignored);
  }
  std::filesystem::path path;
};

// path of the binary STL of `name`, written on first use
const std::string& MeshFile(const std::string& name) {
  static TempFolder folder;
  static std::map<std::string, std::string> files;
  auto it = files.find(name);
  if (it == files.end()) {
    const std::string path = (folder.path / (name + ".stl")).string();
    SaveMesh(MakeNamedMesh(name), path);
    it = files.emplace(name, path).first;
  }
  return it->second;
}

// the loaded (welded) mesh of `name`, loaded once
const TriangleMesh& LoadedMesh(const std::string& name) {
  static std::map<std::string, TriangleMesh> meshes;
  auto it = meshes.find(name);
  if (it == meshes.end()) it = meshes.emplace(name, LoadMesh(MeshFile(name))).first;
  return it->second;
}

void BM_Load(benchmark::State& state, const std::string& name) {
  const std::string& path = MeshFile(name);
  for (auto _ : state) benchmark::DoNotOptimize(LoadMesh(path));
  state.counters["triangles"] = static_cast<double>(LoadedMesh(name).triangles.size());
}

void BM_ConvexHull(benchmark::State& state, const std::string& name) {
  const TriangleMesh& mesh = LoadedMesh(name);
  std::size_t faces = 0;
  for (auto _ : state) {
    const ConvexHull hull = ComputeConvexHull(mesh.vertices, name);
    faces = hull.faces.size();
    benchmark::DoNotOptimize(faces);
  }
  state.counters["hull_faces"] = static_cast<double>(faces);
}

void BM_MassProperties(benchmark::State& state, const std::string& name) {
  const TriangleMesh& mesh = LoadedMesh(name);
  for (auto _ : state) benchmark::DoNotOptimize(ComputeMassProperties(mesh, 1000.0, name));
}

void BM_LoadHullMass(benchmark::State& state, const std::string& name) {
  const std::string& path = MeshFile(name);
  for (auto _ : state) {
    const TriangleMesh mesh = LoadMesh(path);
    benchmark::DoNotOptimize(ComputeConvexHull(mesh.vertices, path));
    benchmark::DoNotOptimize(ComputeMassProperties(mesh, 1000.0, path));
  }
}

#define ECPSIM_GEOMETRY_BENCHMARKS(function)                         \
  BENCHMARK_CAPTURE(function, sphere_10k, std::string("sphere_10k")) \
      ->Unit(benchmark::kMillisecond)                                \
      ->Repetitions(3)                                               \
      ->ReportAggregatesOnly(true);                                  \
  BENCHMARK_CAPTURE(function, bumpy_10k, std::string("bumpy_10k"))   \
      ->Unit(benchmark::kMillisecond)                                \
      ->Repetitions(3)                                               \
      ->ReportAggregatesOnly(true);                                  \
  BENCHMARK_CAPTURE(function, sphere_1M, std::string("sphere_1M"))   \
      ->Unit(benchmark::kMillisecond)                                \
      ->Repetitions(3)                                               \
      ->ReportAggregatesOnly(true);                                  \
  BENCHMARK_CAPTURE(function, bumpy_1M, std::string("bumpy_1M"))     \
      ->Unit(benchmark::kMillisecond)                                \
      ->Repetitions(3)                                               \
      ->ReportAggregatesOnly(true)

ECPSIM_GEOMETRY_BENCHMARKS(BM_Load);
ECPSIM_GEOMETRY_BENCHMARKS(BM_ConvexHull);
ECPSIM_GEOMETRY_BENCHMARKS(BM_MassProperties);
ECPSIM_GEOMETRY_BENCHMARKS(BM_LoadHullMass);

}  // namespace
}  // namespace ecpsim::geometry
