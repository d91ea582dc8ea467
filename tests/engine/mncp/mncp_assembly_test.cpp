#include "engine/mncp/mncp_assembly.h"

#include <algorithm>
#include <cfloat>
#include <cmath>
#include <random>
#include <vector>

#include <gtest/gtest.h>
#include <Eigen/Geometry>

#include "engine/mncp/island_mncp.h"
#include "engine/mncp/mncp_system.h"
#include "tests/engine/island_test_problems.h"

namespace ecpsim::engine {
namespace {

using Eigen::MatrixXd;
using Eigen::Quaterniond;
using Eigen::Vector3d;
using Eigen::VectorXd;
using Other = IslandContact::Other;

// dimensionless, per Jacobian entry relative to max(1, |entry|): the sparse rows sum an entry's
// few terms in another order than the dense rows, a few ulps apart
constexpr double kSumOrderRoundOff = 64 * DBL_EPSILON;

Quaterniond Turn(double angle, const Vector3d& axis) {
  return Quaterniond(Eigen::AngleAxisd(angle, axis.normalized()));
}

// --- the walk ---

// Rows that record what AssembleMncp asks of them: a body's motion is its column and its v
struct RecordingRows {
  struct ContactCall {
    int body_column;  // F's motion as handed over
    const StepMotion* other;
    int a1;  // which layout
    double h;
  };
  std::vector<int> body_columns;
  std::vector<ContactCall> contacts;

  StepMotion AddBody(const BodyProblem& problem, int column) {
    body_columns.push_back(column);
    StepMotion motion;
    motion.column = column;
    motion.v = problem.v;
    return motion;
  }
  void AddContact(const ContactLink& link, const MncpLayout::Contact& L, const StepMotion& body,
                  double h) {
    contacts.push_back({body.column, link.other, L.a1, h});
  }
};

// three bodies and three contacts: body 2 on a fixed G, body 0 on body 2, body 1 on a kinematic G
struct ThreeBodyView {
  std::vector<BodyProblem> bodies;
  std::vector<MncpLayout::Contact> layout;
  StepMotion kinematic;

  double h() const { return 0.005; }
  int NumBodies() const { return 3; }
  const BodyProblem& Body(int b) const { return bodies[b]; }
  int Column(int b) const { return 6 * b; }
  int NumContacts() const { return 3; }
  const MncpLayout::Contact& Layout(int k) const { return layout[k]; }
  ContactLink Link(int k, const PerBody<StepMotion>& motions) const {
    const int body[] = {2, 0, 1};
    const StepMotion* other[] = {nullptr, &motions[2], &kinematic};
    return {ContactSides{}, body[k], other[k]};
  }
};

TEST(AssembleMncpTest, WalksTheBodiesThenTheContactsInOrderWithTheirMotions) {
  ThreeBodyView view;
  for (int b = 0; b < 3; ++b)
    view.bodies.push_back(testing::MakeMovingBody(Vector3d::Zero(), Quaterniond::Identity(),
                                                  Vector3d(b + 1, 0, 0), Vector3d::Zero()));
  view.layout.resize(3);
  for (int k = 0; k < 3; ++k) view.layout[k].a1 = 100 + 10 * k;
  RecordingRows rows;
  AssembleMncp(view, rows);

  EXPECT_EQ(rows.body_columns, (std::vector<int>{0, 6, 12}));
  ASSERT_EQ(rows.contacts.size(), 3u);
  // contact 0: F is body 2 (its motion from AddBody: column 12), G fixed
  EXPECT_EQ(rows.contacts[0].body_column, 12);
  EXPECT_EQ(rows.contacts[0].other, nullptr);
  // contact 1: F is body 0, G is body 2 — the motion AddBody returned for it
  EXPECT_EQ(rows.contacts[1].body_column, 0);
  ASSERT_NE(rows.contacts[1].other, nullptr);
  EXPECT_EQ(rows.contacts[1].other->column, 12);
  EXPECT_EQ(rows.contacts[1].other->v, Vector3d(3, 0, 0));
  // contact 2: F is body 1, G the kinematic body
  EXPECT_EQ(rows.contacts[2].body_column, 6);
  EXPECT_EQ(rows.contacts[2].other, &view.kinematic);
  for (int k = 0; k < 3; ++k) {
    EXPECT_EQ(rows.contacts[k].a1, 100 + 10 * k);
    EXPECT_EQ(rows.contacts[k].h, 0.005);
  }
}

TEST(PerBodyTest, OneValueInPlaceOrOnePerBody) {
  PerBody<int> one(1, 7);
  EXPECT_EQ(one[0], 7);
  one[0] = 3;
  EXPECT_EQ(one[0], 3);
  PerBody<int> three(3, 7);
  three[1] = 5;
  EXPECT_EQ(three[0], 7);
  EXPECT_EQ(three[1], 5);
  EXPECT_EQ(three[2], 7);
}

// --- the rows ---

// EvaluateMncp is, to the bit, the body's Newton–Euler rows and then each contact's rows in order
TEST(DenseMncpRowsTest, OneBodysMncpIsItsBodyRowsThenItsContactRows) {
  const auto box = geometry::MakeBox(Vector3d(0.2, 0.1, 0.05));
  const auto ground = geometry::MakeHalfSpace(Vector3d::UnitZ(), 0);
  const auto fixture = geometry::MakeBox(Vector3d(0.5, 0.4, 0.3));
  BodyProblem problem = testing::MakeMovingBody(Vector3d(0.1, 0, 0.1), Turn(0.3, Vector3d(1, 2, 3)),
                                                Vector3d(0.3, -0.2, 0.1), Vector3d(0.5, 1.5, -2.0));
  for (const geometry::ConvexShape* obstacle : {ground.get(), fixture.get()}) {
    ContactProblem cp;
    cp.hull = box.get();
    cp.obstacle = obstacle;
    for (int i = 0; i < box->NumConstraints(); ++i) cp.window.push_back(i);
    cp.friction = Friction{0.3, 1.0, 0.8, 0.1};
    problem.contacts.push_back(cp);
  }
  const MncpLayout layout = MakeLayout(problem);
  std::mt19937 rng(7);
  VectorXd z = VectorXd::Zero(layout.size);
  z.head<3>() = Vector3d(0.25, -0.1, 0.05);
  z.segment<3>(3) = Vector3d(0.4, 1.2, -1.8);
  for (const MncpLayout::Contact& L : layout.contacts)
    testing::RandomizeContact(L, Vector3d(0.1, 0, 0.05), 0.245, rng, z);

  VectorXd F, F_parts = VectorXd::Zero(layout.size);
  MatrixXd J, J_parts = MatrixXd::Zero(layout.size, layout.size);
  EvaluateMncp(problem, layout, z, &F, &J);
  const StepMotion body = AddBodyRows(problem, 0, z, F_parts, &J_parts);
  for (size_t k = 0; k < problem.contacts.size(); ++k) {
    const ContactProblem& cp = problem.contacts[k];
    const ContactSides sides{cp.hull, &cp.window,  cp.obstacle,
                             nullptr, cp.friction, cp.tangent_reference};
    AddContactRows(sides, layout.contacts[k], body, nullptr, problem.h, z, F_parts, &J_parts);
  }
  for (int i = 0; i < layout.size; ++i) EXPECT_EQ(F[i], F_parts[i]) << "row " << i;
  for (int i = 0; i < layout.size; ++i)
    for (int j = 0; j < layout.size; ++j)
      EXPECT_EQ(J(i, j), J_parts(i, j)) << "row " << i << " column " << j;
}

// SparseMncpRows: the dense rows' F (==), their J to the order of its sums, every
// diagonal entry in the pattern — for an island with a contact between its two bodies, one on a
// plane and one with a kinematic body
TEST(SparseMncpRowsTest, AreTheDenseRowsScatteredWithTheWholeDiagonal) {
  const auto slab = geometry::MakeBox(Vector3d(0.3, 0.3, 0.1));
  const auto top = geometry::MakeBox(Vector3d(0.15, 0.1, 0.05));
  const auto ground = geometry::MakeHalfSpace(Vector3d::UnitZ(), 0);
  const auto ball = geometry::MakeSphere(0.2);
  IslandProblem problem;
  problem.h = 0.01;
  problem.bodies = {testing::MakeMovingBody(Vector3d(0.1, 0, 0.1), Turn(0.1, Vector3d(1, 2, 10)),
                                            Vector3d(0.2, -0.1, 0.05), Vector3d(0.3, -0.5, 1.0)),
                    testing::MakeMovingBody(Vector3d(0.15, 0.05, 0.3), Turn(0.6, Vector3d(1, 1, 1)),
                                            Vector3d(-0.3, 0.2, -0.1), Vector3d(1.5, -1.0, 2.0))};
  KinematicBody pusher;
  pusher.c = Vector3d(0.5, 0.05, 0.3);
  pusher.v = Vector3d(-0.4, 0, 0);
  pusher.w = Vector3d(0, 0.3, 0);
  problem.kinematic = {pusher};
  const auto add = [&](int body, Other kind, int other, const geometry::ConvexShape* shape,
                       const geometry::ConvexShape* hull, double creep) {
    IslandContact cp;
    cp.body = body;
    cp.other_kind = kind;
    cp.other = other;
    cp.hull = hull;
    for (int i = 0; i < hull->NumConstraints(); ++i) cp.window.push_back(i);
    cp.other_shape = shape;
    for (int j = 0; j < shape->NumConstraints(); ++j) cp.other_window.push_back(j);
    cp.friction = Friction{0.3, 1.0, 0.8, 0.1};
    cp.stick_creep = creep;
    problem.contacts.push_back(cp);
  };
  add(0, Other::kFixed, -1, ground.get(), slab.get(), 0);
  add(1, Other::kBody, 0, slab.get(), top.get(), 1e-5);
  add(1, Other::kKinematic, 0, ball.get(), top.get(), 0);
  const IslandLayout layout = MakeIslandLayout(problem);
  std::mt19937 rng(11);
  VectorXd z = VectorXd::Zero(layout.size);
  for (int b = 0; b < 2; ++b) {
    z.segment<3>(IslandLayout::Velocity(b)) = problem.bodies[b].v + Vector3d(0.1, -0.05, 0.02);
    z.segment<3>(IslandLayout::Velocity(b) + 3) = problem.bodies[b].w + Vector3d(0.2, 0.1, -0.1);
  }
  const Vector3d near[] = {Vector3d(0.1, 0, 0), Vector3d(0.15, 0.05, 0.2),
                           Vector3d(0.3, 0.05, 0.3)};
  for (int k = 0; k < 3; ++k) testing::RandomizeContact(layout.contacts[k], near[k], 0.245, rng, z);

  VectorXd F_dense, F_sparse;
  MatrixXd J_dense;
  Eigen::SparseMatrix<double> J_sparse;
  EvaluateIslandMncp(problem, layout, z, &F_dense, &J_dense);
  EvaluateIslandMncpSparse(problem, layout, z, &F_sparse, &J_sparse);
  ASSERT_EQ(F_sparse.size(), layout.size);
  for (int i = 0; i < layout.size; ++i) EXPECT_EQ(F_sparse[i], F_dense[i]) << "row " << i;
  const MatrixXd J_scattered = MatrixXd(J_sparse);
  for (int i = 0; i < layout.size; ++i)
    for (int j = 0; j < layout.size; ++j)
      EXPECT_LE(std::abs(J_scattered(i, j) - J_dense(i, j)),
                kSumOrderRoundOff * std::max(1.0, std::abs(J_dense(i, j))))
          << "row " << i << " column " << j;
  std::vector<bool> diagonal(layout.size, false);
  for (int j = 0; j < J_sparse.outerSize(); ++j)
    for (Eigen::SparseMatrix<double>::InnerIterator it(J_sparse, j); it; ++it)
      if (it.row() == it.col()) diagonal[j] = true;
  EXPECT_EQ(std::count(diagonal.begin(), diagonal.end(), true), layout.size);
}

}  // namespace
}  // namespace ecpsim::engine
