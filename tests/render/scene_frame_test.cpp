// Frames from an engine scene and state: poses, patches against the plane obstacle, ECP, force.

#include <cmath>
#include <memory>

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include "engine/scene.h"
#include "engine/state.h"
#include "geometry/convex_hull.h"
#include "geometry/convex_shape.h"
#include "common/errors.h"
#include "geometry/mass_properties.h"
#include "geometry/paper_bodies.h"
#include "render/renderer.h"
#include "render/scene_frame.h"

namespace ecpsim::render {
namespace {

using ::testing::HasSubstr;
using ::testing::ThrowsMessage;

constexpr double kMass = 15;  // kg, the paper's desk
constexpr double kH = 0.01;   // s

// the desk with its body frame at the centre of mass, on the ground z = 0
engine::Scene DeskScene() {
  geometry::TriangleMesh mesh = geometry::MakeDeskMesh();
  const Eigen::Vector3d cm = geometry::ComputeMassProperties(mesh, 1000).center_of_mass;
  for (auto& v : mesh.vertices) v -= cm;
  engine::Scene scene;
  scene.source = "desk.yaml";
  scene.h = kH;
  engine::Body body;
  body.name = "desk";
  body.hull = std::make_shared<geometry::PolyhedralShape>(geometry::ComputeConvexHull(mesh.vertices));
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
  // the CM lies above the centre of the feet: its projection is (x, y, 0) of p_WB
  EXPECT_NEAR((*contact.cm_projection - Eigen::Vector3d(scene.bodies[0].p0.x(),
                                                        scene.bodies[0].p0.y(), 0)).norm(),
              0, 1e-12);
  // p_n / h = m g = 147 N straight up
  EXPECT_NEAR((*contact.force - Eigen::Vector3d(0, 0, kMass * 9.8)).norm(), 0, 1e-9);
  EXPECT_EQ(frame.iterations, 3);
  EXPECT_DOUBLE_EQ(frame.time, 0.25);
  EXPECT_GT(frame.force_scale, 0);
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
  EXPECT_THAT([&] { SceneFrameBuilder(scene).Build(state); },
              ThrowsMessage<InputError>(HasSubstr("desk.yaml: state with 1 bodies and 0 contacts")));
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
  EXPECT_NEAR(patch.area, 0.3 * 2 * 0.1 * std::sin(M_PI / 96), 1e-9);
}

TEST(SceneFrameBuilder, PolyhedralHullKeepsThePlainTolerance) {
  // the desk lifted by 2 µm: above the 1 µm tolerance, no contact
  const engine::Scene scene = DeskScene();
  engine::State state = RestingState(scene);
  state.bodies[0].p_WB.z() += 2e-6;
  const FrameInput frame = SceneFrameBuilder(scene).Build(state);
  EXPECT_EQ(frame.contacts[0].patch.mode, geometry::ContactMode::kNone);
}

}  // namespace
}  // namespace ecpsim::render
