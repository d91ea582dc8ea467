// The parts of a body in the scene format: convex pieces, each a primitive or a convex mesh,
// placed in the body's mesh frame.

#include <optional>

#include "engine/rotation.h"
#include "engine/scene_io/scene_yaml_reader.h"
#include "geometry/convex_hull.h"
#include "geometry/convex_shape.h"
#include "geometry/part_seams.h"
#include "geometry/posed_shape.h"

namespace ecpsim::engine::yaml {
namespace {

using geometry::ConvexShape;

constexpr const char* kPartExpected =
    "a part: exactly one of box, sphere, cylinder, ellipsoid or mesh, with an optional `at` "
    "[x, y, z] (m, mesh frame) and `rpy` or `quaternion`";

// the part's shape centred where it is given: a primitive about its centre, a mesh's convex hull
// in the mesh file's frame (the body's scale applied)
std::shared_ptr<const ConvexShape> ReadPartShape(const Context& ctx, const MapNode& part,
                                                 const PartFrame& frame,
                                                 std::vector<std::string>& warnings) {
  if (!part.Has("mesh")) return ReadPrimitiveIn(ctx, part).shape;
  const MeshFile file = LoadMeshFile(ctx, part.Get("mesh"), part.Key("mesh"), frame.mesh_scale,
                                     frame.scale_keys, warnings);
  return WithLocation(ctx, part.Get("mesh"), part.Key("mesh"), [&] {
    return std::make_shared<const geometry::PolyhedralShape>(
        geometry::ComputeConvexHull(file.mesh.vertices, file.path));
  });
}

// how far `part` reaches out of the body's hull (m, ≤ 0 inside) and where (body frame): the
// part's support point along each of a polyhedral hull's normals, exact; against a smooth hull
// the part's tessellation's vertices
std::pair<double, Eigen::Vector3d> Outside(const ConvexShape& part, const ConvexShape& hull) {
  std::pair<double, Eigen::Vector3d> worst{-INFINITY, Eigen::Vector3d::Zero()};
  const auto check = [&](const Eigen::Vector3d& y) {
    for (int c = 0; c < hull.NumConstraints(); ++c) {
      const double outside = hull.Value(c, y);
      if (outside > worst.first) worst = {outside, y};
    }
  };
  if (const auto* polyhedron = hull.AsPolyhedron()) {
    for (const Eigen::Vector3d& n : polyhedron->hull().normals) check(part.Support(n));
  } else {
    for (const Eigen::Vector3d& v : part.Tessellate().vertices) check(v);
  }
  return worst;
}

}  // namespace

std::vector<std::shared_ptr<const ConvexShape>> ReadParts(const Context& ctx,
                                                          const YAML::Node& node,
                                                          const std::string& key,
                                                          const PartFrame& frame,
                                                          std::vector<std::string>& warnings) {
  if (!node.IsSequence() || node.size() == 0) {
    Fail(ctx, node, key, "a list of at least one part {box: {size: [x, y, z]}, at: [x, y, z]}");
  }
  ECPSIM_DEMAND(frame.hull != nullptr);
  std::vector<std::shared_ptr<const ConvexShape>> parts;
  for (size_t i = 0; i < node.size(); ++i) {
    const std::string at_key = Index(key, i);
    const MapNode part(
        ctx, node[i], at_key,
        {"box", "sphere", "cylinder", "ellipsoid", "mesh", "at", "rpy", "quaternion"});
    int shapes = 0;
    for (const char* k : {"box", "sphere", "cylinder", "ellipsoid", "mesh"}) shapes += part.Has(k);
    if (shapes != 1) Fail(ctx, node[i], at_key, kPartExpected);
    const Eigen::Vector3d position =
        part.Has("at") ? ReadVector3(ctx, part.Get("at"), part.Key("at"), "m, mesh frame")
                       : Eigen::Vector3d::Zero();
    // a mesh part's file is in the mesh's frame already: `at` moves it from there
    const std::shared_ptr<const ConvexShape> shape = WithLocation(ctx, node[i], at_key, [&] {
      return geometry::Posed(ReadPartShape(ctx, part, frame, warnings),
                             ReadOrientation(ctx, part).toRotationMatrix(),
                             position - frame.center_of_mass);
    });
    // the parts stand for pieces of the body
    const auto [outside, where] = Outside(*shape, *frame.hull);
    if (outside > frame.tolerance) {
      const Eigen::Vector3d mesh = where + frame.center_of_mass;
      Fail(ctx, node[i], at_key,
           fmt::format("a part inside the body; its {} ({:.6g}, {:.6g}, {:.6g}) m (mesh "
                       "frame) lies {:.3g} m outside the body's hull",
                       shape->AsPolyhedron() ? "corner" : "point", mesh.x(), mesh.y(), mesh.z(),
                       outside));
    }
    parts.push_back(shape);
  }
  if (frame.touched) WarnOfSeams(parts, key, frame, warnings);
  return parts;
}

// (a contact at a seam's edge could push along the seam face's normal, which no surface of the
// body has: geometry/part_seams.h)
void WarnOfSeams(const std::vector<std::shared_ptr<const ConvexShape>>& parts,
                 const std::string& key, const PartFrame& frame,
                 std::vector<std::string>& warnings) {
  for (size_t i = 0; i < parts.size(); ++i) {
    for (size_t j = i + 1; j < parts.size(); ++j) {
      const auto* a = parts[i]->AsPolyhedron();
      const auto* b = parts[j]->AsPolyhedron();
      if (a == nullptr || b == nullptr) continue;
      const std::optional<geometry::Seam> seam =
          geometry::FindSeam(a->hull(), b->hull(), frame.tolerance);
      if (!seam) continue;
      const Eigen::Vector3d at = seam->centre + frame.center_of_mass;
      warnings.push_back(fmt::format(
          "{}: parts {} and {} meet face to face (a face centred at ({:.6g}, {:.6g}, {:.6g}) m, "
          "mesh frame): where that seam reaches the surface a contact's normal is not unique; "
          "let one part reach into the other (docs/scene_format.md, \"Decomposition\")",
          key, i, j, at.x(), at.y(), at.z()));
    }
  }
}

}  // namespace ecpsim::engine::yaml
