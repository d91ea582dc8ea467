#include "engine/models/multipatch_model.h"

#include <cmath>
#include <fstream>
#include <random>

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include "common/errors.h"
#include "engine/scene_io/scene_yaml.h"
#include "engine/step_report.h"
#include "engine/time_step.h"
#include "geometry/convex_hull.h"
#include "geometry/paper_bodies.h"
#include "tests/engine/jacobian_check.h"
#include "tests/engine/test_bodies.h"
#include "tests/tolerances.h"

namespace ecpsim::engine {
namespace {

using Eigen::Vector3d;
using Eigen::VectorXd;
using ::testing::HasSubstr;
using testing::kJacobianTolerance;

// m/s, rad/s or m: the paper's bar on the hull-ECP and multi-patch models' difference
// (|Δv_x|, |Δω_z| < 1e-8): both solve to the tolerance 1e-12, which impacts amplify (the largest
// difference measured below is 2.2e-9)
constexpr double kModelAgreement = 1e-8;
// m or N·s: a resting body's height and weight over the step are solved to the scenes' solver
// tolerance 1e-12 of O(1) scales
constexpr double kSolverTolerance = 1e-12;

// the desk mesh's four feet (geometry/paper_bodies.cpp: 0.06 m squares at x, y ∈ ±[0.19, 0.25],
// legs from z = 0 to the top's underside) as boxes in the body (CM) frame
std::vector<std::shared_ptr<const geometry::ConvexShape>> DeskFeet(const Body& desk,
                                                                   double cm_height) {
  // the legs end where the top begins: the mesh's lowest vertex above the feet's bottom
  constexpr double kAboveTheFeet = 1e-9;  // m: the feet's bottom is at −cm_height to round-off
  double leg_top = INFINITY;
  for (const Vector3d& v : desk.mesh.vertices)
    if (v.z() > -cm_height + kAboveTheFeet) leg_top = std::min(leg_top, v.z());
  std::vector<std::shared_ptr<const geometry::ConvexShape>> feet;
  for (double x : {-0.22, 0.22}) {
    for (double y : {-0.22, 0.22}) {
      const double half_height = 0.5 * (leg_top + cm_height);
      const auto box = geometry::MakeBox(Vector3d(0.03, 0.03, half_height));
      feet.push_back(std::make_shared<geometry::PolyhedralShape>(
          geometry::TranslateHull(box->hull(), Vector3d(x, y, -cm_height + half_height))));
    }
  }
  return feet;
}

// the paper's desk (section 5) with its four feet as parts
Scene PaperDesk(ContactModel model) {
  Scene scene = testing::PaperDeskScene(model);
  scene.bodies[0].parts = DeskFeet(scene.bodies[0], 0.45);
  return scene;
}

// a four-foot problem with plausible random unknowns: the Jacobian identity holds for any z with
// p_n > 0 (where the combined ECP's weights are smooth)
struct Fixture {
  MultiPatchProblem problem;
  MncpLayout layout;
  VectorXd z;
};

// `plane_form`: the model's own layout (MakeMultiPatchLayout, a1 free on the ground), else the
// general form (MakeLayout: a2, s, l_G unknowns too); EvaluateMultiPatch takes either
Fixture MakeFixture(const Eigen::Quaterniond& Q, unsigned seed, bool plane_form = false) {
  static const Scene desk_scene = PaperDesk(ContactModel::kMultiPatch);
  static const auto ground = geometry::MakeHalfSpace(Vector3d::UnitZ(), 0);
  const Body& desk = desk_scene.bodies[0];
  Fixture f;
  BodyProblem& p = f.problem.body;
  p.h = 0.01;
  p.mass = desk.mass;
  p.R = Q.toRotationMatrix();
  p.inertia_world = p.R * desk.inertia * p.R.transpose();
  p.c = Vector3d(0.1, -0.2, 0.45);
  p.v = Vector3d(0.3, 0.2, 0.0);
  p.w = Vector3d(0.1, -0.2, 0.5);
  p.p_ext << 0.3, 0.2, -1.47, 0.01, -0.02, 0.03;
  for (const auto& part : desk.parts) {
    ContactProblem cp;
    cp.hull = part.get();
    cp.obstacle = ground.get();
    for (int i = 0; i < part->NumConstraints(); ++i) cp.window.push_back(i);
    cp.friction = Friction{0.3, 1.0, 0.8, 0.1};
    p.contacts.push_back(cp);
    f.problem.group.push_back(0);
  }
  f.problem.num_groups = 1;
  f.problem.weight_floor = 1e-3;  // large, so that its terms show in the differences
  f.layout = plane_form ? MakeMultiPatchLayout(p) : MakeLayout(p);

  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(-1, 1);
  f.z = VectorXd::Zero(f.layout.size);
  for (int i = 0; i < 6; ++i) f.z[i] = (i < 3 ? p.v[i] : p.w[i - 3]) + 0.3 * u(rng);
  for (const MncpLayout::Contact& L : f.layout.contacts) {
    for (int i = 0; i < 3; ++i) {
      f.z[L.a1 + i] = p.c[i] + 0.3 * u(rng);
      if (!plane_form) f.z[L.a2 + i] = p.c[i] + 0.3 * u(rng);
    }
    if (!plane_form) f.z[L.s] = 0.01 * u(rng);
    f.z[L.p_t] = 0.1 * u(rng);
    f.z[L.p_o] = 0.1 * u(rng);
    f.z[L.p_r] = 0.01 * u(rng);
    f.z[L.p_n] = 0.4 * (1 + 0.5 * u(rng));
    f.z[L.sigma] = 0.2 + 0.1 * u(rng);
    for (int i = 0; i < L.l_count; ++i) f.z[L.l + i] = 0.5 + 0.5 * u(rng);
    if (!plane_form) f.z[L.l_g] = 1.0 + 0.3 * u(rng);
  }
  return f;
}

// eps = 1e-6 stays far below every p_n (≥ 0.2), so no weight crosses its kink at 0
double JacobianError(const Fixture& f) {
  return testing::JacobianError(
      [&f](const VectorXd& z, VectorXd* F, Eigen::MatrixXd* J) {
        EvaluateMultiPatch(f.problem, f.layout, z, F, J);
      },
      f.z);
}

TEST(MultiPatchJacobianTest, FourFeetFlat) {
  EXPECT_LT(JacobianError(MakeFixture(Eigen::Quaterniond::Identity(), 1)), kJacobianTolerance);
}

TEST(MultiPatchJacobianTest, FourFeetTilted) {
  const Eigen::Quaterniond Q(Eigen::AngleAxisd(0.3, Vector3d(1, 2, 0.5).normalized()));
  EXPECT_LT(JacobianError(MakeFixture(Q, 2)), kJacobianTolerance);
}

TEST(MultiPatchJacobianTest, FourFeetInThePlaneForm) {
  // the model's layout: 5 unknowns a foot fewer than the general form's, the same Jacobian check
  const Fixture general = MakeFixture(Eigen::Quaterniond::Identity(), 5);
  const Eigen::Quaterniond Q(Eigen::AngleAxisd(0.3, Vector3d(1, 2, 0.5).normalized()));
  for (const Fixture& f :
       {MakeFixture(Eigen::Quaterniond::Identity(), 5, true), MakeFixture(Q, 6, true)}) {
    EXPECT_EQ(f.layout.size, general.layout.size - 5 * 4);
    EXPECT_LT(JacobianError(f), kJacobianTolerance);
  }
}

TEST(MultiPatchJacobianTest, FrictionRowsDifferFromTheHullModels) {
  // the replaced rows really are the multi-patch friction: with the parts' ECPs apart, the
  // sliding velocity at the combined ECP differs from each part's own
  const Fixture f = MakeFixture(Eigen::Quaterniond::Identity(), 3);
  VectorXd F_patch, F_hull;
  EvaluateMultiPatch(f.problem, f.layout, f.z, &F_patch, nullptr);
  EvaluateMncp(f.problem.body, f.layout, f.z, &F_hull, nullptr);
  const MncpLayout::Contact& L = f.layout.contacts[0];
  constexpr double kDifferent = 1e-3;  // far above the rows' round-off
  EXPECT_GT(std::abs(F_patch[L.p_t] - F_hull[L.p_t]), kDifferent);
  // every other row is the hull model's
  for (int i = 0; i < f.layout.size; ++i) {
    bool friction_row = false;
    for (const MncpLayout::Contact& C : f.layout.contacts)
      friction_row |= i == C.p_t || i == C.p_o || i == C.p_r || i == C.sigma;
    if (!friction_row) {
      EXPECT_EQ(F_patch[i], F_hull[i]) << "row " << i;
    }
  }
}

TEST(MultiPatchJacobianTest, ProximalTermsAreTheStatedEntries) {
  // AddProximalTerms adds ecp_damping (I − n nᵀ) at (cone rows, a1) and load_damping at
  // (gap row, p_n) of every block of a group of several parts, and nothing else
  Fixture f = MakeFixture(Eigen::Quaterniond::Identity(), 4);
  f.problem.ecp_damping = 0.3;
  f.problem.load_damping = 0.7;
  VectorXd F;
  Eigen::MatrixXd J, J_damped;
  EvaluateMultiPatch(f.problem, f.layout, f.z, &F, &J);
  J_damped = J;
  AddProximalTerms(f.problem, f.layout, J_damped);
  Eigen::MatrixXd expected = Eigen::MatrixXd::Zero(J.rows(), J.cols());
  const Eigen::Matrix3d along = Eigen::Vector3d(1, 1, 0).asDiagonal();  // the ground's n = z
  for (const MncpLayout::Contact& L : f.layout.contacts) {
    expected.block<3, 3>(L.a2, L.a1) = 0.3 * along;
    expected(L.p_n, L.p_n) = 0.7;
  }
  EXPECT_EQ(J_damped - J, expected);

  // in the plane form the cone rows are a1's
  const Fixture plane = MakeFixture(Eigen::Quaterniond::Identity(), 4, true);
  MultiPatchProblem damped = plane.problem;
  damped.ecp_damping = 0.3;
  damped.load_damping = 0.7;
  EvaluateMultiPatch(damped, plane.layout, plane.z, &F, &J);
  J_damped = J;
  AddProximalTerms(damped, plane.layout, J_damped);
  expected.setZero(J.rows(), J.cols());
  for (const MncpLayout::Contact& L : plane.layout.contacts) {
    expected.block<3, 3>(L.a1, L.a1) = 0.3 * along;
    expected(L.p_n, L.p_n) = 0.7;
  }
  EXPECT_EQ(J_damped - J, expected);

  // a group of one part is the hull model's contact (isolated solutions): nothing is added
  for (size_t i = 0; i < f.problem.group.size(); ++i) f.problem.group[i] = static_cast<int>(i);
  f.problem.num_groups = static_cast<int>(f.problem.group.size());
  EvaluateMultiPatch(f.problem, f.layout, f.z, &F, &J);
  J_damped = J;
  AddProximalTerms(f.problem, f.layout, J_damped);
  EXPECT_EQ(J_damped, J);
}

TEST(MultiPatchModelTest, NewtonConvergesOnTheDeskAsOnTheHullModel) {
  // the desk's multi-patch solutions are not isolated (where each flat foot's ECP lies on its
  // face and how the four feet share the load are not determined); with the proximal terms
  // (engine/README.md, "Non-isolated solutions") Newton takes the hull model's number of
  // iterations from the warm start, as at an isolated solution (without them: 16.7 per step on
  // average against the hull model's 3.0, one step 1,623). Both models start the desk's steps
  // balanced (engine/README.md, "Balanced starts", and multipatch_balance.h): one iteration a
  // step at most, none where the polished start solves the step already. The multi-patch model
  // balances only its warm starts, so its first step, from the sliding guess, takes as many as
  // before (6, the hull model's first 3)
  constexpr int kBalancedStepIterations = 1;  // a Newton step from a start balanced, not polished
  constexpr int kFirstStepExtra = 4;          // the unbalanced first step's 3 more, one to spare
  const Scene hull_scene = PaperDesk(ContactModel::kHull);
  const Scene patch_scene = PaperDesk(ContactModel::kMultiPatch);
  State hull = InitialState(hull_scene), patch = InitialState(patch_scene);
  int hull_sum = 0, patch_sum = 0, hull_max = 0, patch_first = 0, patch_max_warm = 0;
  for (int i = 0; i < 400; ++i) {
    const StepReport hull_report = Step(hull_scene, hull);
    const StepReport patch_report = Step(patch_scene, patch);
    ASSERT_TRUE(patch_report.converged) << "t = " << patch.t;
    ASSERT_EQ(patch_report.retries, 0) << "t = " << patch.t;
    hull_sum += hull_report.iterations;
    patch_sum += patch_report.iterations;
    hull_max = std::max(hull_max, hull_report.iterations);
    if (i == 0) {
      patch_first = patch_report.iterations;
    } else {
      patch_max_warm = std::max(patch_max_warm, patch_report.iterations);
    }
  }
  std::printf(
      "desk, Newton iterations per step: multipatch mean %.3f first %d then at most %d, "
      "hull mean %.3f max %d\n",
      patch_sum / 400.0, patch_first, patch_max_warm, hull_sum / 400.0, hull_max);
  EXPECT_LE(patch_max_warm, kBalancedStepIterations);
  EXPECT_LE(patch_first, hull_max + kFirstStepExtra);
}

TEST(MultiPatchModelTest, AgreesWithTheHullModelOnThePaperDesk) {
  // the paper's claim: |Δv_x|, |Δω_z| < 1e-8 between the hull-ECP and multi-patch models. Both
  // give the same total wrench about the same combined ECP (engine/README.md, "The multi-patch
  // model"), so they agree to the solver tolerance (1e-12) and the combined ECP's weight floor
  // (1e-12 of the impulse scale) times the steps' amplification; measured 1.8e-12 m/s and
  // 3.9e-11 rad/s, the ECPs 5.1e-12 m apart (where in the solution set the balanced warm starts
  // land sets how the weight floor weighs the feet)
  const Scene hull_scene = PaperDesk(ContactModel::kHull);
  const Scene patch_scene = PaperDesk(ContactModel::kMultiPatch);
  State hull = InitialState(hull_scene), patch = InitialState(patch_scene);
  double max_dv = 0, max_dw = 0, max_da = 0;
  for (int i = 0; i < 400; ++i) {
    ASSERT_TRUE(Step(hull_scene, hull).converged);
    const StepReport rep = Step(patch_scene, patch);
    ASSERT_TRUE(rep.converged) << "t = " << patch.t;
    // a sub-stepped step would differ from the hull model's full step by O(h²)
    ASSERT_EQ(rep.substeps, 1) << "t = " << patch.t;
    max_dv = std::max(max_dv, std::abs(hull.bodies[0].v_WB.x() - patch.bodies[0].v_WB.x()));
    max_dw = std::max(max_dw, std::abs(hull.bodies[0].w_WB.z() - patch.bodies[0].w_WB.z()));
    max_da = std::max(max_da, (hull.contacts[0].a1 - patch.contacts[0].a1).norm());
    // the desk stays on the ground
    ASSERT_NEAR(patch.bodies[0].p_WB.z(), 0.45, kSolverTolerance);
  }
  RecordProperty("max_dv", std::to_string(max_dv));
  RecordProperty("max_dw", std::to_string(max_dw));
  std::printf(
      "desk, multipatch vs hull: max |dv_x| = %.3g m/s, max |dw_z| = %.3g rad/s, "
      "max |da1| = %.3g m\n",
      max_dv, max_dw, max_da);
  EXPECT_LT(max_dv, kModelAgreement);
  EXPECT_LT(max_dw, kModelAgreement);
  // the combined ECP is the hull model's ECP
  EXPECT_LT(max_da, kModelAgreement);
  // the desk really moved and turned
  EXPECT_GT(patch.bodies[0].p_WB.head<2>().norm(), 0.5);
}

TEST(MultiPatchModelTest, WithoutPartsItIsTheHullModel) {
  // one part (the hull): the combined ECP is the part's ECP, p_rE = p_r, and the friction rows
  // are the hull model's; a box dropped tilted onto the ground, tipping and settling, follows
  // the same trajectory up to the solver tolerance's effect
  Body box = testing::MakeBoxBody(Vector3d(0.3, 0.2, 0.1), 2);
  box.p0 = Vector3d(0, 0, 0.3);
  box.q0 = Eigen::Quaterniond(Eigen::AngleAxisd(0.4, Vector3d(1, 1, 0).normalized()));
  box.v0 = Vector3d(0.5, 0, 0);
  box.w0 = Vector3d(0, 0, 2);
  Scene hull_scene = testing::MakeGroundScene({box});
  Scene patch_scene = hull_scene;
  patch_scene.model = ContactModel::kMultiPatch;
  State hull = InitialState(hull_scene), patch = InitialState(patch_scene);
  double max_dv = 0;
  for (int i = 0; i < 100; ++i) {
    Step(hull_scene, hull);
    Step(patch_scene, patch);
    max_dv = std::max(max_dv, (hull.bodies[0].v_WB - patch.bodies[0].v_WB).norm());
  }
  // 1e-12 tolerance per step; impacts amplify differences, 1e-8 leaves margin
  EXPECT_LT(max_dv, kModelAgreement);
  // it hit the ground and stopped bouncing
  EXPECT_GT(patch.contacts[0].p_n, 0);
}

TEST(MultiPatchModelTest, RejectsAnObstacleThatIsNotAPlane) {
  Body box = testing::MakeBoxBody(Vector3d(0.3, 0.2, 0.1), 2);
  box.p0 = Vector3d(0, 0, 0.5);
  Scene scene = testing::MakeGroundScene({box});
  Obstacle block;
  block.name = "block";
  block.shape = geometry::MakeBox(Vector3d(0.1, 0.1, 0.1));
  scene.obstacles.push_back(block);
  scene.contacts.push_back(ContactPair{0, 1, testing::PaperFriction()});
  scene.model = ContactModel::kMultiPatch;
  State state = InitialState(scene);
  EXPECT_THAT([&] { Step(scene, state); }, ::testing::ThrowsMessage<ModelInvalid>(
                                               HasSubstr("'block', which is not a half-space")));
}

// a scene file named for the running test (ctest runs tests in parallel), removed at the end
struct TempScene {
  explicit TempScene(const std::string& text) {
    path = std::string(ECPSIM_BINARY_DIR) + "/multipatch_test_" +
           ::testing::UnitTest::GetInstance()->current_test_info()->name() + ".yaml";
    std::ofstream(path) << text;
  }
  ~TempScene() { std::remove(path.c_str()); }
  std::string path;
};

constexpr const char* kBoxScene = R"(
duration: 0.1
model: multipatch
ground: {}
bodies:
  - shape: {box: {size: [0.4, 0.4, 0.2]}}
    mass: 2
    on_ground: true
    parts:
      - box: {size: [0.1, 0.1, 0.2]}
        at: [-0.15, -0.15, 0]
      - box: {size: [0.1, 0.1, 0.2]}
        at: [0.15, 0.15, 0]
        rpy: [0, 0, 0]
)";

TEST(MultiPatchSceneTest, ReadsPartsAndTheModel) {
  const TempScene file(kBoxScene);
  const Scene scene = LoadScene(file.path).scene;
  EXPECT_EQ(scene.model, ContactModel::kMultiPatch);
  ASSERT_EQ(scene.bodies[0].parts.size(), 2u);
  // the second part's corner (0.2, 0.2, −0.1) in the CM frame, the body's own corner
  EXPECT_NEAR(
      (scene.bodies[0].parts[1]->Support(Vector3d(1, 1, -1)) - Vector3d(0.2, 0.2, -0.1)).norm(),
      0.0, kUnitRoundOff);
  // resting on two parts: they carry the weight equally, by symmetry
  State state = InitialState(scene);
  ASSERT_EQ(state.contacts.size(), 1u);
  for (int i = 0; i < 10; ++i) Step(scene, state);
  EXPECT_NEAR(state.contacts[0].p_n, 2 * 9.8 * 0.01, kSolverTolerance);
  EXPECT_NEAR(state.bodies[0].p_WB.z(), 0.1, kSolverTolerance);
  // m: the combined ECP at the centre by symmetry; the parts' shares, solved to the tolerance,
  // move it by far less
  constexpr double kCentredEcp = 1e-9;
  EXPECT_NEAR(state.contacts[0].a1.head<2>().norm(), 0.0, kCentredEcp);
}

TEST(MultiPatchSceneTest, RejectsAPartOutsideTheBody) {
  std::string text = kBoxScene;
  text.replace(text.find("at: [0.15, 0.15, 0]"), 19, "at: [0.25, 0.15, 0]");
  const TempScene file(text);
  EXPECT_THAT([&] { LoadScene(file.path); },
              ::testing::ThrowsMessage<InputError>(
                  HasSubstr("bodies[0].parts[1] = {box: {size: [0.1, 0.1, 0.2]}, at: [0.25, 0.15, "
                            "0], rpy: ...: expected a part inside the body; its corner (0.3, 0.1, "
                            "-0.1) m (mesh frame) lies 0.1 m outside")));
}

// a 0.3 × 0.2 × 0.5 m block standing on two 0.05 m wide legs at its ends (parts), pushed at the
// top edge for 0.3 s: it tips onto one leg's edge, leaves the ground, lands on its side and comes
// to rest, through one-part, two-part, no-part and side contact
constexpr const char* kTippingScene = R"yaml(
duration: 1.0
ground: {friction: {mu: 0.6, e_t: 1, e_o: 1, e_r: 0.1}}
bodies:
  - name: stool
    shape: {box: {size: [0.3, 0.2, 0.5]}}
    mass: 2
    on_ground: true
    parts:
      - {box: {size: [0.05, 0.2, 0.5]}, at: [-0.125, 0, 0]}
      - {box: {size: [0.05, 0.2, 0.5]}, at: [0.125, 0, 0]}
loads:
  - force: ["12*(t<0.3)", 0, 0]
    at: [-0.15, 0, 0.25]
)yaml";

TEST(MultiPatchModelTest, TippingAndLandingMatchTheHullModel) {
  // the union of the two legs has the block's hull as its convex hull, so the wrench argument of
  // engine/README.md holds in every contact mode; measured max difference 2.2e-9 (the landing
  // impact amplifies the 1e-12 solver tolerance), asserted with a 4× margin
  const TempScene file(kTippingScene);
  const Scene hull_scene = LoadScene(file.path).scene;
  const Scene patch_scene = LoadScene(file.path, {"model=multipatch"}).scene;
  State hull = InitialState(hull_scene), patch = InitialState(patch_scene);
  double max_dv = 0, max_tilt = 0;
  bool lifted_off = false;
  for (int i = 0; i < 100; ++i) {
    ASSERT_EQ(Step(hull_scene, hull).substeps, 1);
    ASSERT_EQ(Step(patch_scene, patch).substeps, 1);
    max_dv = std::max({max_dv, (hull.bodies[0].v_WB - patch.bodies[0].v_WB).norm(),
                       (hull.bodies[0].w_WB - patch.bodies[0].w_WB).norm()});
    max_tilt = std::max(max_tilt, std::abs(patch.bodies[0].w_WB.y()));
    lifted_off |= patch.contacts[0].p_n == 0;
  }
  EXPECT_LT(max_dv, kModelAgreement);
  EXPECT_TRUE(lifted_off);
  // it ends on its side: the CM at half the 0.3 m width, to the solver's precision after the
  // landing
  constexpr double kOnItsSide = 1e-9;  // m
  EXPECT_NEAR(patch.bodies[0].p_WB.z(), 0.15, kOnItsSide);
  EXPECT_GT(max_tilt, 5.0);  // rad/s while it falls
}

TEST(MultiPatchSceneTest, ShippedDeskHasItsFourFeetAsParts) {
  const Scene scene = LoadScene(std::string(ECPSIM_SOURCE_DIR) + "/scenes/desk.yaml").scene;
  const Body& desk = scene.bodies[0];
  ASSERT_EQ(desk.parts.size(), 4u);
  // each leg's bottom is the hull's bottom (the feet on z = 0 in the mesh frame; the OBJ file's
  // single-precision rounding is 1.4e-8 m), and its footprint is 0.06 × 0.06 m at a corner
  const double bottom = desk.hull->Support(-Vector3d::UnitZ()).z();
  constexpr double kObjRounding = 1e-7;     // m, over the file's 1.4e-8 m
  constexpr double kWidthRoundOff = 1e-12;  // m, a difference of two part-box coordinates
  for (const auto& part : desk.parts) {
    const Vector3d low = part->Support(Vector3d(-1e-3, -1e-3, -1));
    const Vector3d high = part->Support(Vector3d(1e-3, 1e-3, -1));
    EXPECT_NEAR(low.z(), bottom, kObjRounding);
    EXPECT_NEAR(high.x() - low.x(), 0.06, kWidthRoundOff);
    EXPECT_NEAR(high.y() - low.y(), 0.06, kWidthRoundOff);
    // centred at x, y = ±0.22 m; the CM is at x = y = 0 up to the OBJ file's rounding
    EXPECT_NEAR(std::abs(0.5 * (high.x() + low.x())), 0.22, kObjRounding);
    EXPECT_NEAR(std::abs(0.5 * (high.y() + low.y())), 0.22, kObjRounding);
  }
}

}  // namespace
}  // namespace ecpsim::engine
