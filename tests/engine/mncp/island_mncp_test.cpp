#include "engine/mncp/island_mncp.h"

#include <algorithm>
#include <cfloat>
#include <cmath>
#include <numeric>
#include <random>

#include <gtest/gtest.h>

#include "engine/mncp/island_scaling.h"
#include "engine/mncp/mncp_scaling.h"
#include "engine/rotation.h"
#include "engine/scene_io/scene_builders.h"
#include "geometry/convex_hull.h"
#include "geometry/convex_shape.h"
#include "geometry/paper_bodies.h"
#include "tests/engine/island_test_problems.h"
#include "tests/engine/jacobian_check.h"

namespace ecpsim::engine {
namespace {

using Eigen::Matrix3d;
using Eigen::Quaterniond;
using Eigen::Vector3d;
using Eigen::VectorXd;
using Other = IslandContact::Other;

using testing::kJacobianTolerance;  // a missing or wrong term is O(h) ≈ 1e-2 of its entry or more
// dimensionless, the island measure at a solution built by hand: every scaled row is a handful of
// operations on O(1) quantities, so its round-off is a few ulps; 64 ulps leave margin for the
// products of rotations in the end poses
constexpr double kExactSolutionMeasure = 64 * DBL_EPSILON;
// the same for the contact parts of Newton–Euler rows compared across bodies (N·s, N·m·s),
// relative to the step's impulse and moment magnitudes
constexpr double kRoundOffRelative = 64 * DBL_EPSILON;

constexpr double kG = 9.8;  // m/s², the scenes' gravity (scene.h)
// the scenes' solver tolerance (SolverSettings), on the island measure
constexpr double kSolverTolerance = 1e-12;
// dimensionless: an island measure 10⁹ × the solver tolerance marks a z that is no solution;
// the wrong unknowns below miss O(1) of a row's scale
constexpr double kNoSolutionMeasure = 1e-3;

// --- the one-body island is today's MNCP to the bit ---

std::shared_ptr<const geometry::ConvexShape> MeshHull() {
  const Body desk = MakeMeshBody(geometry::MakeDeskMesh(), 15, "desk");
  return desk.hull;
}

struct Shapes {
  std::shared_ptr<const geometry::ConvexShape> box = geometry::MakeBox(Vector3d(0.2, 0.15, 0.1));
  std::shared_ptr<const geometry::ConvexShape> cylinder = geometry::MakeCylinder(0.1, 0.3, 0);
  std::shared_ptr<const geometry::ConvexShape> mesh = MeshHull();
  std::shared_ptr<const geometry::ConvexShape> ground =
      geometry::MakeHalfSpace(Vector3d::UnitZ(), 0);
  std::shared_ptr<const geometry::ConvexShape> tilted =
      geometry::MakeHalfSpace(Vector3d(0.2, -0.1, 1.0), 0.05);
  std::shared_ptr<const geometry::ConvexShape> fixture = geometry::MakeBox(Vector3d(0.5, 0.4, 0.3));
  std::shared_ptr<const geometry::ConvexShape> sphere = geometry::MakeSphere(1.0);
};

// the first index where two vectors or matrices differ in any bit (−1: none)
template <typename A>
int FirstDifference(const A& x, const A& y) {
  if (x.size() != y.size()) return 0;
  for (int i = 0; i < x.size(); ++i)
    if (!(x.data()[i] == y.data()[i])) return i;
  return -1;
}

// The island of one body against fixed obstacles is EvaluateMncp's MNCP: to the bit where no
// obstacle is a plane; a contact on a plane (a half-space) is the general form with a2, s and l_G
// eliminated (MncpLayout): at a z whose a2, s and l_G are a1's projection, gap and 1, every row
// the plane form keeps is the general form's to the bit (its cone rows are a2's there), and so is
// its Jacobian in the unknowns it keeps, but for the gap row, which depends on a1 through s
TEST(IslandReductionTest, OneBodyWithFixedContactsIsTodaysMncpWithPlanesEliminated) {
  const Shapes shapes;
  const std::vector<const geometry::ConvexShape*> hulls = {shapes.box.get(), shapes.cylinder.get(),
                                                           shapes.mesh.get()};
  const std::vector<std::vector<const geometry::ConvexShape*>> obstacle_sets = {
      {shapes.ground.get()},
      {shapes.ground.get(), shapes.fixture.get()},
      {shapes.fixture.get()},
      {shapes.tilted.get(), shapes.sphere.get()}};
  std::mt19937 rng(2024);
  int compared = 0, planes = 0;
  for (const geometry::ConvexShape* hull : hulls) {
    for (const auto& obstacles : obstacle_sets) {
      for (int trial = 0; trial < 16; ++trial) {
        const bool far = trial % 4 == 3;
        testing::RandomBodyCase c = testing::MakeRandomBodyCase(*hull, obstacles, far, rng);
        const IslandProblem island = testing::OneBodyIsland(c.problem);
        SCOPED_TRACE(::testing::Message() << "hull " << hull->NumConstraints() << " constraints, "
                                          << obstacles.size() << " obstacles, trial " << trial);

        const IslandLayout layout = MakeIslandLayout(island);
        ASSERT_EQ(layout.contacts.size(), c.layout.contacts.size());
        // the island's unknowns and rows in the body layout: unknown j is the body's
        // column[j], row i the body's row[i] (the cone rows a2's where the island's are a1's)
        std::vector<int> column(6), row(6);
        std::iota(column.begin(), column.end(), 0);
        std::iota(row.begin(), row.end(), 0);
        column.resize(layout.size, -1);
        row.resize(layout.size, -1);
        bool any_plane = false;
        for (size_t k = 0; k < layout.contacts.size(); ++k) {
          const MncpLayout::Contact& a = layout.contacts[k];
          const MncpLayout::Contact& b = c.layout.contacts[k];
          const bool plane = obstacles[k]->IsHalfSpace();
          ASSERT_EQ(a.on_plane(), plane);
          ASSERT_EQ(a.l_count, b.l_count);
          ASSERT_EQ(a.l_g_count, plane ? 0 : b.l_g_count);
          for (int i = 0; i < 3; ++i) {
            column[a.a1 + i] = b.a1 + i;
            row[a.a1 + i] = plane ? b.a2 + i : b.a1 + i;
            if (plane) continue;
            column[a.a2 + i] = row[a.a2 + i] = b.a2 + i;
          }
          if (!plane) column[a.s] = row[a.s] = b.s;
          for (int j = 0; j < a.l_g_count; ++j) column[a.l_g + j] = row[a.l_g + j] = b.l_g + j;
          for (int i = 0; i < a.l_count; ++i) column[a.l + i] = row[a.l + i] = b.l + i;
          for (auto [x, y] :
               {std::pair{a.p_t, b.p_t}, std::pair{a.p_o, b.p_o}, std::pair{a.p_r, b.p_r},
                std::pair{a.p_n, b.p_n}, std::pair{a.sigma, b.sigma}})
            column[x] = row[x] = y;
          if (!plane) continue;
          any_plane = true;
          // the body's a2, s and l_G where the plane form has them
          const auto [a2, gap] = ContactGapAt(a, obstacles[k], VectorXd(c.z(column)));
          c.z.segment<3>(b.a2) = a2;
          c.z[b.s] = gap;
          c.z[b.l_g] = 1;
        }
        ASSERT_EQ(std::count(column.begin(), column.end(), -1), 0);
        ASSERT_EQ(layout.num_free, std::count_if(column.begin(), column.end(),
                                                 [&](int j) { return j < c.layout.num_free; }));
        if (!any_plane) {
          ASSERT_EQ(layout.size, c.layout.size);
        }
        const VectorXd z = c.z(column);

        VectorXd F_body, F_island, F_only;
        Eigen::MatrixXd J_body, J_island;
        EvaluateMncp(c.problem, c.layout, c.z, &F_body, &J_body);
        EvaluateIslandMncp(island, layout, z, &F_island, &J_island);
        EvaluateIslandMncp(island, layout, z, &F_only, nullptr);
        ASSERT_TRUE(F_body.allFinite() && J_body.allFinite());
        const VectorXd F_mapped = F_body(row);
        Eigen::MatrixXd J_mapped = J_body(row, column);
        for (size_t k = 0; k < layout.contacts.size(); ++k) {
          const MncpLayout::Contact& a = layout.contacts[k];
          if (!a.on_plane()) continue;
          // the gap row: s = g(a1)/|N|², whose gradient in a1 is N/|N|²
          const Vector3d N = obstacles[k]->Gradient(0, z.segment<3>(a.a1));
          J_mapped.block<1, 3>(a.p_n, a.a1) = N.transpose() / N.squaredNorm();
        }
        EXPECT_EQ(FirstDifference(F_island, F_mapped), -1);
        EXPECT_EQ(FirstDifference(F_only, F_mapped), -1);
        EXPECT_EQ(FirstDifference(J_island, J_mapped), -1);
        // and so is the Jacobian added into a zero matrix the caller keeps (the hull model's
        // solves, complementarity_solver.h)
        Eigen::MatrixXd J_kept = Eigen::MatrixXd::Zero(layout.size, layout.size);
        EvaluateIslandMncp(island, layout, z, &F_only, &J_kept, /*jacobian_is_zero=*/true);
        EXPECT_EQ(FirstDifference(J_kept, J_mapped), -1);

        const IslandScales scales{{c.scales}};
        const VectorXd row_scale = RowScales(c.problem, c.layout, c.scales);
        const VectorXd var_scale = VariableScales(c.problem, c.layout, c.scales);
        const VectorXd island_row_scale = IslandRowScales(island, layout, scales);
        const VectorXd island_var_scale = IslandVariableScales(island, layout, scales);
        EXPECT_EQ(FirstDifference(island_row_scale, VectorXd(row_scale(row))), -1);
        EXPECT_EQ(FirstDifference(island_var_scale, VectorXd(var_scale(column))), -1);
        const double measure =
            MncpResidual(c.layout, c.z, F_body, row_scale, var_scale,
                         {c.scales.length, kSolverTolerance, c.problem.c.cwiseAbs().maxCoeff()});
        const double island_measure =
            IslandMncpResidual(island, layout, z, F_island, island_row_scale, island_var_scale,
                               MakeIslandResidualUnits(island, scales, kSolverTolerance));
        if (any_plane) {
          // the rows eliminated hold at this z, but only to round-off, and a2, s no longer
          // enter the round-off length: the same measure to a few ulps, or less
          constexpr double kFewUlpsRel = 1e-14;
          EXPECT_LE(island_measure, measure * (1 + kFewUlpsRel));
        } else {
          EXPECT_EQ(island_measure, measure);
        }
        EXPECT_EQ(IslandStepEnergyGain(island, layout, z),
                  StepEnergyGain(c.problem, c.z.head<3>(), c.z.segment<3>(3)));
        EXPECT_EQ(IslandEnergyScale(island, scales), EnergyScale(c.problem, c.scales));
        ++compared;
        planes += any_plane;
      }
    }
  }
  EXPECT_EQ(compared, 3 * 4 * 16);
  EXPECT_EQ(planes, 3 * 3 * 16);
}

// --- islands of two or more moving bodies ---

// a solid cylinder body of `radius` and `length` along `axis`
Body MakeCylinderBody(double radius, double length, int axis, double mass) {
  Body body;
  body.name = "cylinder";
  body.hull = geometry::MakeCylinder(radius, length, axis);
  body.mass = mass;
  const double across = mass * (3 * radius * radius + length * length) / 12;
  Vector3d inertia = Vector3d::Constant(across);
  inertia[axis] = mass * radius * radius / 2;
  body.inertia = inertia.asDiagonal();
  return body;
}

// The bodies of an island and the ground z ≤ 0, for StartOfStep: not a scene that runs, so no
// builder (and no ValidateScene) makes it — the bodies' poses are the test's states, not their
// initial ones, primitives have no display mesh, and names may repeat
Scene IslandBodiesOnTheGround(std::vector<Body> bodies, double h) {
  Scene scene;
  scene.source = "island test";
  scene.h = h;
  scene.bodies = std::move(bodies);
  scene.obstacles.push_back({"ground", geometry::MakeHalfSpace(Vector3d::UnitZ(), 0), Friction{}});
  return scene;
}

// An island built from scene bodies at given states (StartOfStep: gravity, world inertia, the
// free flight), contacts added by the test
struct IslandCase {
  Scene scene;
  std::vector<BodyState> states;
  IslandProblem problem;
  IslandLayout layout;
  VectorXd z;

  IslandCase(std::vector<Body> bodies, std::vector<BodyState> body_states, double h = 0.01)
      : scene(IslandBodiesOnTheGround(std::move(bodies), h)), states(std::move(body_states)) {
    problem.h = h;
    for (size_t b = 0; b < states.size(); ++b)
      problem.bodies.push_back(StartOfStep(scene, static_cast<int>(b), states[b], 0, h));
  }

  const geometry::ConvexShape* hull(int b) const { return scene.bodies[b].hull.get(); }

  // a contact of body `body` with G, windows of all constraints on both sides
  IslandContact& Add(int body, Other kind, int other, const geometry::ConvexShape* other_shape,
                     Friction friction = Friction{0.3, 1.0, 0.8, 0.1}) {
    IslandContact cp;
    cp.body = body;
    cp.other_kind = kind;
    cp.other = other;
    cp.hull = hull(body);
    for (int i = 0; i < cp.hull->NumConstraints(); ++i) cp.window.push_back(i);
    cp.other_shape = other_shape;
    for (int j = 0; j < other_shape->NumConstraints(); ++j) cp.other_window.push_back(j);
    cp.friction = friction;
    problem.contacts.push_back(cp);
    return problem.contacts.back();
  }

  void Layout() {
    layout = MakeIslandLayout(problem);
    z = VectorXd::Zero(layout.size);
  }

  // random unknowns of plausible size around the states: ν⁺ near ν, each contact's a1, a2 near
  // `near[k]`, impulses ~ m g h, positive multipliers (the Jacobian identity holds at any z)
  void Randomize(const std::vector<Vector3d>& near, unsigned seed) {
    Layout();
    std::mt19937 rng(seed);
    std::uniform_real_distribution<double> u(-1, 1);
    const auto vector = [&](double scale) -> Vector3d {
      return Vector3d(u(rng), u(rng), u(rng)) * scale;
    };
    for (size_t b = 0; b < states.size(); ++b) {
      z.segment<3>(IslandLayout::Velocity(b)) = states[b].v_WB + vector(0.3);
      z.segment<3>(IslandLayout::Velocity(b) + 3) = states[b].w_WB + vector(0.3);
    }
    for (size_t k = 0; k < layout.contacts.size(); ++k) {
      const MncpLayout::Contact& L = layout.contacts[k];
      const double impulse = scene.bodies[problem.contacts[k].body].mass * kG * problem.h;
      testing::RandomizeContact(L, near[k], impulse, rng, z);
    }
  }

  double JacobianError() const {
    return testing::JacobianError(
        [this](const VectorXd& zz, VectorXd* F, Eigen::MatrixXd* J) {
          EvaluateIslandMncp(problem, layout, zz, F, J);
        },
        z);
  }
};

BodyState MovingState(const Vector3d& p, const Quaterniond& Q, const Vector3d& v,
                      const Vector3d& w) {
  BodyState s;
  s.p_WB = p;
  s.Q_WB = Q;
  s.v_WB = v;
  s.w_WB = w;
  return s;
}

Quaterniond Rotation(double angle, const Vector3d& axis) {
  return Quaterniond(Eigen::AngleAxisd(angle, axis.normalized()));
}

// F (a small box) above G (a larger box resting on the ground), both moving and rotating, F
// turned by `Q_top` (face, edge or vertex down); three contacts: G–ground, F–G, and F–ground
// (far away: only its Jacobian matters)
IslandCase BoxOnMovingBox(const Quaterniond& Q_top, double top_height, unsigned seed) {
  IslandCase c({MakeBoxBody(Vector3d(0.6, 0.6, 0.2), 3, "slab"),
                MakeBoxBody(Vector3d(0.3, 0.2, 0.1), 1, "top")},
               {MovingState(Vector3d(0.1, 0, 0.1), Rotation(0.1, Vector3d(1, 2, 10)),
                            Vector3d(0.2, -0.1, 0.05), Vector3d(0.3, -0.5, 1.0)),
                MovingState(Vector3d(0.15, 0.05, 0.2 + top_height), Q_top,
                            Vector3d(-0.3, 0.2, -0.1), Vector3d(1.5, -1.0, 2.0))});
  const auto ground = c.scene.obstacles[0].shape.get();
  c.Add(0, Other::kFixed, -1, ground);
  c.Add(1, Other::kBody, 0, c.hull(0)).tangent_reference = Vector3d::UnitY();
  c.Add(1, Other::kFixed, -1, ground);
  c.Randomize({Vector3d(0.1, 0, 0), Vector3d(0.15, 0.05, 0.2), Vector3d(0.15, 0.05, 0)}, seed);
  return c;
}

// --- the sparse assembly equals the dense one ---

// the largest difference of EvaluateIslandMncpSparse's F and J from EvaluateIslandMncp's, per
// entry relative to max(1, |entry|); and whether the sparse pattern holds the whole diagonal
struct SparseDifference {
  double F = 0, J = 0;
  bool full_diagonal = true;
};

SparseDifference SparseAgainstDense(const IslandCase& c) {
  VectorXd F_dense, F_sparse;
  Eigen::MatrixXd J_dense;
  Eigen::SparseMatrix<double> J_sparse;
  EvaluateIslandMncp(c.problem, c.layout, c.z, &F_dense, &J_dense);
  EvaluateIslandMncpSparse(c.problem, c.layout, c.z, &F_sparse, &J_sparse);
  SparseDifference d;
  const auto relative = [](double a, double b) {
    return std::abs(a - b) / std::max(1.0, std::abs(a));
  };
  for (int i = 0; i < c.layout.size; ++i) {
    d.F = std::max(d.F, relative(F_dense[i], F_sparse[i]));
    for (int j = 0; j < c.layout.size; ++j)
      d.J = std::max(d.J, relative(J_dense(i, j), J_sparse.coeff(i, j)));
    bool has_diagonal = false;
    for (Eigen::SparseMatrix<double>::InnerIterator it(J_sparse, i); it; ++it)
      has_diagonal |= it.row() == i;
    d.full_diagonal &= has_diagonal;
  }
  return d;
}

TEST(IslandJacobianTest, FaceOnMovingBox) {
  EXPECT_LT(BoxOnMovingBox(Rotation(0.3, Vector3d::UnitZ()), 0.05, 1).JacobianError(),
            kJacobianTolerance);
}

TEST(IslandJacobianTest, EdgeOnMovingBox) {
  EXPECT_LT(BoxOnMovingBox(Rotation(M_PI / 4, Vector3d::UnitX()), 0.08, 2).JacobianError(),
            kJacobianTolerance);
}

TEST(IslandJacobianTest, VertexOnMovingBox) {
  EXPECT_LT(BoxOnMovingBox(Rotation(0.9, Vector3d(1, 2, 3)), 0.15, 3).JacobianError(),
            kJacobianTolerance);
}

TEST(IslandJacobianTest, BoxOnMovingCylinder) {
  // G smooth: a log rolling on the ground, a box on it
  IslandCase c({MakeCylinderBody(0.1, 0.5, 0, 4), MakeBoxBody(Vector3d(0.2, 0.2, 0.1), 1)},
               {MovingState(Vector3d(0, 0, 0.1), Rotation(0.4, Vector3d::UnitX()),
                            Vector3d(0, 0.3, 0), Vector3d(-3, 0.2, 0.5)),
                MovingState(Vector3d(0.05, 0.02, 0.25), Rotation(0.2, Vector3d(1, 1, 0)),
                            Vector3d(0.1, 0.2, -0.3), Vector3d(0.5, 1.0, -1.5))});
  c.Add(0, Other::kFixed, -1, c.scene.obstacles[0].shape.get());
  c.Add(1, Other::kBody, 0, c.hull(0));
  c.Randomize({Vector3d(0, 0, 0), Vector3d(0.05, 0.02, 0.2)}, 4);
  EXPECT_LT(c.JacobianError(), kJacobianTolerance);
}

TEST(IslandJacobianTest, CylinderOnMovingBoxAndCrossedCylinders) {
  // F smooth on a box, and smooth on smooth (two crossed logs)
  IslandCase c({MakeBoxBody(Vector3d(0.6, 0.6, 0.2), 3), MakeCylinderBody(0.1, 0.4, 1, 2),
                MakeCylinderBody(0.08, 0.5, 0, 1)},
               {MovingState(Vector3d(0, 0, 0.1), Rotation(0.1, Vector3d::UnitZ()),
                            Vector3d(0.1, 0, 0), Vector3d(0.1, 0.2, 0.7)),
                MovingState(Vector3d(0, 0, 0.3), Rotation(0.2, Vector3d(1, 0, 1)),
                            Vector3d(0, 0.2, 0.1), Vector3d(2, -1, 0.5)),
                MovingState(Vector3d(0.02, 0.01, 0.48), Rotation(0.3, Vector3d(0, 1, 1)),
                            Vector3d(-0.1, 0.1, -0.2), Vector3d(-1, 2, 1))});
  c.Add(1, Other::kBody, 0, c.hull(0));
  c.Add(2, Other::kBody, 1, c.hull(1)).tangent_reference = Vector3d::UnitZ();
  c.Randomize({Vector3d(0, 0, 0.2), Vector3d(0.01, 0, 0.4)}, 5);
  EXPECT_LT(c.JacobianError(), kJacobianTolerance);
}

TEST(IslandJacobianTest, KinematicTurntableAndSphere) {
  // G kinematic: a box on a turning, rising platform; a cylinder on a moving sphere
  IslandCase c({MakeBoxBody(Vector3d(0.3, 0.2, 0.1), 1), MakeCylinderBody(0.1, 0.3, 2, 2)},
               {MovingState(Vector3d(0.2, 0.1, 0.25), Rotation(0.5, Vector3d(1, 2, 3)),
                            Vector3d(0.3, 0.1, 0), Vector3d(0.5, -0.5, 2)),
                MovingState(Vector3d(2, 0, 1.2), Rotation(0.7, Vector3d(1, 0, 0)),
                            Vector3d(0, 0.1, -0.3), Vector3d(1, 1, -1))});
  const auto platform = geometry::MakeBox(Vector3d(1, 1, 0.1));
  const auto ball = geometry::MakeSphere(1);
  c.problem.kinematic = {{Vector3d(0, 0, 0.1), Rotation(0.3, Vector3d::UnitZ()).toRotationMatrix(),
                          Vector3d(0.1, -0.2, 0.05), Vector3d(0.1, -0.2, 1.5)},
                         {Vector3d(2, 0, 0), Rotation(0.4, Vector3d(1, 1, 1)).toRotationMatrix(),
                          Vector3d(-0.2, 0, 0.1), Vector3d(0.5, 2, -1)}};
  c.Add(0, Other::kKinematic, 0, platform.get());
  c.Add(1, Other::kKinematic, 1, ball.get());
  c.Randomize({Vector3d(0.2, 0.1, 0.2), Vector3d(2, 0, 1.05)}, 6);
  EXPECT_LT(c.JacobianError(), kJacobianTolerance);
}

TEST(IslandJacobianTest, StackOfThreeOnAConveyorWithAWall) {
  // every kind of G in one island: the ground, a fixture, a kinematic belt and two body pairs
  IslandCase c({MakeBoxBody(Vector3d(0.5, 0.5, 0.2), 3), MakeBoxBody(Vector3d(0.4, 0.3, 0.2), 2),
                MakeCylinderBody(0.05, 0.3, 0, 1)},
               {MovingState(Vector3d(0, 0, 0.2), Rotation(0.1, Vector3d(0, 0, 1)),
                            Vector3d(0.5, 0, 0), Vector3d(0.1, 0.1, 0.3)),
                MovingState(Vector3d(0.05, 0, 0.4), Rotation(0.2, Vector3d(1, 1, 3)),
                            Vector3d(0.4, 0.1, 0), Vector3d(-0.3, 0.2, 0.8)),
                MovingState(Vector3d(0.1, 0.05, 0.55), Rotation(0.3, Vector3d(0, 0, 1)),
                            Vector3d(0.3, -0.2, 0.1), Vector3d(3, 0.5, -0.5))});
  const auto belt = geometry::MakeBox(Vector3d(2, 0.5, 0.05));
  const auto wall = geometry::MakeBox(Vector3d(0.1, 1, 1));
  c.problem.kinematic = {
      {Vector3d(0, 0, 0.05), Matrix3d::Identity(), Vector3d(0.5, 0, 0), Vector3d::Zero()}};
  c.Add(0, Other::kKinematic, 0, belt.get());
  c.Add(1, Other::kBody, 0, c.hull(0));
  c.Add(2, Other::kBody, 1, c.hull(1));
  c.Add(2, Other::kBody, 0, c.hull(0));
  c.Add(1, Other::kFixed, -1, wall.get());
  c.Randomize({Vector3d(0, 0, 0.1), Vector3d(0.05, 0, 0.3), Vector3d(0.1, 0.05, 0.5),
               Vector3d(0.1, 0.05, 0.3), Vector3d(0.3, 0, 0.4)},
              7);
  EXPECT_LT(c.JacobianError(),
            kJacobianTolerance);  // the sparse assembly too (IslandSparseJacobianTest)
  const SparseDifference d = SparseAgainstDense(c);
  EXPECT_LE(d.F, kRoundOffRelative);
  EXPECT_LE(d.J, kRoundOffRelative);
  EXPECT_TRUE(d.full_diagonal);
}

TEST(IslandJacobianTest, AGrippersJawsHoldingABoxOnTheGround) {
  // a box between two jaws of different masses, the jaws touching each other's far side too;
  // the gripper's rows replace the jaws' Newton–Euler rows (island_gripper.h), with targets
  // and an axis off every coordinate axis so that no product of the row map vanishes
  // (masses of a few kg: the random impulses scale with m g h, and far below the central
  // differences' 1e-6 step the friction cone's curvature shows in them)
  IslandCase c({MakeBoxBody(Vector3d(0.05, 0.05, 0.08), 2, "box"),
                MakeBoxBody(Vector3d(0.01, 0.04, 0.03), 0.5, "jaw0"),
                MakeBoxBody(Vector3d(0.01, 0.04, 0.03), 0.8, "jaw1")},
               {MovingState(Vector3d(0, 0, 0.04), Rotation(0.1, Vector3d(0, 0, 1)),
                            Vector3d(0.1, 0.05, 0), Vector3d(0.1, -0.2, 0.3)),
                MovingState(Vector3d(-0.03, 0, 0.04), Rotation(0.12, Vector3d(0, 0, 1)),
                            Vector3d(0.2, 0.1, 0), Vector3d(0, 0, 0.4)),
                MovingState(Vector3d(0.03, 0, 0.04), Rotation(0.12, Vector3d(0, 0, 1)),
                            Vector3d(-0.1, 0.1, 0), Vector3d(0, 0, 0.4))});
  c.Add(0, Other::kFixed, -1, c.scene.obstacles[0].shape.get());
  c.Add(0, Other::kBody, 1, c.hull(1));
  c.Add(0, Other::kBody, 2, c.hull(2)).tangent_reference = Vector3d::UnitY();
  c.Add(1, Other::kBody, 2, c.hull(2));
  IslandGripper g;
  g.jaws = {1, 2};
  g.axis = Vector3d(0.9, 0.3, 0.1).normalized();
  g.v = {Vector3d(0.1, 0.12, -0.01), Vector3d(0.09, 0.13, 0.02)};
  g.w = {Vector3d(0.01, -0.02, 0.5), Vector3d(-0.01, 0.02, 0.45)};
  g.centre_speed = 0.11;
  g.grip = 0.05;
  c.problem.grippers = {g};
  SetGripperFreeFlight(g, c.problem.bodies);
  c.Randomize({Vector3d(0, 0, 0), Vector3d(-0.025, 0, 0.04), Vector3d(0.025, 0, 0.04),
               Vector3d(0, 0, 0.04)},
              11);
  EXPECT_LT(c.JacobianError(), kJacobianTolerance);
  const SparseDifference d = SparseAgainstDense(c);
  EXPECT_LE(d.F, kRoundOffRelative);
  EXPECT_LE(d.J, kRoundOffRelative);
  EXPECT_TRUE(d.full_diagonal);
}

TEST(IslandSparseJacobianTest, EqualsTheDenseOneToRoundOff) {
  // every kind of G (fixed, kinematic, a body as F and as G) and face, edge and vertex contact:
  // the same rows, only the Newton–Euler rows' sums over contacts in another order
  std::vector<IslandCase> cases;
  cases.push_back(BoxOnMovingBox(Rotation(0.3, Vector3d::UnitZ()), 0.05, 1));
  cases.push_back(BoxOnMovingBox(Rotation(M_PI / 4, Vector3d::UnitX()), 0.08, 2));
  cases.push_back(BoxOnMovingBox(Rotation(0.9, Vector3d(1, 2, 3)), 0.15, 3));
  for (const IslandCase& c : cases) {
    const SparseDifference d = SparseAgainstDense(c);
    EXPECT_LE(d.F, kRoundOffRelative);
    EXPECT_LE(d.J, kRoundOffRelative);
    EXPECT_TRUE(d.full_diagonal);
  }
}

// --- Newton's third law and the contact's power ---

// the contact parts of the Newton–Euler rows: F(z) − F(z with the impulses of every contact 0)
// (the rows are linear in the impulses), as the wrench each body receives, −ΔF
std::vector<Eigen::Matrix<double, 6, 1>> ContactWrenches(const IslandCase& c) {
  VectorXd F, F_free;
  VectorXd z_free = c.z;
  for (const MncpLayout::Contact& L : c.layout.contacts)
    for (int i : {L.p_n, L.p_t, L.p_o, L.p_r}) z_free[i] = 0;
  EvaluateIslandMncp(c.problem, c.layout, c.z, &F, nullptr);
  EvaluateIslandMncp(c.problem, c.layout, z_free, &F_free, nullptr);
  std::vector<Eigen::Matrix<double, 6, 1>> wrenches;
  for (int b = 0; b < c.layout.num_bodies; ++b) {
    const int col = IslandLayout::Velocity(b);
    wrenches.push_back(-(F.segment<6>(col) - F_free.segment<6>(col)));
  }
  return wrenches;
}

TEST(IslandContactWrenchTest, NewtonsThirdLawAndThePowerOfAContactBetweenBodies) {
  for (unsigned seed = 10; seed < 20; ++seed) {
    IslandCase c = BoxOnMovingBox(Rotation(0.3 + 0.1 * seed, Vector3d(1, seed, 3)), 0.1, seed);
    c.problem.contacts.resize(2);  // G–ground and F–G
    c.problem.contacts.erase(c.problem.contacts.begin());
    c.Randomize({Vector3d(0.15, 0.05, 0.2)}, seed);
    const MncpLayout::Contact& L = c.layout.contacts[0];
    c.z.segment<3>(L.a2) = c.z.segment<3>(L.a1);  // touching: the solutions' case
    const std::vector<Eigen::Matrix<double, 6, 1>> wrench = ContactWrenches(c);

    // the end poses, the contact frame and the relative velocity at the ECP, from z
    std::vector<EndPose> end;
    for (int b = 0; b < 2; ++b) {
      const int col = IslandLayout::Velocity(b);
      end.push_back(
          PoseAfterStep(c.problem.bodies[b], c.z.segment<3>(col), c.z.segment<3>(col + 3)));
    }
    const IslandContact& cp = c.problem.contacts[0];
    const Vector3d a1 = c.z.segment<3>(L.a1), a2 = c.z.segment<3>(L.a2);
    Vector3d N = Vector3d::Zero();
    const Vector3d y_G = end[0].R.transpose() * (a2 - end[0].c);
    for (int j = 0; j < L.l_g_count; ++j)
      N += c.z[L.l_g + j] * end[0].R * cp.other_shape->Gradient(j, y_G);
    const ContactFrame frame = MakeContactFrame(N, cp.tangent_reference);
    const Vector3d force = frame.n * c.z[L.p_n] + frame.t * c.z[L.p_t] + frame.o * c.z[L.p_o];
    const Vector3d v_F = c.z.segment<3>(6), w_F = c.z.segment<3>(9);
    const Vector3d v_G = c.z.segment<3>(0), w_G = c.z.segment<3>(3);
    const Vector3d v_c = (v_F + w_F.cross(a1 - end[1].c)) - (v_G + w_G.cross(a2 - end[0].c));
    const double power_expected = force.dot(v_c) + c.z[L.p_r] * frame.n.dot(w_F - w_G);

    const double impulse = force.norm() + std::abs(c.z[L.p_r]);
    const double moment = impulse * (1 + a1.norm());
    // linear momentum: what F receives, G gives
    EXPECT_LT((wrench[0].head<3>() + wrench[1].head<3>()).norm(), kRoundOffRelative * impulse);
    EXPECT_LT((wrench[1].head<3>() - force).norm(), kRoundOffRelative * impulse);
    // angular momentum about the origin: c⁺ × f + τ summed over both bodies
    Vector3d angular = Vector3d::Zero();
    for (int b = 0; b < 2; ++b)
      angular += end[b].c.cross(wrench[b].head<3>()) + wrench[b].tail<3>();
    EXPECT_LT(angular.norm(), kRoundOffRelative * moment);
    // the power of the two wrenches at ν⁺ is the friction rows' force · v_c + p_r v_r
    double power = 0;
    for (int b = 0; b < 2; ++b) power += wrench[b].dot(c.z.segment<6>(IslandLayout::Velocity(b)));
    EXPECT_NEAR(power, power_expected, kRoundOffRelative * moment * (v_c.norm() + w_F.norm() + 1));
  }
}

// --- exact solutions built by hand ---

// the index of `shape`'s linear constraint with outward normal `normal` (body frame)
int FaceWithNormal(const geometry::ConvexShape& shape, const Vector3d& normal) {
  constexpr double kSameNormal = 1e-12;  // a box face's unit normal is exact up to round-off
  for (int i = 0; i < shape.NumConstraints(); ++i)
    if ((shape.Gradient(i, Vector3d::Zero()) - normal).norm() < kSameNormal) return i;
  ADD_FAILURE() << "no face with normal " << normal.transpose();
  return 0;
}

// sets contact k's unknowns: ECP, touching (s = 0), F's face `face` and G's constraint `g_face`
// carrying the normal cone (multiplier 1), the impulses and σ
void SetContact(IslandCase& c, int k, const Vector3d& ecp, int face, int g_face, double p_n,
                double p_t, double p_o, double p_r, double sigma) {
  const MncpLayout::Contact& L = c.layout.contacts[k];
  c.z.segment<3>(L.a1) = ecp;
  c.z.segment(L.l, L.l_count).setZero();
  c.z[L.l + face] = 1;
  if (!L.on_plane()) {  // (on a plane a2 = a1, s = 0 and l_G = 1 are no unknowns)
    c.z.segment<3>(L.a2) = ecp;
    c.z[L.s] = 0;
    c.z.segment(L.l_g, L.l_g_count).setZero();
    c.z[L.l_g + g_face] = 1;
  }
  c.z[L.p_n] = p_n;
  c.z[L.p_t] = p_t;
  c.z[L.p_o] = p_o;
  c.z[L.p_r] = p_r;
  c.z[L.sigma] = sigma;
}

// The island measure of `c` at its z, each body in its BodyScales
double Measure(const IslandCase& c, const VectorXd& F) {
  IslandScales scales;
  for (size_t b = 0; b < c.states.size(); ++b) {
    scales.bodies.push_back(
        BodyScales(c.scene.bodies[b], c.states[b], c.problem.bodies[b].p_ext, c.problem.h));
  }
  return IslandMncpResidual(c.problem, c.layout, c.z, F,
                            IslandRowScales(c.problem, c.layout, scales),
                            IslandVariableScales(c.problem, c.layout, scales),
                            MakeIslandResidualUnits(c.problem, scales, kSolverTolerance));
}

double Measure(const IslandCase& c) {
  VectorXd F;
  EvaluateIslandMncp(c.problem, c.layout, c.z, &F, nullptr);
  return Measure(c, F);
}

// Two cubes at rest, `top` (edge a1, mass m1) on `bottom` (edge a0, mass m0) on the ground,
// offset and turned about z: contact 0 bottom–ground, contact 1 top–bottom. At rest the exact
// step keeps ν⁺ = 0: the top's p_n is m1 g h under its centre; the bottom carries both, at the
// stack's centre of mass (its moment balance), m0 c0 + m1 c1 over m0 + m1 in x and y.
IslandCase StackAtRest(double a0, double m0, double a1, double m1) {
  const Vector3d c0(0.1 * a0, -0.2 * a0, a0 / 2), c1(0.25 * a0, -0.1 * a0, a0 + a1 / 2);
  IslandCase c(
      {MakeBoxBody(Vector3d::Constant(a0), m0, "bottom"),
       MakeBoxBody(Vector3d::Constant(a1), m1, "top")},
      {MovingState(c0, Rotation(0.2, Vector3d::UnitZ()), Vector3d::Zero(), Vector3d::Zero()),
       MovingState(c1, Rotation(-0.4, Vector3d::UnitZ()), Vector3d::Zero(), Vector3d::Zero())});
  c.Add(0, Other::kFixed, -1, c.scene.obstacles[0].shape.get());
  c.Add(1, Other::kBody, 0, c.hull(0));
  c.Layout();
  const double p_top = -c.problem.bodies[1].p_gravity.z();
  const double p_both = -(c.problem.bodies[0].p_gravity.z() + c.problem.bodies[1].p_gravity.z());
  const Vector3d stack_cm = (m0 * c0 + m1 * c1) / (m0 + m1);
  const int down = FaceWithNormal(*c.hull(0), -Vector3d::UnitZ());
  const int up = FaceWithNormal(*c.hull(0), Vector3d::UnitZ());
  SetContact(c, 0, Vector3d(stack_cm.x(), stack_cm.y(), 0), down, 0, p_both, 0, 0, 0, 0);
  SetContact(c, 1, Vector3d(c1.x(), c1.y(), a0), FaceWithNormal(*c.hull(1), -Vector3d::UnitZ()), up,
             p_top, 0, 0, 0, 0);
  return c;
}

TEST(IslandExactSolutionTest, TwoUnitCubesRestFaceToFaceOnTheGround) {
  IslandCase c = StackAtRest(1, 3, 1, 2);
  EXPECT_LT(Measure(c), kExactSolutionMeasure);
  // the bottom cube carrying only its own weight is far from a solution: its force row misses
  // the top's whole weight, of the order of its scale
  c.z[c.layout.contacts[0].p_n] = -c.problem.bodies[0].p_gravity.z();
  constexpr double kMissingWeightMeasure = 0.5;
  EXPECT_GT(Measure(c), kMissingWeightMeasure);
}

TEST(IslandExactSolutionTest, CubeSlidesOnACubeThatSlidesOnIce) {
  // top cube at 0.5 m/s on the bottom one at 0.1 m/s, whose ground is frictionless: friction
  // −e_t μ p_n brakes the top and drives the bottom; the top's ECP sits 0.5 μ e_t ahead of its
  // centre (zero moment), the bottom's on the ground where the moments balance; σ = e_t v_rel⁺
  const double h = 0.01, m0 = 3, m1 = 2;
  const Friction friction{0.3, 0.8, 0.8, 0.1};
  const Vector3d c0(0, 0, 0.5), c1(0.2, 0, 1.5);
  IslandCase c(
      {MakeBoxBody(Vector3d::Ones(), m0, "bottom"), MakeBoxBody(Vector3d::Ones(), m1, "top")},
      {MovingState(c0, Quaterniond::Identity(), Vector3d(0.1, 0, 0), Vector3d::Zero()),
       MovingState(c1, Rotation(0.3, Vector3d::UnitZ()), Vector3d(0.5, 0, 0), Vector3d::Zero())},
      h);
  c.Add(0, Other::kFixed, -1, c.scene.obstacles[0].shape.get(), Friction{0, 1, 1, 0.1});
  c.Add(1, Other::kBody, 0, c.hull(0), friction);
  c.Layout();
  const double p_n1 = m1 * kG * h, p_n0 = (m0 + m1) * kG * h;
  const double p_t1 = -friction.e_t * friction.mu * p_n1;
  const Vector3d v1(0.5 + p_t1 / m1, 0, 0), v0(0.1 - p_t1 / m0, 0, 0);
  c.z.segment<3>(0) = v0;
  c.z.segment<3>(6) = v1;
  const Vector3d c0_end = c0 + h * v0, c1_end = c1 + h * v1;
  const Vector3d ecp_top = c1_end + Vector3d(-0.5 * p_t1 / p_n1, 0, -0.5);
  const Vector3d arm = ecp_top - c0_end;  // (X, 0, 0.5) from the bottom's centre
  const double dx = (arm.x() * p_n1 - 0.5 * p_t1) / p_n0;
  const double sigma = friction.e_t * (v1.x() - v0.x());
  SetContact(c, 0, c0_end + Vector3d(dx, 0, -0.5), FaceWithNormal(*c.hull(0), -Vector3d::UnitZ()),
             0, p_n0, 0, 0, 0, 0);
  SetContact(c, 1, ecp_top, FaceWithNormal(*c.hull(1), -Vector3d::UnitZ()),
             FaceWithNormal(*c.hull(0), Vector3d::UnitZ()), p_n1, p_t1, 0, 0, sigma);
  EXPECT_LT(Measure(c), kExactSolutionMeasure);
  // momentum: the pair's horizontal momentum is unchanged (ice below, no load)
  EXPECT_NEAR(m0 * v0.x() + m1 * v1.x(), m0 * 0.1 + m1 * 0.5, kRoundOffRelative);
  // friction on the top's own velocity instead of the relative one is not a solution
  c.z[c.layout.contacts[1].sigma] = friction.e_t * v1.x();
  EXPECT_GT(Measure(c), kNoSolutionMeasure);
}

TEST(IslandExactSolutionTest, SpinningCubeTwistsTheCubeBelow) {
  // top cube spinning at 3 rad/s on the bottom one at 1 rad/s (frictionless ground), centres
  // aligned: no slip at the ECP, torsion p_r = −e_r μ p_n on the top and +e_r μ p_n on the
  // bottom; σ = e_r (ω_top − ω_bottom)⁺. Cubes: isotropic inertia, no gyroscopic term.
  const double h = 0.01, m0 = 3, m1 = 2;
  const Friction friction{0.4, 1, 1, 0.05};
  const Vector3d c0(0.1, 0.2, 0.5), c1(0.1, 0.2, 1.5);
  IslandCase c(
      {MakeBoxBody(Vector3d::Ones(), m0), MakeBoxBody(Vector3d::Ones(), m1)},
      {MovingState(c0, Rotation(0.1, Vector3d::UnitZ()), Vector3d::Zero(), Vector3d(0, 0, 1)),
       MovingState(c1, Rotation(0.6, Vector3d::UnitZ()), Vector3d::Zero(), Vector3d(0, 0, 3))},
      h);
  c.Add(0, Other::kFixed, -1, c.scene.obstacles[0].shape.get(), Friction{0, 1, 1, 0.1});
  c.Add(1, Other::kBody, 0, c.hull(0), friction);
  c.Layout();
  const double I0 = m0 / 6, I1 = m1 / 6;  // kg·m², a unit cube's about any axis
  const double p_n1 = m1 * kG * h, p_r = -friction.e_r * friction.mu * p_n1;
  const double w1 = 3 + p_r / I1, w0 = 1 - p_r / I0;
  c.z[5] = w0;
  c.z[11] = w1;
  SetContact(c, 0, Vector3d(0.1, 0.2, 0), FaceWithNormal(*c.hull(0), -Vector3d::UnitZ()), 0,
             (m0 + m1) * kG * h, 0, 0, 0, 0);
  SetContact(c, 1, Vector3d(0.1, 0.2, 1), FaceWithNormal(*c.hull(1), -Vector3d::UnitZ()),
             FaceWithNormal(*c.hull(0), Vector3d::UnitZ()), p_n1, 0, 0, p_r,
             friction.e_r * (w1 - w0));
  EXPECT_LT(Measure(c), kExactSolutionMeasure);
  // the pair's angular momentum about the vertical is unchanged
  EXPECT_NEAR(I0 * w0 + I1 * w1, I0 * 1 + I1 * 3, kRoundOffRelative);
}

TEST(IslandExactSolutionTest, ConveyorBeltDragsABoxAndOnlyTakesTheWorkItGives) {
  // a cube at rest on a kinematic belt moving at V = 1 m/s: friction e_t μ p_n forward, the
  // ECP 0.5 p_t / p_n behind the centre (zero moment), σ = e_t (V − u⁺). The box gains
  // ½ m u⁺², the belt does p_t V of work: the island's gain is p_t (½ u⁺ − V) < 0
  const double h = 0.01, m = 2, V = 1;
  const Friction friction{0.4, 0.9, 0.9, 0.1};
  const Vector3d c0(0.2, 0.3, 0.5);
  IslandCase c(
      {MakeBoxBody(Vector3d::Ones(), m)},
      {MovingState(c0, Rotation(0.5, Vector3d::UnitZ()), Vector3d::Zero(), Vector3d::Zero())}, h);
  const auto belt = geometry::MakeBox(Vector3d(2, 2, 0.1));
  c.problem.kinematic = {
      {Vector3d(0, 0, -0.1), Matrix3d::Identity(), Vector3d(V, 0, 0), Vector3d::Zero()}};
  c.Add(0, Other::kKinematic, 0, belt.get(), friction);
  c.Layout();
  const double p_n = m * kG * h, p_t = friction.e_t * friction.mu * p_n, u = p_t / m;
  c.z[0] = u;
  const Vector3d ecp = c0 + h * Vector3d(u, 0, 0) + Vector3d(-0.5 * p_t / p_n, 0, -0.5);
  SetContact(c, 0, ecp, FaceWithNormal(*c.hull(0), -Vector3d::UnitZ()),
             FaceWithNormal(*belt, Vector3d::UnitZ()), p_n, p_t, 0, 0, friction.e_t * (V - u));
  EXPECT_LT(Measure(c), kExactSolutionMeasure);

  const double box_gain = StepEnergyGain(c.problem.bodies[0], c.z.head<3>(), c.z.segment<3>(3));
  const double island_gain = IslandStepEnergyGain(c.problem, c.layout, c.z);
  const double energy = 0.5 * m * V * V;
  EXPECT_NEAR(box_gain, 0.5 * m * u * u, kRoundOffRelative * energy);
  EXPECT_NEAR(island_gain, p_t * (0.5 * u - V), kRoundOffRelative * energy);
  EXPECT_LT(island_gain, 0);
}

// --- the convergence measure: each body's rows in its own units ---

TEST(IslandMeasureTest, ContactRowsInTheSmallerLengthAndNewtonEulerRowsInEachBodysImpulse) {
  // a 0.1 m cube on a 2 m cube: at the exact stack an error δ in the contact's a1 − a2 row
  // measures δ / L_small, and an error δ in a body's force row measures δ / P of that body
  IslandCase c = StackAtRest(2, 50, 0.1, 0.5);
  VectorXd F;
  EvaluateIslandMncp(c.problem, c.layout, c.z, &F, nullptr);
  ASSERT_LT(Measure(c, F), kExactSolutionMeasure);
  std::vector<Scales> scales;
  for (int b = 0; b < 2; ++b) {
    scales.push_back(
        BodyScales(c.scene.bodies[b], c.states[b], c.problem.bodies[b].p_ext, c.problem.h));
  }
  ASSERT_LT(scales[1].length, scales[0].length);

  // the other rows, and the perturbed one before, are within kExactSolutionMeasure of 0
  constexpr double kError = 1e-6;  // m and N·s: far above round-off, far below the rows' scales
  VectorXd F_length = F;
  F_length[c.layout.contacts[1].a1] += kError;
  EXPECT_NEAR(Measure(c, F_length), kError / scales[1].length, kExactSolutionMeasure);
  for (int b = 0; b < 2; ++b) {
    VectorXd F_force = F;
    F_force[IslandLayout::Velocity(b) + 2] += kError;
    EXPECT_NEAR(Measure(c, F_force), kError / scales[b].impulse, kExactSolutionMeasure);
  }
}

}  // namespace
}  // namespace ecpsim::engine
