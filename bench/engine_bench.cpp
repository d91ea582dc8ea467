// Step-time benchmarks of the MNCP time stepper: the paper's desk and T-bar, and step time
// against hull face count (the window keeps large hulls cheap).

#include <cmath>
#include <vector>

#include <benchmark/benchmark.h>

#include "bench/step_loop.h"
#include "engine/time_step.h"
#include "geometry/convex_hull.h"
#include "geometry/paper_bodies.h"
#include "tests/engine/test_bodies.h"

namespace ecpsim::engine {
namespace {

// the paper's desk: pushed by f_x = 22.5 sin(2πt) + 22.5, f_y = 22.5 cos(2πt) + 22.5,
// τ_z = 2.1 cos(2πt), v0 = (0.3, 0.2, 0), ω_z = 0.5, 4 s at h = 0.01
void BM_DeskStep(benchmark::State& bench) {
  RunSteps(bench, testing::PaperDeskScene(ContactModel::kHull), 400);
}
BENCHMARK(BM_DeskStep)->Unit(benchmark::kMicrosecond);

// the same desk under model: auto (the default): flat on its feet all along, every step is a
// planar step accepted as the hull model's (engine/README.md, "model: auto")
void BM_DeskStepAuto(benchmark::State& bench) {
  RunSteps(bench, testing::PaperDeskScene(ContactModel::kAuto), 400);
}
BENCHMARK(BM_DeskStepAuto)->Unit(benchmark::kMicrosecond);

// the same desk with the point-contact baseline (hull vertices near the ground, d = 8 friction
// directions, one LCP per step by Lemke's method); "newton_iters" counts Lemke pivots here
void BM_PointContactDesk(benchmark::State& bench) {
  RunSteps(bench, testing::PaperDeskScene(ContactModel::kPoint), 400);
}
BENCHMARK(BM_PointContactDesk)->Unit(benchmark::kMicrosecond);

// the T-bar sliding and turning flat under a push
void BM_TBarStep(benchmark::State& bench) {
  Body tbar = testing::MakeMeshBody(geometry::MakeTBarMesh(), 2, "tbar");
  tbar.p0 = Eigen::Vector3d(0, 0, 0.025);
  tbar.v0 = Eigen::Vector3d(0.4, -0.1, 0);
  tbar.w0 = Eigen::Vector3d(0, 0, 1.0);
  Scene scene = testing::MakeGroundScene({tbar});
  scene.model = ContactModel::kHull;  // the hull step, not auto's planar step of a flat T-bar
  Load force;
  force.x = TimeFunction("3*sin(2*pi*t)+3", "bench");
  scene.loads = {force};
  RunSteps(bench, scene, 300);
}
BENCHMARK(BM_TBarStep)->Unit(benchmark::kMicrosecond);

// a convex body with about `faces` hull faces: points on a unit-ish sphere (Fibonacci lattice)
// with a flat bottom cap, sliding and spinning on that cap until it stops
void BM_HullFaces(benchmark::State& bench) {
  const int faces = static_cast<int>(bench.range(0));
  const int points = std::max(8, faces / 2 + 2);  // a triangulated sphere has ≈ 2N − 4 faces
  std::vector<Eigen::Vector3d> cloud;
  const double golden = M_PI * (3 - std::sqrt(5.0));
  for (int i = 0; i < points; ++i) {
    const double z = 1 - 2 * (i + 0.5) / points;
    const double r = std::sqrt(1 - z * z);
    cloud.emplace_back(0.1 * r * std::cos(golden * i), 0.1 * r * std::sin(golden * i),
                       0.1 * std::max(z, -0.8));
  }
  // six faces: a box, the smallest hull there is
  auto hull = faces <= 6 ? geometry::MakeBox(Eigen::Vector3d(0.1, 0.1, 0.08))
                         : std::make_shared<geometry::PolyhedralShape>(
                               geometry::ComputeConvexHull(cloud, "fibonacci sphere"));
  Body body = testing::MakeBoxBody(Eigen::Vector3d(0.2, 0.2, 0.2), 1, "ball");
  // the CM at the cloud's origin is close enough for a benchmark: the cap is at z = −0.08
  body.hull = hull;
  body.mesh = hull->Tessellate();
  body.p0 = Eigen::Vector3d(0, 0, 0.08);
  body.v0 = Eigen::Vector3d(0.5, 0.1, 0);
  body.w0 = Eigen::Vector3d(0, 0, 2);
  Scene scene = testing::MakeGroundScene({body});
  scene.model = ContactModel::kHull;  // the hull window's cost, not auto's planar step
  scene.solver.sleep = false;         // and its steps at rest solved, not replayed
  bench.counters["hull_faces"] = hull->NumConstraints();
  RunSteps(bench, scene, 100);
}
BENCHMARK(BM_HullFaces)
    ->Arg(6)
    ->Arg(20)
    ->Arg(100)
    ->Arg(1000)
    ->Arg(20000)
    ->Unit(benchmark::kMicrosecond);

}  // namespace
}  // namespace ecpsim::engine
