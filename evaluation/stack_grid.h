#pragma once
// The scaling benchmark's scene family: N cubes at rest in stacks on a square grid, the same
// scene at every N but for its number of stacks (issue 30: cost per step against bodies).

#include "engine/scene.h"

namespace ecpsim::evaluation {

/// Boxes per stack: each box rests on the one below, so a stack is one island of four bodies and
/// four contacts, as in a pile, not a set of lone boxes.
constexpr int kStackHeight = 4;
/// m, the cubes' edge and kg, their mass: scenes/pyramid.yaml's boxes.
constexpr double kGridBoxSize = 0.1;
constexpr double kGridBoxMass = 1;
/// m between neighbouring stacks' axes: a gap of two boxes, wider than the peers' soft-contact
/// drift over a measured run (mm; baselines/README.md, scenes/stack.yaml), so stacks never touch.
constexpr double kStackSpacing = 0.3;
/// s, the time step: the shipped scenes' h.
constexpr double kGridStep = 0.01;
/// The largest grid MakeStackGrid builds (bodies): 10× the benchmark's 1,000, to keep a typo
/// from asking for a scene the machine cannot hold.
constexpr int kMaxGridBodies = 10000;

/// `bodies` cubes (kGridBoxSize, kGridBoxMass) in stacks of kStackHeight, the last one shorter
/// when kStackHeight does not divide `bodies`: stack k at column k mod s, row k / s of a square
/// grid of side s = ⌈√stacks⌉ with pitch kStackSpacing centred on the origin, its boxes exactly
/// on the ground (z = 0) and on each other, axis-aligned, at rest; μ = 0.5, e_r = 0.05 (scenes/
/// pyramid.yaml's friction). Contact pairs: every box with the ground, and every two boxes of one
/// stack; boxes of different stacks are two box widths apart and have no pair, as a user would
/// leave out what cannot touch (every pair would hand MuJoCo half a million explicit pairs at
/// 1,000 bodies, baselines/README.md). Step kGridStep, duration 1 s, body names "s<stack>b<level>".
/// Precondition (ECPSIM_DEMAND): 1 ≤ bodies ≤ kMaxGridBodies.
engine::Scene MakeStackGrid(int bodies);

}  // namespace ecpsim::evaluation
