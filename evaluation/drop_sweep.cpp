#include "evaluation/drop_sweep.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>

#include <fmt/format.h>

#include "common/errors.h"
#include "engine/report/penetration.h"
#include "engine/scene_io/scene_yaml.h"
#include "engine/state.h"
#include "engine/step_report.h"
#include "engine/time_step.h"
#include "evaluation/cpu_budget.h"
#include "evaluation/csv_file.h"
#include "evaluation/seeded_random.h"
#include "geometry/convex_shape.h"
#include "geometry/mass_properties.h"
#include "geometry/mesh_io.h"

namespace ecpsim::evaluation {
namespace {

namespace fs = std::filesystem;
using Eigen::Vector3d;

constexpr double kUnitSize = 1;  // m: DropStep::kScaled steps a body of this size with kDropStep

// a mesh's companions in a collection folder, never meshes themselves
const char* const kCompanionExtensions[] = {".png", ".jpg", ".jpeg", ".tga", ".bmp", ".dds",
                                            ".gif", ".tif", ".tiff", ".ktx", ".mtl", ".txt",
                                            ".md",  ".bin", ".glsl", ".pdf", ".html"};

double WallSeconds() {
  return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();
}

// the seed of a case's pose stream: the kind (or the file's name — not its path, so a mesh
// collection unpacked anywhere draws the same poses) and the seed
SeededRandom PoseRandom(const DropCase& c) {
  const std::string source = c.kind == kFileKind ? fs::path(c.path).filename().string() : c.kind;
  return SeededRandom(c.seed, StableHash("drop pose " + source));
}

MeshKind KindNamed(const std::string& name) {
  for (MeshKind kind : AllMeshKinds()) {
    if (name == MeshKindName(kind)) return kind;
  }
  std::string choices;
  for (MeshKind kind : AllMeshKinds()) choices += std::string(MeshKindName(kind)) + ", ";
  throw InputError(
      fmt::format("drop sweep kind '{}': expected one of {}{}", name, choices, kFileKind));
}

void CentreAndNormalize(geometry::TriangleMesh& mesh) {
  Vector3d lo = Vector3d::Constant(INFINITY), hi = Vector3d::Constant(-INFINITY);
  for (const Vector3d& v : mesh.vertices) lo = lo.cwiseMin(v), hi = hi.cwiseMax(v);
  const double diagonal = (hi - lo).norm();
  ECPSIM_DEMAND(diagonal > 0);  // LoadMesh rejects files without a non-degenerate triangle
  for (Vector3d& v : mesh.vertices) v = (v - (lo + hi) / 2) / diagonal;
}

double Energy(const engine::Scene& scene, const engine::BodyState& b) {
  const engine::Body& body = scene.bodies[0];
  const Eigen::Matrix3d R = b.Q_WB.toRotationMatrix();
  const Eigen::Matrix3d I_W = R * body.inertia * R.transpose();
  return 0.5 * body.mass * b.v_WB.squaredNorm() + 0.5 * b.w_WB.dot(I_W * b.w_WB) -
         body.mass * scene.gravity.dot(b.p_WB);
}

std::string Exact(double value) { return fmt::format("{:.17g}", value); }

// drop_sweep.csv's columns, in order: a case's pose exactly, what it measured in short
using Row = DropRow;
constexpr int kExactDigits = 17;  // significant digits: a double reads back as it was
constexpr int kShortDigits = 6;   // measurements: penetration, energy, effort, time
const std::vector<CsvColumn<Row>> kColumns = {
    TextColumn<Row>("kind", &Row::kind),
    WholeColumn<Row>("seed", &Row::seed),
    EnumColumn<Row>("step", DropStepName, kDropStepCount, &Row::step),
    TextColumn<Row>("mesh", &Row::mesh),
    NumberColumn<Row>("size", kExactDigits, &Row::size),
    WholeColumn<Row>("vertices", &Row::vertices),
    WholeColumn<Row>("hull_faces", &Row::hull_faces),
    NumberColumn<Row>("height", kExactDigits, &Row::height),
    NumberColumn<Row>("q_w", kExactDigits, [](auto& row) -> decltype(auto) { return row.q0.w(); }),
    NumberColumn<Row>("q_x", kExactDigits, [](auto& row) -> decltype(auto) { return row.q0.x(); }),
    NumberColumn<Row>("q_y", kExactDigits, [](auto& row) -> decltype(auto) { return row.q0.y(); }),
    NumberColumn<Row>("q_z", kExactDigits, [](auto& row) -> decltype(auto) { return row.q0.z(); }),
    NumberColumn<Row>("w_x", kExactDigits, [](auto& row) -> decltype(auto) { return row.w0.x(); }),
    NumberColumn<Row>("w_y", kExactDigits, [](auto& row) -> decltype(auto) { return row.w0.y(); }),
    NumberColumn<Row>("w_z", kExactDigits, [](auto& row) -> decltype(auto) { return row.w0.z(); }),
    NumberColumn<Row>("h", kExactDigits, &Row::h),
    NumberColumn<Row>("duration", kExactDigits, &Row::duration),
    EnumColumn<Row>("outcome", DropOutcomeName, kDropOutcomeCount, &Row::outcome),
    WholeColumn<Row>("steps", &Row::steps),
    NumberColumn<Row>("max_penetration_rel", kShortDigits, &Row::max_penetration_rel),
    NumberColumn<Row>("energy_gain_rel", kShortDigits, &Row::energy_gain_rel),
    NumberColumn<Row>("final_speed_rel", kShortDigits, &Row::final_speed_rel),
    WholeColumn<Row>("iterations_max", &Row::iterations_max),
    WholeColumn<Row>("retries", &Row::retries),
    WholeColumn<Row>("substepped", &Row::substepped),
    NumberColumn<Row>("cpu_s", kShortDigits, &Row::cpu_s),
    NumberColumn<Row>("wall_s", kShortDigits, &Row::wall_s),
    NumberColumn<Row>("max_step_cpu_s", kShortDigits, &Row::max_step_cpu_s),
    TextColumn<Row>("message", &Row::message),
};

// the sweep's order of kinds: the generated ones, then the collection's files
int KindRank(const std::string& kind) {
  for (MeshKind k : AllMeshKinds()) {
    if (kind == MeshKindName(k)) return static_cast<int>(k);
  }
  return kMeshKindCount;
}

}  // namespace

const char* DropStepName(DropStep step) {
  switch (step) {
    case DropStep::kFixed:
      return "fixed";
    case DropStep::kScaled:
      return "scaled";
  }
  return "unknown";
}

std::string DropCaseKey(const DropCase& c) {
  return fmt::format("{}:{}{}", c.kind == kFileKind ? c.path : c.kind, c.seed,
                     c.step == DropStep::kScaled ? ":scaled" : "");
}

DropCase ParseDropCaseKey(const std::string& full_key) {
  const std::string kScaledSuffix = ":scaled";
  const bool scaled = full_key.size() > kScaledSuffix.size() &&
                      full_key.compare(full_key.size() - kScaledSuffix.size(), kScaledSuffix.size(),
                                       kScaledSuffix) == 0;
  const std::string key =
      scaled ? full_key.substr(0, full_key.size() - kScaledSuffix.size()) : full_key;
  const size_t colon = key.rfind(':');
  const std::string name = colon == std::string::npos ? key : key.substr(0, colon);
  const std::string seed = colon == std::string::npos ? "" : key.substr(colon + 1);
  if (name.empty() || seed.empty() || seed.find_first_not_of("0123456789") != std::string::npos ||
      seed.size() > 18) {
    throw InputError(
        fmt::format("drop case '{}': expected KIND:SEED (e.g. convex:17) or "
                    "MESH_FILE:SEED with a whole seed, optionally then :scaled",
                    full_key));
  }
  DropCase c;
  c.seed = std::stoull(seed);
  c.step = scaled ? DropStep::kScaled : DropStep::kFixed;
  for (MeshKind kind : AllMeshKinds()) {
    if (name == MeshKindName(kind)) {
      c.kind = name;
      return c;
    }
  }
  std::error_code error;
  if (!fs::is_regular_file(name, error)) {
    throw InputError(
        fmt::format("drop case '{}': '{}' is neither a mesh kind nor a file", full_key, name));
  }
  c.kind = kFileKind;
  c.path = name;
  return c;
}

const char* DropOutcomeName(DropOutcome outcome) {
  switch (outcome) {
    case DropOutcome::kOk:
      return "ok";
    case DropOutcome::kSolverFailure:
      return "solver_failure";
    case DropOutcome::kNonFinite:
      return "non_finite";
    case DropOutcome::kEnergyGain:
      return "energy_gain";
    case DropOutcome::kPenetration:
      return "penetration";
    case DropOutcome::kCpuLimit:
      return "cpu_limit";
    case DropOutcome::kException:
      return "exception";
    case DropOutcome::kSkipped:
      return "skipped";
  }
  return "unknown";
}

bool IsDropFailure(DropOutcome outcome) {
  return outcome != DropOutcome::kOk && outcome != DropOutcome::kSkipped;
}

DropCase DropRow::Case() const {
  DropCase c;
  c.kind = kind;
  c.seed = seed;
  c.step = step;
  if (kind == kFileKind) c.path = mesh;
  return c;
}

UnitMesh MakeUnitMesh(const DropCase& c) {
  if (c.kind != kFileKind) {
    GeneratedMesh generated = GenerateMesh(KindNamed(c.kind), c.seed);
    return {std::move(generated.mesh), std::move(generated.description)};
  }
  UnitMesh unit{geometry::LoadMesh(c.path), c.path};
  CentreAndNormalize(unit.mesh);
  // closed, consistently wound, not flat: the mass-property checks (their result is unused)
  geometry::ComputeMassProperties(unit.mesh, kDropDensity, c.path);
  return unit;
}

DropPose DrawDropPose(const DropCase& c) {
  SeededRandom random = PoseRandom(c);
  DropPose pose;
  pose.size = random.LogUniform(kDropMinSize, kDropMaxSize);
  pose.q0 = random.Rotation();
  pose.height = random.Uniform(kDropMinHeight, kDropMaxHeight) * pose.size;
  const double g = engine::Scene().gravity.norm();
  pose.w0 = random.Uniform(0, kDropMaxSpin) * std::sqrt(g / pose.size) * random.UnitVector();
  // kScaled: the time unit sqrt(size / g) relative to a 1 m body's
  const double time_scale = c.step == DropStep::kScaled ? std::sqrt(pose.size / kUnitSize) : 1;
  pose.h = kDropStep * time_scale;
  // long enough to fall, then to tumble and settle; a whole number of steps
  const double fall = std::sqrt(2 * pose.height / g);
  const double settle = kDropSettleTimes * std::sqrt(pose.size / g);
  const double least = kDropMinDuration * time_scale;
  pose.duration = pose.h * std::ceil(std::max(least, fall + settle) / pose.h - 1e-9);
  return pose;
}

geometry::TriangleMesh ScaleUnitMesh(const UnitMesh& unit, double size) {
  geometry::TriangleMesh mesh = unit.mesh;
  for (Vector3d& v : mesh.vertices) v = (v * size).cast<float>().cast<double>();
  return mesh;
}

namespace {

std::string DropName(const DropCase& c) {
  // a file's stem alone may repeat across a collection's folders: its path's hash tells apart
  const std::string mesh = c.kind == kFileKind
                               ? fmt::format("{}-{:06x}", fs::path(c.path).stem().string(),
                                             StableHash(c.path) & 0xffffff)
                               : c.kind;
  return fmt::format("{}_{}{}", mesh, c.seed, c.step == DropStep::kScaled ? "_scaled" : "");
}

}  // namespace

DropFiles WriteDropFiles(const DropCase& c, const UnitMesh& unit, const std::string& dir) {
  const DropPose pose = DrawDropPose(c);
  DropFiles files;
  files.name = DropName(c);
  files.obj_path = (fs::path(dir) / (files.name + ".obj")).string();
  files.yaml_path = (fs::path(dir) / (files.name + ".yaml")).string();
  fs::create_directories(dir);
  geometry::SaveMesh(ScaleUnitMesh(unit, pose.size), files.obj_path);
  // the scene format's default ground friction is `ecpsim drop`'s (mu 0.22, e = 1, 1, 0.1 m)
  const std::string yaml = fmt::format(
      "# drop sweep case {key} ({mesh}); rerun it with\n"
      "#   ecpsim bench --no-work-precision --no-stability --drop-case {key}\n"
      "# or drop this scene with ecpsim run: the sweep loads these very files\n"
      "duration: {duration}\n"
      "h: {h}\n"
      "ground: {{}}\n"
      "bodies:\n"
      "  - name: body\n"
      "    mesh: {name}.obj  # bounding-box diagonal {size} m\n"
      "    density: {density}\n"
      "    quaternion: [{qw}, {qx}, {qy}, {qz}]\n"
      "    lowest_point_height: {height}\n"
      "    angular_velocity: [{wx}, {wy}, {wz}]\n",
      fmt::arg("key", DropCaseKey(c)), fmt::arg("mesh", unit.description),
      fmt::arg("duration", Exact(pose.duration)), fmt::arg("h", Exact(pose.h)),
      fmt::arg("name", files.name), fmt::arg("size", Exact(pose.size)),
      fmt::arg("density", Exact(kDropDensity)), fmt::arg("qw", Exact(pose.q0.w())),
      fmt::arg("qx", Exact(pose.q0.x())), fmt::arg("qy", Exact(pose.q0.y())),
      fmt::arg("qz", Exact(pose.q0.z())), fmt::arg("height", Exact(pose.height)),
      fmt::arg("wx", Exact(pose.w0.x())), fmt::arg("wy", Exact(pose.w0.y())),
      fmt::arg("wz", Exact(pose.w0.z())));
  std::ofstream out(files.yaml_path);
  out << yaml;
  out.close();
  if (!out) throw InputError(fmt::format("{}: cannot write the scene", files.yaml_path));
  return files;
}

namespace {

// the row of a case before it runs: what it is and its drawn pose
DropRow CaseRow(const DropCase& c, const std::string& mesh) {
  DropRow row;
  row.kind = c.kind;
  row.seed = c.seed;
  row.step = c.step;
  row.mesh = mesh;
  const DropPose pose = DrawDropPose(c);
  row.h = pose.h;
  row.size = pose.size;
  row.height = pose.height;
  row.q0 = pose.q0;
  row.w0 = pose.w0;
  row.duration = pose.duration;
  return row;
}

}  // namespace

DropRow RunDropCase(const DropCase& c, const UnitMesh& unit, const std::string& dir,
                    double cpu_limit_s) {
  DropRow row = CaseRow(c, unit.description);
  row.vertices = static_cast<int>(unit.mesh.vertices.size());
  const double size = row.size;
  const double wall_start = WallSeconds();
  try {
    const engine::Scene scene = engine::LoadScene(WriteDropFiles(c, unit, dir).yaml_path).scene;
    const engine::Body& body = scene.bodies[0];
    if (const auto* hull = body.hull->AsPolyhedron()) {
      row.hull_faces = static_cast<int>(hull->hull().faces.size());
    }

    const double g = scene.gravity.norm();
    const double energy_scale = body.mass * g * size;
    const engine::PenetrationProbe probe(scene);
    engine::State state = engine::InitialState(scene);
    const double energy0 = Energy(scene, state.bodies[0]);
    const long steps = std::lround(scene.duration / scene.h);
    engine::StepWorkspace workspace;
    // the limit stops a step of minutes within a solver iteration of it
    CpuBudget budget(cpu_limit_s);
    engine::StopStepsOn(workspace, budget.flag());
    const auto limit_reached = [&] {
      row.outcome = DropOutcome::kCpuLimit;
      row.message = fmt::format("CPU limit of {} s reached at t = {} s", cpu_limit_s, state.t);
    };
    for (long k = 1; k <= steps; ++k) {
      engine::StepReport report;
      CpuBudget::Outcome charged = CpuBudget::Outcome::kWithin;
      const double used_before = budget.used_s();
      try {
        charged = budget.Charge([&] { report = engine::Step(scene, state, workspace); });
      } catch (const engine::SolverFailure& failure) {
        row.outcome = DropOutcome::kSolverFailure;
        row.message = failure.what();
      }
      row.cpu_s = budget.used_s();
      row.max_step_cpu_s = std::max(row.max_step_cpu_s, budget.used_s() - used_before);
      // (a step the limit stopped is undone: the state is the last step's)
      if (charged == CpuBudget::Outcome::kStopped) limit_reached();
      if (row.outcome != DropOutcome::kOk) break;
      const engine::BodyState& b = state.bodies[0];
      if (!engine::IsFinite(b)) {
        row.outcome = DropOutcome::kNonFinite;
        row.message = fmt::format("non-finite state at t = {} s", state.t);
        break;
      }
      row.steps = k;
      row.iterations_max = std::max(row.iterations_max, report.iterations);
      row.retries += report.retries;
      row.substepped += report.substeps > 1;
      row.max_penetration_rel =
          std::max(row.max_penetration_rel, probe.MaxDepth(scene, state) / size);
      row.energy_gain_rel =
          std::max(row.energy_gain_rel, (Energy(scene, b) - energy0) / energy_scale);
      row.final_speed_rel = (b.v_WB.norm() + size * b.w_WB.norm()) / std::sqrt(g * size);
      if (charged == CpuBudget::Outcome::kSpent) {
        limit_reached();
        break;
      }
    }
    if (row.outcome == DropOutcome::kOk && row.energy_gain_rel > kDropEnergyGainBar) {
      row.outcome = DropOutcome::kEnergyGain;
      row.message = fmt::format("energy rose by {:.3g} m |g| size", row.energy_gain_rel);
    } else if (row.outcome == DropOutcome::kOk && row.max_penetration_rel > kDropPenetrationBar) {
      row.outcome = DropOutcome::kPenetration;
      row.message = fmt::format("a mesh vertex {:.3g} × size deep", row.max_penetration_rel);
    }
  } catch (const std::exception& error) {
    row.outcome = DropOutcome::kException;
    row.message = error.what();
  }
  row.wall_s = WallSeconds() - wall_start;
  return row;
}

std::vector<std::string> CollectionFiles(const std::vector<std::string>& dirs) {
  std::vector<std::string> files;
  for (const std::string& dir : dirs) {
    std::error_code error;
    if (!fs::is_directory(dir, error)) {
      throw InputError(fmt::format("mesh collection '{}': no such folder", dir));
    }
    for (const fs::directory_entry& entry : fs::recursive_directory_iterator(dir)) {
      if (!entry.is_regular_file()) continue;
      std::string extension = entry.path().extension().string();
      std::transform(extension.begin(), extension.end(), extension.begin(),
                     [](unsigned char ch) { return static_cast<char>(std::tolower(ch)); });
      const bool companion =
          std::find(std::begin(kCompanionExtensions), std::end(kCompanionExtensions), extension) !=
          std::end(kCompanionExtensions);
      if (!companion) files.push_back(entry.path().string());
    }
  }
  std::sort(files.begin(), files.end());
  return files;
}

DropPlan PlanDropSweep(const DropSweepOptions& o) {
  // the groups in order: one per generated case, one per file (all its poses)
  DropPlan groups;
  if (!o.only.empty()) {
    for (const std::string& key : o.only) groups.push_back({ParseDropCaseKey(key)});
  } else {
    bool files = o.kinds.empty();
    std::vector<MeshKind> kinds = o.kinds.empty() ? AllMeshKinds() : std::vector<MeshKind>{};
    for (const std::string& name : o.kinds) {
      if (name == kFileKind) {
        files = true;
      } else {
        kinds.push_back(KindNamed(name));
      }
    }
    for (MeshKind kind : kinds) {
      for (int seed = 0; seed < o.seeds_per_kind; ++seed) {
        std::vector<DropCase> steps;
        for (DropStep step : o.steps) {
          steps.push_back(DropCase{MeshKindName(kind), "", static_cast<std::uint64_t>(seed), step});
        }
        groups.push_back(steps);
      }
    }
    if (files) {
      std::vector<std::string> paths = CollectionFiles(o.mesh_dirs);
      if (o.max_files >= 0 && static_cast<int>(paths.size()) > o.max_files) {
        paths.resize(o.max_files);
      }
      for (const std::string& path : paths) {
        std::vector<DropCase> poses;
        for (int pose = 0; pose < o.poses_per_file; ++pose) {
          for (DropStep step : o.steps) {
            poses.push_back(DropCase{kFileKind, path, static_cast<std::uint64_t>(pose), step});
          }
        }
        groups.push_back(poses);
      }
    }
  }
  return groups;
}

std::vector<DropRow> RunDropSweep(const DropSweepOptions& o) {
  return RunDropSweep(o, PlanDropSweep(o));
}

std::vector<DropRow> RunDropSweep(const DropSweepOptions& o, const DropPlan& groups) {
  ECPSIM_DEMAND(o.shard_count >= 1 && o.shard_index >= 1 && o.shard_index <= o.shard_count);
  ECPSIM_DEMAND(!o.scratch_dir.empty() && !o.failures_dir.empty());
  std::vector<DropRow> rows;
  std::map<std::string, std::pair<int, int>> ok_of_kind;  // kind → (ok, cases), for progress
  for (size_t g = 0; g < groups.size(); ++g) {
    if (static_cast<int>(g % o.shard_count) != o.shard_index - 1 || groups[g].empty()) continue;
    const DropCase& first = groups[g].front();
    UnitMesh unit;
    try {
      unit = MakeUnitMesh(first);
    } catch (const InputError& error) {
      // a file that is not a closed solid is not part of the sweep; a generated mesh that is
      // rejected is a failure of each of its cases
      if (first.kind == kFileKind) {
        DropRow skipped;
        skipped.kind = kFileKind;
        skipped.mesh = first.path;
        skipped.outcome = DropOutcome::kSkipped;
        skipped.message = error.what();
        rows.push_back(skipped);
        continue;
      }
      for (const DropCase& c : groups[g]) {
        rows.push_back(CaseRow(c, "(rejected)"));
        rows.back().outcome = DropOutcome::kException;
        rows.back().message = error.what();
      }
      continue;
    }
    for (const DropCase& c : groups[g]) {
      rows.push_back(RunDropCase(c, unit, o.scratch_dir, o.cpu_limit_s));
      // a failed case's files are its reproduction; a passed case's are not kept
      const bool failed = IsDropFailure(rows.back().outcome);
      if (failed) {
        fs::create_directories(o.failures_dir);
        // a message naming the case's files names them where they are kept
        std::string& message = rows.back().message;
        const std::string scratch = (fs::path(o.scratch_dir) / "").string();
        const std::string kept = (fs::path(o.failures_dir) / "").string();
        for (size_t at = message.find(scratch); at != std::string::npos;
             at = message.find(scratch, at + kept.size())) {
          message.replace(at, scratch.size(), kept);
        }
      }
      for (const char* extension : {".obj", ".yaml"}) {
        const fs::path file = fs::path(o.scratch_dir) / (DropName(c) + extension);
        std::error_code missing;  // a case that failed before writing its files has none
        if (!fs::exists(file, missing)) continue;
        if (failed) {
          fs::rename(file, fs::path(o.failures_dir) / file.filename());
        } else {
          fs::remove(file);
        }
      }
      auto& [ok, cases] = ok_of_kind[c.kind];
      ok += rows.back().outcome == DropOutcome::kOk;
      ++cases;
      if (o.progress && IsDropFailure(rows.back().outcome)) {
        o.progress(fmt::format("drop {}: {}: {:.200}", DropCaseKey(c),
                               DropOutcomeName(rows.back().outcome), rows.back().message));
      }
    }
  }
  std::error_code not_empty;  // the scratch folder goes when nothing is left in it
  fs::remove(o.scratch_dir, not_empty);
  if (o.progress) {
    for (const auto& [kind, counts] : ok_of_kind) {
      o.progress(
          fmt::format("drop sweep {}: {} of {} cases ok", kind, counts.first, counts.second));
    }
  }
  return rows;
}

void SortDropRows(std::vector<DropRow>& rows) {
  std::stable_sort(rows.begin(), rows.end(), [](const DropRow& a, const DropRow& b) {
    const int ka = KindRank(a.kind), kb = KindRank(b.kind);
    if (ka != kb) return ka < kb;
    if (a.kind == kFileKind && a.mesh != b.mesh) return a.mesh < b.mesh;
    if (a.seed != b.seed) return a.seed < b.seed;
    return a.step < b.step;
  });
}

std::string DropSweepCsv(const std::vector<DropRow>& rows) { return WriteCsv(kColumns, rows); }

std::vector<DropRow> ReadDropSweepCsv(const std::string& path) { return ReadCsv(path, kColumns); }

}  // namespace ecpsim::evaluation
