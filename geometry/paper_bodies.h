#pragma once
// The paper's three bodies (desk, T-bar, dumbbell) as meshes built from their parameters.

#include "geometry/triangle_mesh.h"

namespace ecpsim::geometry {

/// Four-legged desk: square top, four square feet at the corners; z up, feet on z = 0, centred on
/// the z axis. The total height is solved so that a uniform density puts the centre of mass at
/// `com_height` (0.587 m for the defaults).
/// @throws InputError for non-positive sizes, feet wider than half the top, or
///         com_height ≤ top_thickness / 2.
struct DeskParams {
  double top_size = 0.5;        // m, top is top_size × top_size
  double foot_size = 0.06;      // m, each foot is foot_size × foot_size
  double top_thickness = 0.05;  // m
  double com_height = 0.45;     // m, the total height is solved for this
};
TriangleMesh MakeDeskMesh(const DeskParams& params = {});

/// Flat T-shaped bar lying on z = 0, `thickness` thick: a bar along x and a stem along −y, placed
/// so that its centre of mass is at (0, 0, thickness/2).
/// @throws InputError for non-positive sizes or stem_width ≥ bar_length.
struct TBarParams {
  double bar_length = 0.4;   // m (along x)
  double bar_width = 0.1;    // m
  double stem_length = 0.3;  // m (along −y, below the bar)
  double stem_width = 0.1;   // m
  double thickness = 0.05;   // m
};
TriangleMesh MakeTBarMesh(const TBarParams& params = {});

/// Dumbbell along the x axis centred at the origin: two end discs of radius R joined by a bar.
/// Ring vertices lie exactly on their circles at angles 2πk/segments from +y towards +z, so the
/// mesh stays inside the cylinder (R, L), and with segments divisible by 4 a vertex of each rim
/// is straight below the axis (lying on its side, each disc touches the ground along an edge).
/// @throws InputError for non-positive sizes, bar_length ≥ length, bar_radius ≥ radius or
///         segments < 3.
struct DumbbellParams {
  double length = 0.3;       // L, m, overall
  double bar_length = 0.18;  // L_b, m
  double radius = 0.1;       // R, m, end discs
  double bar_radius = 0.05;  // R_b, m
  int segments = 96;         // around the axis
};
TriangleMesh MakeDumbbellMesh(const DumbbellParams& params = {});

}  // namespace ecpsim::geometry
