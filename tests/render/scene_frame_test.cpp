// Frames from an engine scene and state: poses, patches against the plane obstacle, ECP, force.

#include <cmath>
#include <cstring>
#include <filesystem>
#include <memory>
#include <string>
#include <vector>

#include <fmt/format.h>
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include "common/errors.h"
#include "engine/scene.h"
#include "engine/scene_io/scene_builders.h"
#include "engine/scene_io/scene_yaml.h"
#include "engine/state.h"
#include "engine/time_step.h"
#include "geometry/convex_hull.h"
#include "geometry/convex_shape.h"
#include "geometry/mass_properties.h"
#include "geometry/paper_bodies.h"
#include "render/image_compare.h"
#include "render/png_writer.h"
#include "render/renderer.h"
#include "render/scene_frame.h"

namespace ecpsim::render {
namespace {

using ::testing::HasSubstr;
using ::testing::ThrowsMessage;

constexpr double kMass = 15;  // kg, the paper's desk
constexpr double kH = 0.01;   // s
// m or m²: what a solved resting pose fixes (a patch's area, the ECP in its hull), to the
// solver's precision of O(1) lengths, with margin
constexpr double kSolvedPose = 1e-9;

// the desk (scaled by `scale`) with its body frame at the centre of mass, on the ground z = 0
engine::Scene DeskScene(double scale = 1) {
  geometry::TriangleMesh mesh = geometry::MakeDeskMesh();
  for (auto& v : mesh.vertices) v *= scale;
  const Eigen::Vector3d cm = geometry::ComputeMassProperties(mesh, 1000).center_of_mass;
  for (auto& v : mesh.vertices) v -= cm;
  engine::Scene scene;
  scene.source = "desk.yaml";
  scene.h = kH;
  engine::Body body;
  body.name = "desk";
  body.hull =
      std::make_shared<geometry::PolyhedralShape>(geometry::ComputeConvexHull(mesh.vertices));
  body.mesh = std::move(mesh);
  body.mass = kMass;
  body.p0 = cm;
  scene.bodies.push_back(std::move(body));
  engine::Obstacle ground;
  ground.name = "ground";
  ground.shape = geometry::MakeHalfSpace(Eigen::Vector3d::UnitZ(), 0);
  scene.obstacles.push_back(ground);
  scene.contacts.push_back(engine::ContactPair{0, 0, {}});
  return scene;
}

// resting: weight carried by the ECP at the centre, p_n = m g h
engine::State RestingState(const engine::Scene& scene) {
  engine::State state;
  state.t = 0.25;
  engine::BodyState body;
  body.p_WB = scene.bodies[0].p0;
  state.bodies.push_back(body);
  engine::ContactState contact;
  contact.a1 = Eigen::Vector3d(body.p_WB.x(), body.p_WB.y(), 0);
  contact.a2 = contact.a1;
  contact.p_n = kMass * 9.8 * kH;
  state.contacts.push_back(contact);
  return state;
}

TEST(SceneFrameBuilder, RestingDeskHasFourFeetTheEcpAndItsWeight) {
  const engine::Scene scene = DeskScene();
  const SceneFrameBuilder builder(scene);
  const FrameInput frame = builder.Build(RestingState(scene), 3);
  ASSERT_EQ(frame.bodies.size(), 1u);
  ASSERT_EQ(frame.planes.size(), 1u);
  EXPECT_EQ(frame.planes[0].plane.normal, Eigen::Vector3d::UnitZ());
  EXPECT_EQ(frame.planes[0].plane.offset, 0.0);
  ASSERT_EQ(frame.contacts.size(), 1u);
  const ContactVisual& contact = frame.contacts[0];
  EXPECT_EQ(contact.patch.polygons.size(), 4u);
  ASSERT_TRUE(contact.cm_projection && contact.a1 && contact.force);
  // the CM lies above the centre of the feet: its projection is (x, y, 0) of p_WB, to round-off
  constexpr double kProjectionRoundOff = 1e-12;  // m
  EXPECT_NEAR(
      (*contact.cm_projection - Eigen::Vector3d(scene.bodies[0].p0.x(), scene.bodies[0].p0.y(), 0))
          .norm(),
      0, kProjectionRoundOff);
  // p_n / h = m g = 147 N straight up; N, the state's p_n divided by h
  constexpr double kForceRoundOff = 1e-9;
  EXPECT_NEAR((*contact.force - Eigen::Vector3d(0, 0, kMass * 9.8)).norm(), 0, kForceRoundOff);
  EXPECT_EQ(frame.iterations, 3);
  EXPECT_DOUBLE_EQ(frame.time, 0.25);
  EXPECT_GT(frame.force_scale, 0);
}

// Bodies on bodies: scenes/stack.yaml's boxes at rest show, for each pair, the upper box's
// bottom where the lower box's top reaches — the whole 0.2 m and 0.1 m squares, each box being
// the smaller — with the ECP in it and the weight above it as the force
TEST(SceneFrameBuilder, AStackShowsEachBoxsFaceOnTheOneBelow) {
  const engine::Scene scene =
      engine::LoadScene(std::string(ECPSIM_SOURCE_DIR) + "/scenes/stack.yaml").scene;
  engine::State state = engine::InitialState(scene);
  for (int k = 0; k < 5; ++k) engine::Step(scene, state);
  const SceneFrameBuilder builder(scene);
  const FrameInput frame = builder.Build(state, 0);
  int body_pairs = 0;
  for (size_t k = 0; k < scene.contacts.size(); ++k) {
    const engine::ContactPair& pair = scene.contacts[k];
    if (!pair.WithBody() || state.contacts[k].p_n == 0) continue;
    ++body_pairs;
    const ContactVisual& contact = frame.contacts[k];
    // the upper box of the pair is the smaller: its bottom face, 0.2 m or 0.1 m square
    const int upper = scene.bodies[pair.body].p0.z() > scene.bodies[pair.other_body].p0.z()
                          ? pair.body
                          : pair.other_body;
    const double side = upper == 1 ? 0.2 : 0.1;
    EXPECT_EQ(contact.patch.mode, geometry::ContactMode::kConvexPatch) << k;
    EXPECT_NEAR(contact.patch.area, side * side, kSolvedPose) << k;
    ASSERT_TRUE(contact.a1 && contact.force) << k;
    EXPECT_TRUE(geometry::PatchHullContains(contact.patch, contact.plane, *contact.a1, kSolvedPose))
        << k;
    // the weight of what rests on this face (top 1 kg, middle + top 3 kg), after 5 steps of
    // settling: N, the solver's share between the stacked contacts with margin
    constexpr double kStackForce = 1e-6;
    const double above = upper == 1 ? 3 : 1;
    EXPECT_NEAR(std::abs(contact.force->z()), above * 9.8, kStackForce) << k;
  }
  EXPECT_EQ(body_pairs, 2);
}

TEST(SceneFrameBuilder, SeparatedContactShowsNoEcp) {
  const engine::Scene scene = DeskScene();
  engine::State state = RestingState(scene);
  state.bodies[0].p_WB.z() += 0.1;  // lifted 10 cm
  state.contacts[0].p_n = 0;
  const FrameInput frame = SceneFrameBuilder(scene).Build(state);
  EXPECT_EQ(frame.contacts[0].patch.mode, geometry::ContactMode::kNone);
  EXPECT_FALSE(frame.contacts[0].a1.has_value());
  EXPECT_FALSE(frame.contacts[0].force.has_value());
}

TEST(SceneFrameBuilder, MismatchedStateIsAnInputError) {
  const engine::Scene scene = DeskScene();
  engine::State state = RestingState(scene);
  state.contacts.clear();
  EXPECT_THAT(
      [&] { SceneFrameBuilder(scene).Build(state); },
      ThrowsMessage<InputError>(HasSubstr("desk.yaml: state with 1 bodies and 0 contacts")));
}

// Bit-for-bit equality of two body states (positions, orientations, velocities).
bool BitIdentical(const engine::BodyState& a, const engine::BodyState& b) {
  const auto same = [](const double* x, const double* y, size_t n) {
    return std::memcmp(x, y, n * sizeof(double)) == 0;
  };
  return same(a.p_WB.data(), b.p_WB.data(), 3) &&
         same(a.Q_WB.coeffs().data(), b.Q_WB.coeffs().data(), 4) &&
         same(a.v_WB.data(), b.v_WB.data(), 3) && same(a.w_WB.data(), b.w_WB.data(), 3);
}

// Bug: the frame builder asks the body's hull for its support point (PatchTolerance), and the
// hull is the engine's. Frames built between steps must leave every step bit-identical: the
// T-bar of scenes/tbar.yaml through its first wobble (it lies flat, tilts onto the edge B+C+ and
// rocks; the run that first differed did so at t = 1.38 s).
TEST(SceneFrameBuilder, BuildingFramesBetweenStepsLeavesEveryStepBitIdentical) {
  constexpr int kSteps = 145;  // to t = 1.45 s at h = 0.01 s
  // two loads: each run has hulls of its own
  const engine::Scene plain_scene = engine::LoadScene(ECPSIM_SOURCE_DIR "/scenes/tbar.yaml").scene;
  const engine::Scene scene = engine::LoadScene(ECPSIM_SOURCE_DIR "/scenes/tbar.yaml").scene;
  const SceneFrameBuilder builder(scene);
  engine::State plain = engine::InitialState(plain_scene);
  engine::State framed = engine::InitialState(scene);
  int frames_with_a_patch = 0;
  for (int k = 1; k <= kSteps; ++k) {
    engine::Step(plain_scene, plain);
    engine::Step(scene, framed);
    const FrameInput frame = builder.Build(framed);
    if (!frame.contacts[0].patch.points.empty() || !frame.contacts[0].patch.polygons.empty()) {
      ++frames_with_a_patch;
    }
    ASSERT_TRUE(BitIdentical(plain.bodies[0], framed.bodies[0])) << "step " << k;
  }
  EXPECT_EQ(frames_with_a_patch, kSteps);  // in contact all along: every frame asked the hull
}

TEST(SceneFrameBuilder, EcpMarkerLandsOnItsProjectedPixel) {
  // the ECP's red disc (5 px radius) is drawn last over everything: the pixel containing the
  // projected ECP is exactly the marker colour (0.90, 0, 0) → (230, 0, 0)
  const engine::Scene scene = DeskScene();
  const FrameInput frame = SceneFrameBuilder(scene).Build(RestingState(scene));
  RenderSettings settings;
  settings.width = 160;
  settings.height = 120;
  Renderer renderer(settings);
  const Image image = renderer.Render(frame);
  Eigen::Vector3d pixel;
  ASSERT_TRUE(renderer.FrameCamera(frame).ToPixel(*frame.contacts[0].a1, &pixel));
  const int x = static_cast<int>(pixel.x()), y = static_cast<int>(pixel.y());
  ASSERT_TRUE(x >= 0 && x < 160 && y >= 0 && y < 120);
  EXPECT_EQ(image.Pixel(x, y)[0], 230);
  EXPECT_EQ(image.Pixel(x, y)[1], 0);
  EXPECT_EQ(image.Pixel(x, y)[2], 0);
}

}  // namespace
}  // namespace ecpsim::render

namespace ecpsim::render {
namespace {

// the dumbbell (a 96-gon mesh) whose declared hull is the exact cylinder R = 0.1, L = 0.3
engine::Scene DumbbellOnItsSide() {
  engine::Scene scene = DeskScene();
  engine::Body& body = scene.bodies[0];
  body.name = "dumbbell";
  body.mesh = geometry::MakeDumbbellMesh();  // centred at its CM, axis x
  body.hull = geometry::MakeCylinder(0.1, 0.3, 0);
  body.p0 = Eigen::Vector3d(0, 0, 0.1);  // the cylinder touches the ground along a line
  return scene;
}

TEST(SceneFrameBuilder, TessellatedMeshUnderAPrimitiveHullShowsItsLowestFeatures) {
  // rolled by half a segment, a flat facet of each rim faces down, R (1 − cos(π/96)) = 5.4e-5 m
  // above the ground where the cylinder touches: that gap, not the plain 1e-6 m tolerance,
  // decides which mesh features carry the contact — the two rim facets
  const engine::Scene scene = DumbbellOnItsSide();
  engine::State state = RestingState(scene);
  state.bodies[0].Q_WB = Eigen::Quaterniond(Eigen::AngleAxisd(M_PI / 96, Eigen::Vector3d::UnitX()));
  const FrameInput frame = SceneFrameBuilder(scene).Build(state);
  const geometry::ContactPatch& patch = frame.contacts[0].patch;
  EXPECT_EQ(patch.mode, geometry::ContactMode::kNonConvexPatch);
  EXPECT_EQ(patch.polygons.size(), 2u);
  constexpr double kFacetAreaRoundOff = 1e-9;  // m²: round-off of the facets' 1.96e-3 m², with room
  EXPECT_NEAR(patch.area, 0.3 * 2 * 0.1 * std::sin(M_PI / 96), kFacetAreaRoundOff);
}

TEST(SceneFrameBuilder, PolyhedralHullKeepsThePlainTolerance) {
  // the desk (bounding-box diagonal 0.91 m) lifted by 2 µm: above the tolerance of 1e-6
  // diagonals, no
  // contact; lifted by 0.2 µm: its four feet. The same at a thousandth and a thousand times the
  // size (a fixed 1 µm made a lifted millimetre desk touch)
  for (double scale : {1e-3, 1.0, 1e3}) {
    const engine::Scene scene = DeskScene(scale);
    for (double lift : {2e-6, 0.2e-6}) {
      engine::State state = RestingState(scene);
      state.bodies[0].p_WB.z() += lift * scale;
      const FrameInput frame = SceneFrameBuilder(scene).Build(state);
      const bool above = lift > geometry::kContactPatchRelTolerance;
      EXPECT_EQ(frame.contacts[0].patch.polygons.size(), above ? 0u : 4u)
          << "scale " << scale << ", lifted " << lift * scale << " m";
    }
  }
}

// ---- scale: a scene in millimetres or kilometres is drawn like one in metres ----

// the golden tests' tolerance (renderer_golden_test.cpp explains the numbers)
const CompareTolerance kGoldenTolerance{24, 0.0005};
constexpr int kWidth = 320, kHeight = 240;  // pixels, the goldens' size and supersampling
constexpr double kSupersample = 2;

// A box of sides (1, 0.6, 0.4) × L, density 1000 kg/m³, tipped 25° about x onto a long edge
// (a line contact), with its ECP on that edge carrying its weight and a sideways push: patch,
// ECP, centre-of-mass ring, force arrow, hull and ground all in view.
struct TippedBox {
  engine::Scene scene;
  engine::State state;
};

TippedBox MakeTippedBox(double L) {
  constexpr double kDensity = 1000;  // kg/m³
  constexpr double kG = 9.8;         // m/s²
  const Eigen::Vector3d size = L * Eigen::Vector3d(1, 0.6, 0.4);
  engine::Body body = engine::MakeBoxBody(size, kDensity * size.prod(), "box");
  engine::BodyState pose;
  pose.Q_WB = Eigen::Quaterniond(Eigen::AngleAxisd(25 * M_PI / 180, Eigen::Vector3d::UnitX()));
  double lowest = 0;
  for (const Eigen::Vector3d& v : body.mesh.vertices)
    lowest = std::min(lowest, (pose.Q_WB * v).z());
  pose.p_WB = Eigen::Vector3d(0.1 * L, -0.05 * L, -lowest);
  // the scene starts at that pose, on the ground
  body.q0 = pose.Q_WB;
  body.p0 = pose.p_WB;
  TippedBox box;
  box.scene = engine::MakeGroundScene({body}, kH, engine::Friction{});
  box.state = engine::InitialState(box.scene);
  box.state.bodies[0] = pose;
  engine::ContactState& contact = box.state.contacts[0];
  const Eigen::Vector3d on_edge =
      pose.p_WB + pose.Q_WB * (0.5 * size.cwiseProduct(Eigen::Vector3d(0.4, -1, -1)));
  contact.a1 = Eigen::Vector3d(on_edge.x(), on_edge.y(), 0);
  contact.a2 = contact.a1;
  contact.p_n = body.mass * kG * kH;  // N·s: the weight over one step
  contact.p_t = 0.3 * contact.p_n;
  return box;
}

// The inset's last row holds the scale bar's label, the one text that prints a length: blanked
// in both images. The inset is 0.42 of the height square, 8 pixels from the top-right corner
// (draw_contact_overlay.cpp); its label row is the bottom 18 pixels of it at 240 rows.
void BlankScaleBarLabel(Image& image) {
  const int side = static_cast<int>(std::lround(0.42 * image.height));
  const int right = image.width - 8, bottom = 8 + side;
  for (int y = bottom - 18; y < bottom; ++y) {
    for (int x = right - side; x < right; ++x) {
      std::uint8_t* p = image.Pixel(x, y);
      p[0] = p[1] = p[2] = 0;
    }
  }
}

class ScaleFreeFrames : public ::testing::TestWithParam<bool> {
 protected:
  static void SetUpTestSuite() {
    RenderSettings settings;
    settings.width = kWidth;
    settings.height = kHeight;
    settings.supersample = kSupersample;
    renderer_ = std::make_unique<Renderer>(settings);
  }
  static void TearDownTestSuite() { renderer_.reset(); }

  // the frame of the box of size L, automatic camera or a fixed one (scaled with L)
  Image Render(double L) {
    const TippedBox box = MakeTippedBox(L);
    FrameInput frame = SceneFrameBuilder(box.scene).Build(box.state, 7);
    if (!GetParam()) {
      frame.camera.automatic = false;
      frame.camera.position = L * Eigen::Vector3d(1.4, -2.2, 1.3);
      frame.camera.target = L * Eigen::Vector3d(0.1, 0, 0.1);
    }
    Image image = renderer_->Render(frame);
    const std::string dir = std::string(ECPSIM_BINARY_DIR) + "/tests/render/scale_output";
    std::filesystem::create_directories(dir);
    WritePng(fmt::format("{}/box_{}_{:g}.png", dir, GetParam() ? "auto" : "fixed", L), image);
    return image;
  }

  static std::unique_ptr<Renderer> renderer_;
};
std::unique_ptr<Renderer> ScaleFreeFrames::renderer_;

TEST_P(ScaleFreeFrames, MillimetreAndKilometreBoxesLookLikeTheMetreBox) {
  Image metre = Render(1);
  BlankScaleBarLabel(metre);
  for (double L : {1e-3, 1e3}) {
    Image scaled = Render(L);
    BlankScaleBarLabel(scaled);
    const ImageComparison comparison = CompareImages(metre, scaled, kGoldenTolerance);
    EXPECT_TRUE(comparison.match) << "L = " << L << " m: " << comparison.Summary(kGoldenTolerance);
  }
}

INSTANTIATE_TEST_SUITE_P(Camera, ScaleFreeFrames, ::testing::Bool(),
                         [](const ::testing::TestParamInfo<bool>& param_info) {
                           return std::string(param_info.param ? "Automatic" : "Fixed");
                         });

}  // namespace
}  // namespace ecpsim::render
