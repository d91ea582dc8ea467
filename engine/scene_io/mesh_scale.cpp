#include "engine/scene_io/mesh_scale.h"

#include <fmt/format.h>

#include <cmath>
#include <limits>

#include "common/errors.h"
#include "engine/scene_limits.h"
#include "geometry/mesh_io.h"

namespace ecpsim::engine {
namespace {

struct Unit {
  const char* name;  // as typed after --units / units:
  const char* long_name;
  double metres;  // per unit
};

// the units a mesh file is usually written in; the inch is exactly 0.0254 m
constexpr Unit kUnits[] = {
    {"mm", "millimetres", 0.001},
    {"cm", "centimetres", 0.01},
    {"m", "metres", 1},
    {"in", "inches", 0.0254},
};

// a scale and a unit agree when they are the same factor up to round-off of a typed decimal
constexpr double kScaleAgreement = 1e-12;  // relative

// "--units mm" on the command line, "bodies[0].units: mm" in a scene
std::string Setting(const std::string& key, const std::string& value) {
  return key.rfind("--", 0) == 0 ? fmt::format("{} {}", key, value)
                                 : fmt::format("{}: {}", key, value);
}

bool Plausible(double across) {
  return across >= kMinPlausibleMeshSize && across <= kMaxPlausibleMeshSize;
}

}  // namespace

std::optional<double> MetresPerUnit(const std::string& units) {
  for (const Unit& unit : kUnits) {
    if (units == unit.name) return unit.metres;
  }
  return std::nullopt;
}

const char* KnownUnits() { return "mm, cm, m, in"; }

bool ScalesAgree(double scale, double metres) {
  return std::abs(scale - metres) <= kScaleAgreement * metres;
}

double ResolveMeshScale(const std::optional<double>& scale, const std::optional<std::string>& units,
                        const MeshScaleKeys& keys) {
  if (scale) {
    const std::string expected = OutOfRange(*scale, kMeshScaleRange);
    if (!expected.empty()) {
      throw InputError(
          fmt::format("{} = {}: expected {} (mesh units to m)", keys.scale, *scale, expected));
    }
  }
  if (!units) return scale.value_or(1.0);
  const std::optional<double> metres = MetresPerUnit(*units);
  if (!metres) {
    throw InputError(fmt::format("{} = {}: expected one of {}", keys.units, *units, KnownUnits()));
  }
  if (scale && !ScalesAgree(*scale, *metres)) {
    throw InputError(
        fmt::format("{} = {} and {} = {} ({} m per unit) disagree: expected one of "
                    "them, or both for the same factor",
                    keys.scale, *scale, keys.units, *units, *metres));
  }
  return *metres;
}

double MeshAcross(const geometry::TriangleMesh& mesh) {
  if (mesh.vertices.empty()) return 0;
  Eigen::Vector3d lo = Eigen::Vector3d::Constant(std::numeric_limits<double>::infinity());
  Eigen::Vector3d hi = -lo;
  for (const Eigen::Vector3d& v : mesh.vertices) {
    lo = lo.cwiseMin(v);
    hi = hi.cwiseMax(v);
  }
  return (hi - lo).norm();
}

std::string MeshSizeWarning(const std::string& mesh, double across, double scale,
                            const MeshScaleKeys& keys) {
  if (Plausible(across)) return "";
  const bool large = across > kMaxPlausibleMeshSize;
  // the first unit smaller (larger) than the scale used that makes the size plausible: metres
  // first (an unneeded scale), then in the order CAD files are most often written
  static constexpr const char* kLargeOrder[] = {"m", "mm", "cm", "in"};
  static constexpr const char* kSmallOrder[] = {"m", "in", "cm", "mm"};
  const double in_file_units = across / scale;
  const Unit* suggestion = nullptr;
  for (const char* name : large ? kLargeOrder : kSmallOrder) {
    for (const Unit& unit : kUnits) {
      const bool other = large ? unit.metres < scale : unit.metres > scale;
      if (name == std::string(unit.name) && other && Plausible(in_file_units * unit.metres)) {
        suggestion = &unit;
      }
    }
    if (suggestion != nullptr) break;
  }
  const std::string size =
      across >= 1 ? fmt::format("{:.3g} m", across) : fmt::format("{:.3g} mm", across * 1000);
  if (suggestion == nullptr) {
    return fmt::format("{} is {} across; check its unit ({} or {})", mesh, size, keys.units,
                       keys.scale);
  }
  return fmt::format("{} is {} across; if it is in {} use {} (or {})", mesh, size,
                     suggestion->long_name, Setting(keys.units, suggestion->name),
                     Setting(keys.scale, fmt::format("{:g}", suggestion->metres)));
}

ScaledMesh LoadScaledMesh(const std::string& path, const std::optional<double>& scale,
                          const std::optional<std::string>& units, const MeshScaleKeys& keys) {
  ScaledMesh out;
  out.scale = ResolveMeshScale(scale, units, keys);
  // LoadMesh refuses sizes outside kLengthRange (geometry::kMinMeshSize … kMaxMeshSize)
  out.mesh = geometry::LoadMesh(path, out.scale);
  out.across = MeshAcross(out.mesh);
  out.warning = MeshSizeWarning(path, out.across, out.scale, keys);
  return out;
}

}  // namespace ecpsim::engine
