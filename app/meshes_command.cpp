// `ecpsim meshes [DIR]`: writes the paper's desk, T-bar and dumbbell as OBJ meshes (metres, z up).

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <string>
#include <system_error>

#include <fmt/format.h>

#include "app/commands.h"
#include "common/errors.h"
#include "geometry/mass_properties.h"
#include "geometry/mesh_io.h"
#include "geometry/paper_bodies.h"

namespace ecpsim::app {
namespace {

// the paper's masses (section 5), kg: only for the printed summary, the files carry no mass
constexpr double kDeskMass = 15.0;
constexpr double kTBarMass = 2.0;
constexpr double kDumbbellMass = 3.0;

// writes `mesh` to DIR/`name` and prints one summary line with `details`
void WriteBody(const std::filesystem::path& folder, const std::string& name,
               const geometry::TriangleMesh& mesh, double paper_mass, const std::string& details) {
  const std::string path = (folder / name).string();
  geometry::SaveMesh(mesh, path);
  const geometry::MassProperties p = geometry::ComputeMassPropertiesForMass(mesh, paper_mass, path);
  const Eigen::Vector3d& c = p.center_of_mass;
  const Eigen::Vector3d& moments = p.principal_moments;
  std::printf(
      "%s\n",
      fmt::format("wrote {}: {} vertices, {} triangles; {}; volume {:.6g} m³, "
                  "centre of mass ({:.6g}, {:.6g}, {:.6g}) m; with the paper's {} kg, "
                  "principal moments ({:.6g}, {:.6g}, {:.6g}) kg·m²",
                  path, mesh.vertices.size(), mesh.triangles.size(), details, p.volume, c.x() + 0.0,
                  c.y() + 0.0, c.z() + 0.0, paper_mass, moments[0], moments[1], moments[2])
          .c_str());
}

void RunMeshes(const std::string& folder_name) {
  const std::filesystem::path folder(folder_name);
  std::error_code error;
  std::filesystem::create_directories(folder, error);
  if (error) {
    throw InputError(
        fmt::format("{}: cannot create the output folder: {}", folder_name, error.message()));
  }

  const geometry::DeskParams desk;
  const geometry::TriangleMesh desk_mesh = geometry::MakeDeskMesh(desk);
  double height = 0;
  for (const Eigen::Vector3d& v : desk_mesh.vertices) height = std::max(height, v.z());
  WriteBody(folder, "desk.obj", desk_mesh, kDeskMass,
            fmt::format("top {} × {} × {} m, feet {} × {} m, height {:.6g} m for the CM at {} m",
                        desk.top_size, desk.top_size, desk.top_thickness, desk.foot_size,
                        desk.foot_size, height, desk.com_height));

  const geometry::TBarParams tbar;
  WriteBody(
      folder, "tbar.obj", geometry::MakeTBarMesh(tbar), kTBarMass,
      fmt::format("bar {} × {} m, stem {} × {} m, {} m thick, CM above the origin", tbar.bar_length,
                  tbar.bar_width, tbar.stem_length, tbar.stem_width, tbar.thickness));

  const geometry::DumbbellParams dumbbell;
  WriteBody(
      folder, "dumbbell.obj", geometry::MakeDumbbellMesh(dumbbell), kDumbbellMass,
      fmt::format("L {} m, L_b {} m, R {} m, R_b {} m, {} segments, axis x", dumbbell.length,
                  dumbbell.bar_length, dumbbell.radius, dumbbell.bar_radius, dumbbell.segments));
}

}  // namespace

void AddMeshesCommand(CLI::App& app) {
  CLI::App* command = app.add_subcommand(
      "meshes", "Write the paper's desk, T-bar and dumbbell meshes as OBJ (metres, z up)");
  auto folder = std::make_shared<std::string>("scenes/meshes");
  command->add_option("DIR", *folder, "output folder, created if missing")->capture_default_str();
  command->callback([folder] { RunMeshes(*folder); });
}

}  // namespace ecpsim::app
