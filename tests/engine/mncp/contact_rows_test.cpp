#include "engine/mncp/contact_rows.h"

#include <algorithm>
#include <cfloat>
#include <memory>
#include <random>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <Eigen/Geometry>

#include "tests/engine/island_test_problems.h"
#include "tests/engine/jacobian_check.h"

namespace ecpsim::engine {
namespace {

using Eigen::MatrixXd;
using Eigen::Quaterniond;
using Eigen::Vector3d;
using Eigen::VectorXd;

// dimensionless: the closed-form rows below are a handful of operations on O(1) numbers
constexpr double kRoundOff = 16 * DBL_EPSILON;

Quaterniond Turn(double angle, const Vector3d& axis) {
  return Quaterniond(Eigen::AngleAxisd(angle, axis.normalized()));
}

enum class Other { kFixed, kKinematic, kBody };

// One contact made by hand: F's hull on body 0 against G — a fixed obstacle (world frame), a
// kinematic body (its motion prescribed) or body 1 — laid out after the bodies' ν⁺ (a fixed
// half-space in the plane form), with unknowns z
struct HandContact {
  std::string name;
  std::vector<BodyProblem> bodies;
  std::shared_ptr<const geometry::ConvexShape> hull, other;
  std::vector<int> window, other_window;
  Other kind = Other::kFixed;
  StepMotion kinematic;  // G's motion when kinematic
  Friction friction{0.3, 1.0, 0.8, 0.1};
  Vector3d tangent_reference = Vector3d::UnitX();
  double stick_creep = 0;
  MncpLayout::Contact L{};
  int size = 0;
  VectorXd z;

  ContactSides Sides() const {
    return {hull.get(), &window,           other.get(), &other_window,
            friction,   tangent_reference, stick_creep};
  }
  double h() const { return bodies[0].h; }

  // windows of every constraint, the layout, and z zero
  void Layout() {
    window.clear();
    other_window.clear();
    for (int i = 0; i < hull->NumConstraints(); ++i) window.push_back(i);
    for (int j = 0; j < other->NumConstraints(); ++j) other_window.push_back(j);
    const bool plane = kind == Other::kFixed && other->IsHalfSpace();
    const int l_g_count = plane ? 0 : static_cast<int>(other_window.size());
    const MncpLayout layout = LayOutContacts(6 * static_cast<int>(bodies.size()),
                                             {{static_cast<int>(window.size()), l_g_count}});
    L = layout.contacts[0];
    size = layout.size;
    z = VectorXd::Zero(size);
  }

  // random unknowns of plausible size (the Jacobian identity holds at any z): ν⁺ near ν, a1 and
  // a2 near `near`
  void Randomize(const Vector3d& near, unsigned seed) {
    Layout();
    std::mt19937 rng(seed);
    std::uniform_real_distribution<double> u(-1, 1);
    for (size_t b = 0; b < bodies.size(); ++b) {
      z.segment<3>(6 * b) = bodies[b].v + Vector3d(u(rng), u(rng), u(rng)) * 0.3;
      z.segment<3>(6 * b + 3) = bodies[b].w + Vector3d(u(rng), u(rng), u(rng)) * 0.3;
    }
    testing::RandomizeContact(L, near, 0.245, rng, z);
  }
};

using Part = void (*)(const ContactAtZ&, VectorXd&, MatrixXd*);

// the contact at z as AddContactRows sees it, handed to `use`: the bodies' motions from their
// own Newton–Euler rows, which are left out of F and J
template <typename Use>
void WithContactAt(const HandContact& hc, const VectorXd& z, bool with_jacobian, const Use& use) {
  VectorXd body_rows = VectorXd::Zero(hc.size);
  MatrixXd body_jacobian = MatrixXd::Zero(with_jacobian ? hc.size : 0, with_jacobian ? hc.size : 0);
  std::vector<StepMotion> motions;
  for (size_t b = 0; b < hc.bodies.size(); ++b)
    motions.push_back(AddBodyRows(hc.bodies[b], static_cast<int>(6 * b), z, body_rows,
                                  with_jacobian ? &body_jacobian : nullptr));
  const StepMotion* other = hc.kind == Other::kBody        ? &motions[1]
                            : hc.kind == Other::kKinematic ? &hc.kinematic
                                                           : nullptr;
  const ContactSides sides = hc.Sides();
  use(sides, motions[0], other);
}

// F and J of `part` alone at z
void EvaluatePart(const HandContact& hc, Part part, const VectorXd& z, VectorXd* F, MatrixXd* J) {
  F->setZero(hc.size);
  if (J) J->setZero(hc.size, hc.size);
  WithContactAt(hc, z, J != nullptr,
                [&](const ContactSides& sides, const StepMotion& body, const StepMotion* other) {
                  part(ContactAtZ(sides, hc.L, body, other, hc.h(), z, J != nullptr), *F, J);
                });
}

// F and J of AddContactRows at z
void EvaluateContact(const HandContact& hc, const VectorXd& z, VectorXd* F, MatrixXd* J) {
  F->setZero(hc.size);
  J->setZero(hc.size, hc.size);
  WithContactAt(hc, z, true,
                [&](const ContactSides& sides, const StepMotion& body, const StepMotion* other) {
                  AddContactRows(sides, hc.L, body, other, hc.h(), z, *F, J);
                });
}

// --- the hand-made contacts ---

// a box tilted onto an edge on the ground: the plane form
HandContact BoxOnGround() {
  HandContact hc;
  hc.name = "BoxOnGround";
  hc.bodies = {testing::MakeMovingBody(Vector3d(0, 0, 0.08), Turn(0.4, Vector3d::UnitX()),
                                       Vector3d(0.3, -0.2, 0), Vector3d(0.5, 1.5, -2.0))};
  hc.hull = geometry::MakeBox(Vector3d(0.2, 0.1, 0.05));
  hc.other = geometry::MakeHalfSpace(Vector3d::UnitZ(), 0);
  hc.Randomize(Vector3d(0, 0, 0), 1);
  return hc;
}

// a box on a vertex against a fixed box: G with six constraints, N a combination of them
HandContact BoxOnBoxFixture() {
  HandContact hc;
  hc.name = "BoxOnBoxFixture";
  hc.bodies = {testing::MakeMovingBody(Vector3d(0.1, 0.2, 0.7), Turn(0.5, Vector3d(1, -1, 0)),
                                       Vector3d(0.1, 0.2, -0.3), Vector3d(1.0, -0.5, 0.3))};
  hc.hull = geometry::MakeBox(Vector3d(0.1, 0.1, 0.1));
  hc.other = geometry::MakeBox(Vector3d(0.5, 0.5, 0.5));
  hc.tangent_reference = Vector3d(1, 0.3, -0.2).normalized();
  hc.Randomize(Vector3d(0.1, 0.2, 0.5), 2);
  return hc;
}

// a cylinder on a fixed sphere: curved on both sides (Hessians of f and g)
HandContact CylinderOnSphere() {
  HandContact hc;
  hc.name = "CylinderOnSphere";
  hc.bodies = {testing::MakeMovingBody(Vector3d(0, 0.1, 1.1), Turn(0.3, Vector3d(1, 2, 0)),
                                       Vector3d(-0.2, 0.1, 0.05), Vector3d(0.4, -1.0, 0.6))};
  hc.hull = geometry::MakeCylinder(0.1, 0.3, 0);
  hc.other = geometry::MakeSphere(1.0);
  hc.Randomize(Vector3d(0, 0.1, 1.0), 3);
  return hc;
}

// a box on a moving, turning box, G a body of the island: its ν⁺ unknowns too
HandContact BoxOnMovingBox() {
  HandContact hc;
  hc.name = "BoxOnMovingBox";
  hc.kind = Other::kBody;
  hc.bodies = {testing::MakeMovingBody(Vector3d(0.15, 0.05, 0.3), Turn(0.6, Vector3d(1, 1, 1)),
                                       Vector3d(-0.3, 0.2, -0.1), Vector3d(1.5, -1.0, 2.0)),
               testing::MakeMovingBody(Vector3d(0.1, 0, 0.1), Turn(0.1, Vector3d(1, 2, 10)),
                                       Vector3d(0.2, -0.1, 0.05), Vector3d(0.3, -0.5, 1.0))};
  hc.hull = geometry::MakeBox(Vector3d(0.15, 0.1, 0.05));
  hc.other = geometry::MakeBox(Vector3d(0.3, 0.3, 0.1));
  hc.tangent_reference = Vector3d::UnitY();
  hc.Randomize(Vector3d(0.15, 0.05, 0.2), 4);
  return hc;
}

// a cylinder on a kinematic sphere that moves and turns, with a sticking creep (σ + ε)
HandContact CylinderOnKinematicSphere() {
  HandContact hc;
  hc.name = "CylinderOnKinematicSphere";
  hc.kind = Other::kKinematic;
  hc.bodies = {testing::MakeMovingBody(Vector3d(0.2, 0, 0.65), Turn(0.7, Vector3d(0, 1, 1)),
                                       Vector3d(0.1, 0.1, -0.2), Vector3d(-0.6, 0.8, 0.4))};
  const Eigen::Matrix3d R_G = Turn(0.2, Vector3d(1, 0, 1)).toRotationMatrix();
  hc.kinematic.v = Vector3d(0.4, -0.1, 0.05);
  hc.kinematic.w = Vector3d(0.2, 0.3, -0.5);
  hc.kinematic.end = PoseAfterStep(Vector3d(0.1, 0, 0), R_G, 0.01, hc.kinematic.v, hc.kinematic.w);
  hc.hull = geometry::MakeCylinder(0.08, 0.25, 2);
  hc.other = geometry::MakeSphere(0.5);
  hc.stick_creep = 1e-3;
  hc.Randomize(Vector3d(0.2, 0, 0.55), 5);
  return hc;
}

std::vector<HandContact> HandContacts() {
  return {BoxOnGround(), BoxOnBoxFixture(), CylinderOnSphere(), BoxOnMovingBox(),
          CylinderOnKinematicSphere()};
}

// --- the parts and the rows each one owns ---

struct NamedPart {
  const char* name;
  Part part;
};

const NamedPart kParts[] = {
    {"AddContactImpulse", AddContactImpulse},
    {"SetSeparationRows", SetSeparationRows},
    {"SetNormalConeRows", SetNormalConeRows},
    {"SetHullConstraintRows", SetHullConstraintRows},
    {"SetObstacleConstraintRows", SetObstacleConstraintRows},
    {"SetGapRow", SetGapRow},
    {"SetMaximumDissipationRows", SetMaximumDissipationRows},
};
constexpr int kNumParts = static_cast<int>(std::size(kParts));

// the rows part `p` (an index of kParts) sets: its equation's rows, and for the impulse the
// Newton–Euler rows of F and of a dynamic G
std::vector<int> RowsOfPart(const HandContact& hc, int p) {
  const MncpLayout::Contact& L = hc.L;
  const auto range = [](int first, int count) {
    std::vector<int> rows;
    for (int i = 0; i < count; ++i) rows.push_back(first + i);
    return rows;
  };
  switch (p) {
    case 0:
      return range(0, hc.kind == Other::kBody ? 12 : 6);
    case 1:
      return L.on_plane() ? std::vector<int>{} : range(L.a1, 3);
    case 2:
      return range(L.on_plane() ? L.a1 : L.a2, 3);
    case 3:
      return range(L.l, L.l_count);
    case 4: {
      if (L.on_plane()) return {};
      std::vector<int> rows = range(L.l_g, L.l_g_count);
      rows.push_back(L.s);
      return rows;
    }
    case 5:
      return {L.p_n};
    case 6:
      return {L.p_t, L.p_o, L.p_r, L.sigma};
    default:
      ADD_FAILURE() << "no part " << p;
      return {};
  }
}

// every part's Jacobian rows against central differences of its own residual rows (trap 5)
class ContactPartJacobianTest : public ::testing::TestWithParam<std::tuple<int, int>> {};

TEST_P(ContactPartJacobianTest, MatchesCentralDifferences) {
  const HandContact hc = HandContacts()[std::get<0>(GetParam())];
  const Part part = kParts[std::get<1>(GetParam())].part;
  const double error = testing::JacobianError(
      [&](const VectorXd& z, VectorXd* F, MatrixXd* J) { EvaluatePart(hc, part, z, F, J); }, hc.z);
  EXPECT_LT(error, 1e-7);
}

INSTANTIATE_TEST_SUITE_P(
    EveryPartOfEveryContact, ContactPartJacobianTest,
    ::testing::Combine(::testing::Range(0, 5), ::testing::Range(0, kNumParts)),
    [](const ::testing::TestParamInfo<std::tuple<int, int>>& contact_and_part) {
      return HandContacts()[std::get<0>(contact_and_part.param)].name + "_" +
             kParts[std::get<1>(contact_and_part.param)].name;
    });

// Each part sets its own rows and no others, every row of the contact belongs to exactly one
// part, and the parts together are AddContactRows to the bit
TEST(ContactPartsTest, PartitionTheContactsRowsAndSumToAddContactRows) {
  for (const HandContact& hc : HandContacts()) {
    SCOPED_TRACE(hc.name);
    VectorXd F_sum = VectorXd::Zero(hc.size), F_part, F_whole;
    MatrixXd J_sum = MatrixXd::Zero(hc.size, hc.size), J_part, J_whole;
    std::vector<int> owner(hc.size, -1);
    for (int p = 0; p < kNumParts; ++p) {
      SCOPED_TRACE(kParts[p].name);
      EvaluatePart(hc, kParts[p].part, hc.z, &F_part, &J_part);
      std::vector<bool> own(hc.size, false);
      for (int row : RowsOfPart(hc, p)) {
        EXPECT_EQ(owner[row], -1) << "row " << row << " also set by " << kParts[owner[row]].name;
        owner[row] = p;
        own[row] = true;
        EXPECT_TRUE((J_part.row(row).array() != 0).any()) << "row " << row << " left unset";
      }
      for (int row = 0; row < hc.size; ++row) {
        if (own[row]) continue;
        EXPECT_EQ(F_part[row], 0) << "row " << row;
        EXPECT_TRUE((J_part.row(row).array() == 0).all()) << "row " << row;
      }
      F_sum += F_part;
      J_sum += J_part;
    }
    // every row: a body's Newton–Euler row or one of the contact's (the layout's rows past ν⁺)
    const int first_contact_row = 6 * static_cast<int>(hc.bodies.size());
    for (int row = first_contact_row; row < hc.size; ++row)
      EXPECT_NE(owner[row], -1) << "row " << row << " set by no part";
    EvaluateContact(hc, hc.z, &F_whole, &J_whole);
    for (int i = 0; i < hc.size; ++i) EXPECT_EQ(F_sum[i], F_whole[i]) << "row " << i;
    for (int i = 0; i < hc.size; ++i)
      for (int j = 0; j < hc.size; ++j)
        EXPECT_EQ(J_sum(i, j), J_whole(i, j)) << "row " << i << " column " << j;
  }
}

// --- rows with a closed form ---

// the index in hc's window of the constraint of `shape` whose gradient at y is `normal`
int ConstraintWithGradient(const geometry::ConvexShape& shape, const Vector3d& y,
                           const Vector3d& normal) {
  for (int i = 0; i < shape.NumConstraints(); ++i)
    if ((shape.Gradient(i, y) - normal).norm() < kRoundOff) return i;
  ADD_FAILURE() << "no constraint with gradient " << normal.transpose();
  return -1;
}

// the rows of `part` alone at hc.z
VectorXd PartRows(const HandContact& hc, Part part) {
  VectorXd F;
  EvaluatePart(hc, part, hc.z, &F, nullptr);
  return F;
}

// A box (half extents 0.2, 0.1, 0.05) level on the ground, CM at height 0.05, sliding along x at
// 0.3 m/s without turning, its ECP 2 mm above the ground: every row by hand
TEST(ContactRowsTest, ABoxSlidingLevelOnTheGround) {
  HandContact hc;
  hc.bodies = {testing::MakeMovingBody(Vector3d(0, 0, 0.05), Quaterniond::Identity(),
                                       Vector3d(0.3, 0, 0), Vector3d::Zero())};
  hc.hull = geometry::MakeBox(Vector3d(0.2, 0.1, 0.05));
  hc.other = geometry::MakeHalfSpace(Vector3d::UnitZ(), 0);
  hc.Layout();
  const MncpLayout::Contact& L = hc.L;
  ASSERT_TRUE(L.on_plane());
  hc.z.head<3>() = Vector3d(0.3, 0, 0);  // v⁺; ω⁺ = 0: c⁺ = (0.003, 0, 0.05), R⁺ = I
  hc.z.segment<3>(L.a1) = Vector3d(0.03, -0.02, 0.002);
  for (int i = 0; i < L.l_count; ++i) hc.z[L.l + i] = 1;
  hc.z[L.p_n] = 0.245;
  hc.z[L.p_t] = -0.05;
  hc.z[L.p_o] = 0.01;
  hc.z[L.p_r] = 0.002;
  hc.z[L.sigma] = 0.4;

  // gap: s = g(a1) = a1_z
  EXPECT_NEAR(PartRows(hc, SetGapRow)[L.p_n], 0.002, kRoundOff);
  // hull: −f_i = d_i − n_i · y, y = a1 − c⁺ = (0.027, −0.02, −0.048), over the six faces
  const VectorXd hull = PartRows(hc, SetHullConstraintRows);
  std::vector<double> distances(hull.data() + L.l, hull.data() + L.l + L.l_count);
  std::sort(distances.begin(), distances.end());
  const std::vector<double> expected = {0.002, 0.08, 0.098, 0.12, 0.173, 0.227};
  ASSERT_EQ(distances.size(), expected.size());
  for (size_t i = 0; i < expected.size(); ++i) EXPECT_NEAR(distances[i], expected[i], kRoundOff);
  // normal cone with every l_i = 1: N + Σ n_i = e_z (a box's face normals sum to zero)
  const VectorXd cone = PartRows(hc, SetNormalConeRows);
  EXPECT_LT((cone.segment<3>(L.a1) - Vector3d::UnitZ()).norm(), kRoundOff);
  // impulse: n = e_z, t = e_x, o = e_y, force = (p_t, p_o, p_n) at r = (0.027, −0.02, −0.048);
  // the rows are −force and −(r × force + n p_r)
  const VectorXd impulse = PartRows(hc, AddContactImpulse);
  EXPECT_LT((impulse.head<3>() - Vector3d(0.05, -0.01, -0.245)).norm(), kRoundOff);
  EXPECT_LT((impulse.segment<3>(3) - Vector3d(0.00442, 0.004215, -0.00127)).norm(), kRoundOff);
  // friction (μ = 0.3, e = (1, 0.8, 0.1)) at v_c = (0.3, 0, 0): e² μ p_n v + p σ, and the cone
  const VectorXd friction = PartRows(hc, SetMaximumDissipationRows);
  EXPECT_NEAR(friction[L.p_t], 0.3 * 0.245 * 0.3 - 0.05 * 0.4, kRoundOff);
  EXPECT_NEAR(friction[L.p_o], 0.01 * 0.4, kRoundOff);
  EXPECT_NEAR(friction[L.p_r], 0.002 * 0.4, kRoundOff);
  EXPECT_NEAR(friction[L.sigma], 0.3 * 0.245 - std::sqrt(0.0025 + 0.00015625 + 0.0004), kRoundOff);
}

// A box at rest 1 mm above a kinematic platform (half extents 0.5, 0.5, 0.1, its top at z = 0)
// that moves at 0.5 m/s along x and turns at 0.2 rad/s about z, with a creep ε = 1 mm/s: G's
// rows in the general form, and the friction on the velocity relative to the platform at a2
TEST(ContactRowsTest, ABoxAtRestAboveAMovingTurningPlatform) {
  HandContact hc;
  hc.kind = Other::kKinematic;
  hc.bodies = {testing::MakeMovingBody(Vector3d(0.1, 0, 0.051), Quaterniond::Identity(),
                                       Vector3d::Zero(), Vector3d::Zero())};
  hc.hull = geometry::MakeBox(Vector3d(0.2, 0.1, 0.05));
  hc.other = geometry::MakeBox(Vector3d(0.5, 0.5, 0.1));
  hc.kinematic.v = Vector3d(0.5, 0, 0);
  hc.kinematic.w = Vector3d(0, 0, 0.2);
  hc.kinematic.end = PoseAfterStep(Vector3d(0, 0, -0.1), Eigen::Matrix3d::Identity(), 0.01,
                                   hc.kinematic.v, hc.kinematic.w);
  hc.stick_creep = 1e-3;
  hc.Layout();
  const MncpLayout::Contact& L = hc.L;
  ASSERT_FALSE(L.on_plane());
  // a2 on the top face 0.1 m ahead of the platform's centre at the end of the step, a1 above it
  const Vector3d a2 = hc.kinematic.end.c + Vector3d(0.1, 0, 0.1);
  const Vector3d y_G = hc.kinematic.end.R.transpose() * (a2 - hc.kinematic.end.c);
  const int top = ConstraintWithGradient(*hc.other, y_G, Vector3d::UnitZ());
  const int bottom = ConstraintWithGradient(*hc.other, y_G, -Vector3d::UnitZ());
  hc.z.segment<3>(L.a1) = a2 + Vector3d(0, 0, 0.001);
  hc.z.segment<3>(L.a2) = a2;
  hc.z[L.s] = 0.001;
  hc.z[L.l_g + top] = 1;
  hc.z[L.p_n] = 0.245;
  hc.z[L.p_t] = -0.05;
  hc.z[L.p_o] = 0.01;
  hc.z[L.p_r] = 0.002;
  hc.z[L.sigma] = 0.4;

  // a1 − a2 − s N = 0 with N = e_z; Σ l_G − 1 = 0; a2 on the top face, 0.2 m above the bottom
  EXPECT_LT(PartRows(hc, SetSeparationRows).segment<3>(L.a1).norm(), kRoundOff);
  const VectorXd obstacle = PartRows(hc, SetObstacleConstraintRows);
  EXPECT_EQ(obstacle[L.s], 0);
  EXPECT_NEAR(obstacle[L.l_g + top], 0, kRoundOff);
  EXPECT_NEAR(obstacle[L.l_g + bottom], 0.2, kRoundOff);
  EXPECT_NEAR(PartRows(hc, SetGapRow)[L.p_n], 0.001, kRoundOff);
  // the platform's point at a2 moves at v_G + ω_G × (0.1, 0, 0.1) = (0.5, 0.02, 0), so the box
  // slips at v_t = −0.5, v_o = −0.02 and spins at v_r = −0.2 relative to it; σ + ε = 0.401
  const VectorXd friction = PartRows(hc, SetMaximumDissipationRows);
  EXPECT_NEAR(friction[L.p_t], 0.3 * 0.245 * -0.5 - 0.05 * 0.401, kRoundOff);
  EXPECT_NEAR(friction[L.p_o], 0.64 * 0.3 * 0.245 * -0.02 + 0.01 * 0.401, kRoundOff);
  EXPECT_NEAR(friction[L.p_r], 0.01 * 0.3 * 0.245 * -0.2 + 0.002 * 0.401, kRoundOff);
}

}  // namespace
}  // namespace ecpsim::engine
