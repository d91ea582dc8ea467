// `ecpsim hull MESH`: mass properties and the body-frame convex hull (n·y ≤ d) of a mesh file.

#include <cmath>
#include <cstdio>
#include <memory>
#include <optional>
#include <string>
#include <utility>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "app/commands.h"
#include "app/option_checks.h"
#include "common/errors.h"
#include "engine/scene_io/mesh_report.h"
#include "geometry/convex_hull.h"
#include "geometry/mass_properties.h"
#include "geometry/mesh_io.h"
#include "geometry/mesh_topology.h"

namespace ecpsim::app {
namespace {

struct HullOptions {
  std::string mesh;
  bool json = false;
  std::optional<double> scale;
  std::optional<std::string> units;
  std::optional<double> mass;
  std::optional<double> density;
};

nlohmann::json ToJson(const Eigen::Vector3d& v) { return {v.x(), v.y(), v.z()}; }

nlohmann::json RowsToJson(const Eigen::Matrix3d& m) {
  return {ToJson(m.row(0).transpose()), ToJson(m.row(1).transpose()), ToJson(m.row(2).transpose())};
}

std::string Format(const Eigen::Vector3d& v) {
  // + 0.0 turns −0 into 0 in the printout
  return fmt::format("({:.9g}, {:.9g}, {:.9g})", v.x() + 0.0, v.y() + 0.0, v.z() + 0.0);
}

void RunHull(const HullOptions& options) {
  const std::string& path = options.mesh;
  engine::ScaledMesh scaled =
      engine::LoadScaledMesh(path, options.scale, options.units, {"--scale", "--units"});
  if (!scaled.warning.empty()) {
    std::fprintf(stderr, "ecpsim: warning: %s\n", scaled.warning.c_str());
  }
  const engine::MeshReport report =
      engine::ReportMesh(std::move(scaled), path, options.mass, options.density);
  if (!report.warning.empty()) {
    std::fprintf(stderr, "ecpsim: warning: %s\n", report.warning.c_str());
  }
  const geometry::TriangleMesh& mesh = report.scaled.mesh;
  const double scale = report.scaled.scale;
  const geometry::MeshTopology& topology = report.topology;
  const std::string& mass_source = report.mass_source;
  const geometry::MassProperties& props = report.props;
  const geometry::ConvexHull& body_hull = report.body_hull;

  if (options.json) {
    nlohmann::json hull_json;
    hull_json["vertices"] = nlohmann::json::array();
    for (const Eigen::Vector3d& v : body_hull.vertices) hull_json["vertices"].push_back(ToJson(v));
    hull_json["faces"] = body_hull.faces;
    hull_json["halfspaces"] = nlohmann::json::array();
    for (std::size_t i = 0; i < body_hull.normals.size(); ++i) {
      const Eigen::Vector3d& n = body_hull.normals[i];
      hull_json["halfspaces"].push_back({n.x(), n.y(), n.z(), body_hull.offsets[i]});
    }
    nlohmann::json axes = nlohmann::json::array();
    for (int a = 0; a < 3; ++a) axes.push_back(ToJson(props.principal_axes.col(a)));

    nlohmann::json out;
    out["mesh"] = path;
    out["scale"] = scale;
    out["vertices"] = mesh.vertices.size();
    out["triangles"] = mesh.triangles.size();
    out["closed"] = topology.closed;
    out["oriented"] = topology.consistently_oriented;
    out["boundary_edges"] = topology.boundary_edges;
    out["non_manifold_edges"] = topology.non_manifold_edges;
    out["mass_source"] = mass_source;
    out["volume"] = props.volume;
    out["mass"] = props.mass;
    out["density"] = props.mass / props.volume;
    out["center_of_mass"] = ToJson(props.center_of_mass);
    out["inertia"] = RowsToJson(props.inertia);
    out["principal_moments"] = ToJson(props.principal_moments);
    out["principal_axes"] = axes;
    out["hull"] = hull_json;
    std::printf("%s\n", out.dump(2).c_str());
    return;
  }

  std::string text = fmt::format("mesh {} (scale {})\n", path, scale);
  text += fmt::format(
      "  {} vertices, {} triangles; {}, {}\n", mesh.vertices.size(), mesh.triangles.size(),
      topology.closed ? "closed"
                      : fmt::format("open ({} boundary edges, {} "
                                    "non-manifold edges)",
                                    topology.boundary_edges, topology.non_manifold_edges),
      topology.consistently_oriented ? "consistently oriented" : "inconsistently oriented");
  text += fmt::format("mass properties from the {}\n", mass_source);
  text += fmt::format("  volume           {:.9g} m³\n", props.volume);
  text += fmt::format("  mass             {:.9g} kg (density {:.9g} kg/m³)\n", props.mass,
                      props.mass / props.volume);
  text += fmt::format("  centre of mass   {} m (mesh frame)\n", Format(props.center_of_mass));
  text += "  inertia about the centre of mass, mesh axes (kg·m²):\n";
  for (int r = 0; r < 3; ++r) {
    text += fmt::format("    {}\n", Format(props.inertia.row(r).transpose()));
  }
  text += fmt::format("  principal moments {} kg·m²\n", Format(props.principal_moments));
  for (int a = 0; a < 3; ++a) {
    text += fmt::format("    axis {}        {}\n", a + 1, Format(props.principal_axes.col(a)));
  }
  text += fmt::format(
      "convex hull: {} vertices, {} faces; body frame (origin at the centre of "
      "mass, mesh axes), n·y ≤ d:\n",
      body_hull.vertices.size(), body_hull.faces.size());
  for (std::size_t i = 0; i < body_hull.normals.size(); ++i) {
    text +=
        fmt::format("  n = {}  d = {:.9g} m\n", Format(body_hull.normals[i]), body_hull.offsets[i]);
  }
  std::fputs(text.c_str(), stdout);
}

}  // namespace

void AddHullCommand(CLI::App& app) {
  CLI::App* command = app.add_subcommand(
      "hull",
      "Mass properties and convex hull of a mesh; the hull as n·y ≤ d in the body frame (origin at "
      "the centre of mass). An open mesh falls back to its convex hull's mass properties.");
  auto options = std::make_shared<HullOptions>();
  command->add_option("MESH", options->mesh, "mesh file (any format assimp reads)")->required();
  command->add_flag("--json", options->json, "print JSON instead of text");
  command
      ->add_option("--scale", options->scale,
                   "multiply coordinates by S (e.g. 0.001 for mm; default 1)")
      ->check(FinitePositive("--scale", engine::kMeshScaleRange));
  command
      ->add_option("--units", options->units,
                   "the mesh's unit: mm, cm, m or in (the readable --scale; both must agree)")
      ->check(KnownUnit("--units"));
  CLI::Option* mass = command->add_option("--mass", options->mass, "total mass M, kg")
                          ->check(FinitePositive("--mass", engine::kMassRange));
  CLI::Option* density =
      command
          ->add_option("--density", options->density, "uniform density RHO, kg/m³ (default 1000)")
          ->check(FinitePositive("--density", engine::kDensityRange));
  mass->excludes(density);
  command->callback([options] { RunHull(*options); });
}

}  // namespace ecpsim::app
