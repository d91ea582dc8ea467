#include "geometry/paper_bodies.h"

#include <array>
#include <cmath>
#include <functional>
#include <string>
#include <vector>

#include <fmt/format.h>

#include "common/errors.h"

namespace ecpsim::geometry {
namespace {

constexpr double kPi = 3.14159265358979323846;

// throws unless `value` is finite and > 0
void RequirePositive(const char* body, const char* key, double value, const char* unit) {
  if (!std::isfinite(value) || value <= 0.0) {
    throw InputError(
        fmt::format("{}: {} = {}: expected a finite length > 0 {}", body, key, value, unit));
  }
}

// The union of the filled cells of a rectilinear grid (node coordinates xs × ys × zs, strictly
// increasing) as a closed, outward-wound mesh: every face between a filled cell and an empty
// (or outside) cell becomes two triangles on the shared grid nodes, so neighbouring faces share
// their vertices and edges exactly (watertight, no T-junctions). Manifold as long as no two
// filled cells touch only along an edge or at a corner.
TriangleMesh MeshFilledCells(const std::vector<double>& xs, const std::vector<double>& ys,
                             const std::vector<double>& zs,
                             const std::function<bool(int, int, int)>& filled) {
  const int nx = static_cast<int>(xs.size()) - 1;
  const int ny = static_cast<int>(ys.size()) - 1;
  const int nz = static_cast<int>(zs.size()) - 1;
  auto is_filled = [&](int i, int j, int k) {
    return i >= 0 && j >= 0 && k >= 0 && i < nx && j < ny && k < nz && filled(i, j, k);
  };

  TriangleMesh mesh;
  std::vector<int> node_index(xs.size() * ys.size() * zs.size(), -1);
  auto node = [&](int i, int j, int k) {
    int& index = node_index[(static_cast<std::size_t>(k) * ys.size() + j) * xs.size() + i];
    if (index < 0) {
      index = static_cast<int>(mesh.vertices.size());
      mesh.vertices.emplace_back(xs[i], ys[j], zs[k]);
    }
    return index;
  };
  // a quad counter-clockwise seen from outside, as two triangles
  using Node = std::array<int, 3>;
  auto quad = [&](const Node& a, const Node& b, const Node& c, const Node& d) {
    const int ia = node(a[0], a[1], a[2]);
    const int ib = node(b[0], b[1], b[2]);
    const int ic = node(c[0], c[1], c[2]);
    const int id = node(d[0], d[1], d[2]);
    mesh.triangles.emplace_back(ia, ib, ic);
    mesh.triangles.emplace_back(ia, ic, id);
  };

  for (int k = 0; k < nz; ++k) {
    for (int j = 0; j < ny; ++j) {
      for (int i = 0; i < nx; ++i) {
        if (!is_filled(i, j, k)) continue;
        // corner order per face: (first edge) × (second edge) is the outward normal
        if (!is_filled(i + 1, j, k))
          quad({i + 1, j, k}, {i + 1, j + 1, k}, {i + 1, j + 1, k + 1}, {i + 1, j, k + 1});
        if (!is_filled(i - 1, j, k))
          quad({i, j, k}, {i, j, k + 1}, {i, j + 1, k + 1}, {i, j + 1, k});
        if (!is_filled(i, j + 1, k))
          quad({i, j + 1, k}, {i, j + 1, k + 1}, {i + 1, j + 1, k + 1}, {i + 1, j + 1, k});
        if (!is_filled(i, j - 1, k))
          quad({i, j, k}, {i + 1, j, k}, {i + 1, j, k + 1}, {i, j, k + 1});
        if (!is_filled(i, j, k + 1))
          quad({i, j, k + 1}, {i + 1, j, k + 1}, {i + 1, j + 1, k + 1}, {i, j + 1, k + 1});
        if (!is_filled(i, j, k - 1))
          quad({i, j, k}, {i, j + 1, k}, {i + 1, j + 1, k}, {i + 1, j, k});
      }
    }
  }
  return mesh;
}

}  // namespace

TriangleMesh MakeDeskMesh(const DeskParams& params) {
  const double s = params.top_size;
  const double f = params.foot_size;
  const double t = params.top_thickness;
  const double c = params.com_height;
  RequirePositive("desk", "top_size", s, "m");
  RequirePositive("desk", "foot_size", f, "m");
  RequirePositive("desk", "top_thickness", t, "m");
  RequirePositive("desk", "com_height", c, "m");
  if (2.0 * f >= s) {
    throw InputError(fmt::format(
        "desk: foot_size = {} m: expected less than half of top_size = {} m (feet must not touch)",
        f, s));
  }
  if (c <= 0.5 * t) {
    throw InputError(fmt::format(
        "desk: com_height = {} m: expected more than half of top_thickness = {} m (the CM of the "
        "top alone)",
        c, t));
  }

  // leg height h from the CM condition, uniform density: with top area A = s² and four feet of
  // area f², [A t (h + t/2) + 4 f² h · h/2] / (A t + 4 f² h) = c, i.e.
  // 2 f² h² + (A t − 4 f² c) h + A t (t/2 − c) = 0, whose constant term is < 0 (c > t/2): one
  // positive root, taken in the cancellation-free form 2|q| / (b + √(b² + 8 f² |q|)) when b ≥ 0
  const double area = s * s;
  const double a2 = 2.0 * f * f;
  const double b = area * t - 4.0 * f * f * c;
  const double q = area * t * (0.5 * t - c);
  const double root = std::sqrt(b * b - 4.0 * a2 * q);
  const double h = b >= 0.0 ? -2.0 * q / (b + root) : (root - b) / (2.0 * a2);

  // 3 × 3 × 2 cells: the top layer full, the bottom layer only at the four corners
  const std::vector<double> xs = {-0.5 * s, -0.5 * s + f, 0.5 * s - f, 0.5 * s};
  return MeshFilledCells(xs, xs, {0.0, h, h + t},
                         [](int i, int j, int k) { return k == 1 || (i != 1 && j != 1); });
}

TriangleMesh MakeTBarMesh(const TBarParams& params) {
  RequirePositive("T-bar", "bar_length", params.bar_length, "m");
  RequirePositive("T-bar", "bar_width", params.bar_width, "m");
  RequirePositive("T-bar", "stem_length", params.stem_length, "m");
  RequirePositive("T-bar", "stem_width", params.stem_width, "m");
  RequirePositive("T-bar", "thickness", params.thickness, "m");
  if (params.stem_width >= params.bar_length) {
    throw InputError(fmt::format("T-bar: stem_width = {} m: expected less than bar_length = {} m",
                                 params.stem_width, params.bar_length));
  }

  // the centre of mass at x = y = 0: stem y ∈ [0, stem_length], bar above it, then shifted
  const double bar_area = params.bar_length * params.bar_width;
  const double stem_area = params.stem_width * params.stem_length;
  const double bar_centre = params.stem_length + 0.5 * params.bar_width;
  const double stem_centre = 0.5 * params.stem_length;
  const double cm_y = (bar_area * bar_centre + stem_area * stem_centre) / (bar_area + stem_area);

  // 3 × 2 × 1 cells: the bar row full, the stem row only in the middle column
  const std::vector<double> xs = {-0.5 * params.bar_length, -0.5 * params.stem_width,
                                  0.5 * params.stem_width, 0.5 * params.bar_length};
  const std::vector<double> ys = {-cm_y, params.stem_length - cm_y,
                                  params.stem_length + params.bar_width - cm_y};
  return MeshFilledCells(xs, ys, {0.0, params.thickness},
                         [](int i, int j, int) { return j == 1 || i == 1; });
}

TriangleMesh MakeDumbbellMesh(const DumbbellParams& params) {
  const double half_length = 0.5 * params.length;
  const double half_bar = 0.5 * params.bar_length;
  const double radius = params.radius;
  const double bar_radius = params.bar_radius;
  RequirePositive("dumbbell", "length", params.length, "m");
  RequirePositive("dumbbell", "bar_length", params.bar_length, "m");
  RequirePositive("dumbbell", "radius", radius, "m");
  RequirePositive("dumbbell", "bar_radius", bar_radius, "m");
  if (params.bar_length >= params.length) {
    throw InputError(fmt::format("dumbbell: bar_length = {} m: expected less than length = {} m",
                                 params.bar_length, params.length));
  }
  if (bar_radius >= radius) {
    throw InputError(fmt::format("dumbbell: bar_radius = {} m: expected less than radius = {} m",
                                 bar_radius, radius));
  }
  if (params.segments < 3) {
    throw InputError(fmt::format("dumbbell: segments = {}: expected at least 3", params.segments));
  }

  // the profile (x, r) from the left cap centre round the outside to the right cap centre,
  // revolved about the x axis; r = 0 points are single vertices (the cap centres)
  const std::array<std::array<double, 2>, 8> profile = {{{-half_length, 0.0},
                                                         {-half_length, radius},
                                                         {-half_bar, radius},
                                                         {-half_bar, bar_radius},
                                                         {half_bar, bar_radius},
                                                         {half_bar, radius},
                                                         {half_length, radius},
                                                         {half_length, 0.0}}};
  const int n = params.segments;
  TriangleMesh mesh;
  std::vector<int> ring_start(profile.size());
  for (std::size_t p = 0; p < profile.size(); ++p) {
    ring_start[p] = static_cast<int>(mesh.vertices.size());
    const double x = profile[p][0];
    const double r = profile[p][1];
    if (r == 0.0) {
      mesh.vertices.emplace_back(x, 0.0, 0.0);
      continue;
    }
    // ring vertices exactly on the circle at angles 2πk/n from +y towards +z
    for (int k = 0; k < n; ++k) {
      const double angle = 2.0 * kPi * k / n;
      mesh.vertices.emplace_back(x, r * std::cos(angle), r * std::sin(angle));
    }
  }
  auto vertex = [&](std::size_t p, int k) {
    return profile[p][1] == 0.0 ? ring_start[p] : ring_start[p] + (k % n);
  };

  // band between consecutive profile points: (p_k, p_k+1, q_k+1) and (p_k, q_k+1, q_k) face
  // outwards (on the outer cylinder: +z × +x = +y at angle 0); triangles that touch a cap centre
  // twice are dropped
  for (std::size_t p = 0; p + 1 < profile.size(); ++p) {
    for (int k = 0; k < n; ++k) {
      const Eigen::Vector3i first(vertex(p, k), vertex(p, k + 1), vertex(p + 1, k + 1));
      const Eigen::Vector3i second(vertex(p, k), vertex(p + 1, k + 1), vertex(p + 1, k));
      for (const Eigen::Vector3i& tri : {first, second}) {
        if (tri[0] != tri[1] && tri[1] != tri[2] && tri[2] != tri[0]) mesh.triangles.push_back(tri);
      }
    }
  }
  return mesh;
}

}  // namespace ecpsim::geometry
