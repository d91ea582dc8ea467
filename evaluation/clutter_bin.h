#pragma once
// The clutter benchmark's scene: assorted boxes dropped in layers into a square bin (issue 30's
// "two dozen assorted boxes in a bin"), generated from a seed, the same on every platform.

#include <cstdint>

#include "engine/scene.h"

namespace ecpsim::evaluation {

/// m, the bin's inside is a square of this side centred on the origin; its floor is the ground
/// z ≤ 0 and its four walls are the half-spaces beyond |x| = ½ side and |y| = ½ side (the peers'
/// adapters model half-spaces only; a wall's height never matters to boxes that start inside and
/// fall).
constexpr double kClutterBinSide = 0.6;
/// m, each edge of each box is uniform in [kClutterEdgeMin, kClutterEdgeMax).
constexpr double kClutterEdgeMin = 0.04, kClutterEdgeMax = 0.09;
/// kg/m³: wood, so the boxes weigh 32–365 g.
constexpr double kClutterDensity = 500;
/// Coulomb's μ on every contact (box–box, box–floor, box–wall).
constexpr double kClutterMu = 0.4;
/// Boxes per layer: a 3 × 3 grid whose pitch (kClutterPitch) fits inside the bin.
constexpr int kClutterPerRow = 3;
/// m, each grid point is moved by up to this along x and y, so that no two layers stack exactly.
constexpr double kClutterJitter = 0.01;
/// m between grid points and between layers: the largest box's diagonal (√3 · 9 cm = 0.156 m),
/// two jitters and 5 mm, so that boxes turned any way never overlap at the start; the outer
/// boxes' corners stay 3 cm inside the walls.
constexpr double kClutterPitch = 0.181;
/// s: when the pile has settled. With h = 0.005 the 24-box bin's boxes fall, tumble and are at
/// rest by 0.8 s (every box's |v| + 9 cm · |ω| below 1e-6 m/s under `hull`, sampled every
/// 0.05 s); the drift at rest is measured from here.
constexpr double kClutterSettleTime = 1.0;
/// The largest bin ClutterBinScene builds: 1,000 boxes stand 112 layers (18 m) high, beyond any
/// use but a typo.
constexpr int kMaxClutterBoxes = 1000;

/// `boxes` boxes (named "b<i>") with edges and density as above, each turned uniformly at random
/// and dropped from rest at a point of a kClutterPerRow × kClutterPerRow grid of pitch
/// kClutterPitch, layer by layer (the lowest box's centre one pitch above the floor, each point
/// moved by up to ±kClutterJitter), into the bin; the friction ellipsoid's torsion e_r is the mean radius of
/// a mean box face (MeanRadiusOfRectangle of 6.5 cm squared, 2.5 cm). Contact pairs: every box
/// with the floor and each wall, and every two boxes. Step h, duration 2 × kClutterSettleTime.
/// Precondition (ECPSIM_DEMAND): 1 ≤ boxes ≤ kMaxClutterBoxes, h > 0.
engine::Scene ClutterBinScene(int boxes, std::uint64_t seed, double h);

}  // namespace ecpsim::evaluation
