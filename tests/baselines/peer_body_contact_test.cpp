// The peers (MuJoCo, Bullet, ODE, both settings each) on the scenes with bodies touching bodies
// (issue 13): scenes/stack.yaml for 10 s and scenes/push_box.yaml for 2 s at h = 0.01 s. The
// tests assert what every adapter must do (run without failure, move a kinematic body exactly
// along its prescribed motion, carry the pushed box) and print what
// baselines/README.md tabulates ("Bodies touching bodies"):
//   build/tests/ecpsim_baselines_tests --gtest_filter='PeerBodyContact*'

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "baselines/external_simulation.h"
#include "common/errors.h"
#include "engine/scene_io/scene_yaml.h"

namespace ecpsim::baselines {
namespace {

using Eigen::Vector3d;

constexpr double kG = 9.8;  // m/s², the scenes' |g|
// m: how far a kinematic body may be from its prescribed pose after a step. Bullet sets it
// there and ODE moves it by c + h v with v = (p(t + h) − p(t)) / h (round-off of 0.1 m
// coordinates, 1e-17 m); MuJoCo sets it at the step's start and moves a body 1e6 times heavier
// than the box, whose impulse J moves it by J h / M within the step: measured 2e-9 m at the
// first touch, when the box is set moving
constexpr double kKinematicTrack = 1e-8;
// rad: the same for its orientation; MuJoCo's heavy pusher is turned within the step by the
// box's off-centre impulses, measured 1.7e-7 rad (2e-8 m at its 0.1 m half-width)
constexpr double kKinematicTurn = 1e-6;
// relative: the pushed box's mean speed over the last second within 25 % of the pusher's: every
// peer carries it, its soft contact chattering (MuJoCo's default: mean 0.085 m/s, between
// 0.004 and 0.18 m/s); the chatter, the gaps and the overlaps are printed
constexpr double kPushMeanSpeed = 0.25;
// relative: the pusher's mean force on the box over the last second (ExternalSimulation::
// ContactForce) within 25 % of μ m g: the box's momentum changes by at most m × its speed's
// spread over that second, and the ground's friction on it is μ times a normal force the
// pusher's friction moves by a few per cent (the 3–8 %); a sign or frame error of an
// adapter's force is off by 100 % or more
constexpr double kPushMeanForce = 0.25;

struct Peer {
  ExternalEngine engine;
  FrictionSetting setting;
};

std::string PeerName(const Peer& p) {
  return std::string(ExternalEngineName(p.engine)) +
         (p.setting == FrictionSetting::kDefault ? "-default" : "-coulomb");
}

std::vector<Peer> AvailablePeers() {
  std::vector<Peer> peers;
  for (ExternalEngine e : {ExternalEngine::kMujoco, ExternalEngine::kBullet, ExternalEngine::kOde})
    if (IsAvailable(e))
      for (FrictionSetting s : {FrictionSetting::kDefault, FrictionSetting::kCoulomb})
        peers.push_back({e, s});
  return peers;
}

engine::Scene Scene(const char* file) {
  return engine::LoadScene(std::string(ECPSIM_SOURCE_DIR) + "/scenes/" + file).scene;
}

TEST(PeerBodyContact, StackOfThreeBoxesForTenSeconds) {
  const engine::Scene scene = Scene("stack.yaml");
  const int steps = static_cast<int>(std::lround(scene.duration / scene.h));
  std::printf(
      "peer             first-step drop (mm) bottom/middle/top  top drift 10 s (mm): "
      "horizontal, vertical, max  speed in the last 1 s (m/s)\n");
  for (const Peer& peer : AvailablePeers()) {
    auto sim = MakeExternalSimulation(peer.engine, peer.setting, scene);
    const engine::State start = sim->state();
    double drop[3] = {0, 0, 0}, max_drift = 0, late_speed = 0;
    for (int k = 1; k <= steps; ++k) {
      ASSERT_NO_THROW(sim->Step()) << PeerName(peer) << " step " << k;
      const engine::State& s = sim->state();
      if (k == 1)
        for (int b = 0; b < 3; ++b) drop[b] = start.bodies[b].p_WB.z() - s.bodies[b].p_WB.z();
      max_drift = std::max(max_drift, (s.bodies[2].p_WB - start.bodies[2].p_WB).norm());
      if (s.t > scene.duration - 1)
        for (const engine::BodyState& b : s.bodies)
          late_speed = std::max(late_speed, b.v_WB.norm());
    }
    const Vector3d drift = sim->state().bodies[2].p_WB - start.bodies[2].p_WB;
    std::printf("%-16s %.3f / %.3f / %.3f (g h² = %.3f)  %.2f, %.3f, %.2f  %.3g\n",
                PeerName(peer).c_str(), 1e3 * drop[0], 1e3 * drop[1], 1e3 * drop[2],
                1e3 * kG * scene.h * scene.h, 1e3 * drift.head<2>().norm(), 1e3 * drift.z(),
                1e3 * max_drift, late_speed);
    EXPECT_TRUE(std::isfinite(max_drift)) << PeerName(peer);
  }
}

TEST(PeerBodyContact, FlatPusherAtATenthOfAMeterPerSecond) {
  const engine::Scene scene = Scene("push_box.yaml");
  const int steps = static_cast<int>(std::lround(scene.duration / scene.h));
  const engine::KinematicMotion& motion = *scene.bodies[1].motion;
  const double speed = 0.1;
  std::printf(
      "peer             box speed t > 0.5 s (m/s): mean, min, max  gap t > 0.5 s (mm): "
      "mean, max  deepest overlap (mm)  lateral drift (mm)\n");
  for (const Peer& peer : AvailablePeers()) {
    auto sim = MakeExternalSimulation(peer.engine, peer.setting, scene);
    double sum = 0, lowest = INFINITY, highest = -INFINITY, overlap = 0, late_sum = 0;
    double gap_sum = 0, widest = -INFINITY, late_force = 0;
    int count = 0, late_count = 0;
    for (int k = 1; k <= steps; ++k) {
      ASSERT_NO_THROW(sim->Step()) << PeerName(peer) << " step " << k;
      const engine::State& s = sim->state();
      const engine::KinematicPose pose = motion.PoseAt(s.t);
      ASSERT_LE((s.bodies[1].p_WB - pose.p).norm(), kKinematicTrack)
          << PeerName(peer) << " t = " << s.t;
      ASSERT_LE(s.bodies[1].Q_WB.angularDistance(pose.q), kKinematicTurn)
          << PeerName(peer) << " t = " << s.t;
      // the box's −x face against the pusher's +x face (both stay upright: the x extents)
      const double gap = (s.bodies[0].p_WB.x() - 0.1) - (pose.p.x() + 0.01);
      overlap = std::max(overlap, -gap);
      if (s.t < 0.5) continue;
      const double v = s.bodies[0].v_WB.x();
      sum += v;
      ++count;
      lowest = std::min(lowest, v);
      highest = std::max(highest, v);
      gap_sum += gap;
      widest = std::max(widest, gap);
      if (s.t > scene.duration - 1) {
        late_sum += v;
        late_force += sim->ContactForce(0, 1).x();
        ++late_count;
      }
    }
    std::printf("%-16s %.4f, %.4f, %.4f  %.3f, %.3f  %.2f  %.3f\n", PeerName(peer).c_str(),
                sum / count, lowest, highest, 1e3 * gap_sum / count, 1e3 * widest, 1e3 * overlap,
                1e3 * std::abs(sim->state().bodies[0].p_WB.y()));
    EXPECT_NEAR(late_sum / late_count, speed, kPushMeanSpeed * speed) << PeerName(peer);
    const double friction = 0.3 * 1 * kG;  // N: μ m g of the scene's 1 kg box
    EXPECT_NEAR(late_force / late_count, friction, kPushMeanForce * friction) << PeerName(peer);
  }
}

// scenes/peg_in_hole.yaml as first shipped (the shipped one may change): a 2 cm square peg,
// its lowest 1 cm in the 2.2 cm square hole through a 10 × 10 × 5 cm block made of four slabs,
// moving toward the hole's +x wall; run for 1 s, long enough for the peers to settle. Against the
// block's hull it would stop on the block's top (its centre at 0.09 m); against the slabs it
// falls in and stands on the table (its centre at 0.04 m). Under `decomposition: auto` the scene
// lists the hulls' contact too, which the peers leave out (PeerModels)
engine::Scene PegInHoleScene(const std::string& decomposition) {
  const std::string yaml =
      "h: 0.005\nduration: 1\nground: {friction: {mu: 0.3, e_t: 1, e_o: 1, e_r: 0.01}}\n"
      "bodies:\n"
      "  - name: block\n"
      "    mesh: meshes/block_with_hole.obj\n"
      "    mass: 1\n"
      "    on_ground: true\n"
      "    position: [0, 0]\n"
      "    decomposition: " +
      decomposition +
      "\n"
      "    parts:\n"
      "      - {box: {size: [0.039, 0.10, 0.05]}, at: [-0.0305, 0, 0.025]}\n"
      "      - {box: {size: [0.039, 0.10, 0.05]}, at: [0.0305, 0, 0.025]}\n"
      "      - {box: {size: [0.032, 0.039, 0.05]}, at: [0, -0.0305, 0.025]}\n"
      "      - {box: {size: [0.032, 0.039, 0.05]}, at: [0, 0.0305, 0.025]}\n"
      "  - {name: peg, shape: {box: {size: [0.02, 0.02, 0.08]}}, mass: 0.05, "
      "position: [0, 0, 0.08], velocity: [0.02, 0, -0.1]}\n";
  return engine::LoadSceneText(yaml, "peg_in_hole (test)",
                               std::string(ECPSIM_SOURCE_DIR) + "/scenes")
      .scene;
}

// m: where the peg's centre ends, standing on the table in the hole: its half length up
constexpr double kPegOnTheTable = 0.04;
// m: how far from kPegOnTheTable it may end. The softest peer, MuJoCo, sinks a resting body by
// at most 0.11 mm (baselines/mujoco.md; ODE and Bullet's Coulomb settings by far less), and a
// peg leaning in the hole stands at most 0.4 mm higher (half its 2 cm width × the lean, 2 mm of
// slack across the hole over the 5 cm wall, 0.04 rad): 1 mm covers both, and is 50 times less
// than the 5 cm the block's hull would leave
constexpr double kPegRestTolerance = 1e-3;
// m: the hole's half width. Standing on the table with its centre this close to the hole's
// axis, the peg is in the hole (beside the block it would be 6 cm from it); a soft peer may hold
// it inside a wall beyond the 1 mm clearance (MuJoCo's defaults: 1.9 mm; its vertex points miss
// a face crossing a face: the peg's corners are on the table and above the wall)
constexpr double kHoleHalfWidth = 0.011;

class PeerPegInHole : public ::testing::TestWithParam<std::string> {};

TEST_P(PeerPegInHole, APegFallsIntoTheHoleBetweenTheBlocksParts) {
  const engine::Scene scene = PegInHoleScene(GetParam());
  ASSERT_EQ(scene.bodies[1].name, "peg");
  const int steps = static_cast<int>(std::lround(scene.duration / scene.h));
  std::printf("peer             peg's centre after %g s: x, y, z (mm)  speed (m/s)\n",
              scene.duration);
  for (const Peer& peer : AvailablePeers()) {
    auto sim = MakeExternalSimulation(peer.engine, peer.setting, scene);
    for (int k = 1; k <= steps; ++k)
      ASSERT_NO_THROW(sim->Step()) << PeerName(peer) << " step " << k;
    const engine::BodyState& peg = sim->state().bodies[1];
    std::printf("%-16s %.3f, %.3f, %.3f  %.3g\n", PeerName(peer).c_str(), 1e3 * peg.p_WB.x(),
                1e3 * peg.p_WB.y(), 1e3 * peg.p_WB.z(), peg.v_WB.norm());
    // Bullet's default 4 cm collision margin around every part closes the 1 mm clearance: the
    // peg stays on the block's top (baselines/bullet.md)
    if (peer.engine == ExternalEngine::kBullet && peer.setting == FrictionSetting::kDefault)
      continue;
    EXPECT_NEAR(peg.p_WB.z(), kPegOnTheTable, kPegRestTolerance) << PeerName(peer);
    EXPECT_LT(peg.p_WB.head<2>().lpNorm<Eigen::Infinity>(), kHoleHalfWidth) << PeerName(peer);
  }
}

INSTANTIATE_TEST_SUITE_P(Decompositions, PeerPegInHole, ::testing::Values("parts", "auto"));

}  // namespace
}  // namespace ecpsim::baselines
