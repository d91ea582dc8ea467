#pragma once
// The drop sweep (issue 14): generated meshes and the closed meshes of a public collection,
// each scaled to a random size in [1e-3, 1e2] m and dropped at a random orientation, spin and
// height onto the ground; per case the outcome, the penetration relative to the size, the
// solver's effort and the time. Each case runs from its own files (a mesh and a scene for
// `ecpsim run`), so a failure's files reproduce it exactly. Rows that shards write and a merge
// joins.

#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "evaluation/mesh_generators.h"
#include "geometry/triangle_mesh.h"

namespace ecpsim::evaluation {

// the bars: no failure, and no mesh vertex deeper in the ground than this × the size
constexpr double kDropPenetrationBar = 1e-9;  // × size (bounding-box diagonal)
// energy may not rise above its start by more than this × m |g| size: the scheme dissipates
// (implicit Euler loses ½ g² h² per unit mass per step in free flight, contact only takes
// energy out), so a gain this large (the stability maps' 1 % bar, here of the body's own
// potential-energy scale) is a numerical blow-up
constexpr double kDropEnergyGainBar = 1e-2;  // × m |g| size

constexpr double kDropMinSize = 1e-3;   // m, bounding-box diagonal, drawn log-uniformly ...
constexpr double kDropMaxSize = 1e2;    // m ... up to this
constexpr double kDropDensity = 1000;   // kg/m³, water (`ecpsim drop`'s default)
constexpr double kDropStep = 0.01;      // s, h of DropStep::kFixed; of kScaled at size 1 m
constexpr double kDropMinDuration = 1;  // s, at least (kScaled: × sqrt(size / 1 m))
// after the fall, this many free-fall times sqrt(size / g) to bounce, tumble and settle
constexpr double kDropSettleTimes = 10;
// lowest hull point at t = 0 above the ground, × size
constexpr double kDropMinHeight = 0.05, kDropMaxHeight = 1;
// initial spin about a random axis up to this × sqrt(g / size) rad/s
constexpr double kDropMaxSpin = 1;

/// The kind name of a collection file's cases.
inline constexpr const char* kFileKind = "file";

/// The step size of a case: the same for every size, or scaled with sqrt(size), which makes
/// every case the dimensionless image (time in units of sqrt(size / g)) of a drop at size 1 m:
/// for a scale-free solver only the mesh and pose then differ between cases.
enum class DropStep {
  kFixed,   // h = kDropStep, duration max(kDropMinDuration, fall + settle)
  kScaled,  // h = kDropStep sqrt(size / 1 m), duration max(kDropMinDuration sqrt(size / 1 m), …)
};
constexpr int kDropStepCount = 2;
const char* DropStepName(DropStep step);  // fixed, scaled

/// Which mesh a case drops (a generated kind and seed, or a collection file and its pose
/// number `seed`) and with which step; its size and pose are drawn from the seed.
struct DropCase {
  std::string kind;  // a MeshKindName, or kFileKind
  std::string path;  // kind "file": the mesh file
  std::uint64_t seed = 0;
  DropStep step = DropStep::kFixed;
};

/// "convex:17", "convex:17:scaled", or "path/to/mesh.off:2" for a file: what `ecpsim bench
/// --drop-case` takes.
std::string DropCaseKey(const DropCase& c);
/// @throws InputError for a key that is not KIND:SEED or PATH:SEED (with an existing file),
///         optionally followed by :scaled.
DropCase ParseDropCaseKey(const std::string& key);

/// How a case ended; a case whose files do not load (its mesh rejected) ends as kException.
enum class DropOutcome {
  kOk = 0,
  kSolverFailure,  // engine::Step threw SolverFailure
  kNonFinite,      // the state stopped being finite
  kEnergyGain,     // energy rose by more than kDropEnergyGainBar × m |g| size
  kPenetration,    // a mesh vertex deeper than kDropPenetrationBar × size
  kCpuLimit,       // the steps took longer than the CPU limit
  kException,      // anything else thrown (InputError loading the scene, ...)
  kSkipped,        // a collection file that does not load or is not a closed solid
};
constexpr int kDropOutcomeCount = 8;
const char* DropOutcomeName(DropOutcome outcome);  // ok, solver_failure, non_finite, ...
/// Every outcome but ok and skipped.
bool IsDropFailure(DropOutcome outcome);

/// A case's mesh before scaling: bounding box centred at 0, diagonal 1.
struct UnitMesh {
  geometry::TriangleMesh mesh;
  std::string description;  // the generator's parameters, or the file's path
};

/// The unit mesh of a case: generated, or loaded (geometry::LoadMesh), centred and scaled to
/// diagonal 1, whatever the file's units, and checked to be a closed solid.
/// @throws InputError naming the file when it does not load or fails the mass-property checks.
UnitMesh MakeUnitMesh(const DropCase& c);

/// A case's size and initial pose, drawn from its seed.
struct DropPose {
  double size = 0;  // m, bounding-box diagonal, log-uniform in [kDropMinSize, kDropMaxSize]
  Eigen::Quaterniond q0 = Eigen::Quaterniond::Identity();  // body → world, uniform
  double height = 0;  // m, lowest hull point above the ground: [kDropMinHeight, kDropMaxHeight]
                      // × size
  Eigen::Vector3d w0 = Eigen::Vector3d::Zero();  // rad/s, world; a random axis
  double h = 0;                                  // s, by the case's DropStep
  double duration = 0;  // s, whole steps: to fall, then kDropSettleTimes sqrt(size / g)
};
/// The same for a case's two DropSteps but for h and the duration.
DropPose DrawDropPose(const DropCase& c);

/// `unit` scaled to `size` metres, every coordinate rounded to float: what a mesh file holds,
/// so the saved OBJ is this very mesh.
geometry::TriangleMesh ScaleUnitMesh(const UnitMesh& unit, double size);

/// The files of a case: `<name>.obj` (ScaleUnitMesh, metres) and `<name>.yaml`, a scene for
/// `ecpsim run` dropping it: density kDropDensity, `ecpsim drop`'s friction (the scene format's
/// defaults), the drawn orientation, lowest point height and spin, h and duration. `name` is
/// the kind (or the file's stem and a hash of its path), the seed and the step.
struct DropFiles {
  std::string name;
  std::string obj_path, yaml_path;
};
/// Writes them into `dir` (created if missing).
/// @throws InputError if they cannot be written.
DropFiles WriteDropFiles(const DropCase& c, const UnitMesh& unit, const std::string& dir);

struct DropRow {
  std::string kind;
  std::uint64_t seed = 0;
  DropStep step = DropStep::kFixed;
  std::string mesh;  // the generator's parameters, or the file's path
  double size = 0;   // m
  int vertices = 0, hull_faces = 0;
  double height = 0;                                       // m
  Eigen::Quaterniond q0 = Eigen::Quaterniond::Identity();  // body → world at t = 0
  Eigen::Vector3d w0 = Eigen::Vector3d::Zero();            // rad/s, world
  double h = 0, duration = 0;                              // s
  DropOutcome outcome = DropOutcome::kOk;
  long steps = 0;                  // completed
  double max_penetration_rel = 0;  // max over steps of the deepest mesh vertex ÷ size
  double energy_gain_rel = 0;      // max over steps of (E − E(0)) ÷ (m |g| size), ≥ 0
  double final_speed_rel = 0;      // (|v| + size |ω|) ÷ sqrt(|g| size) at the end
  int iterations_max = 0;          // Newton iterations of one step
  long retries = 0;                // restarts of the ladder, summed over steps
  long substepped = 0;             // steps that needed h/2 or h/4
  double cpu_s = 0, wall_s = 0;    // of the steps
  double max_step_cpu_s = 0;       // the slowest step
  std::string message;             // the failure's or the skip's reason

  DropCase Case() const;
};

/// Runs one case: writes its files into `dir` (WriteDropFiles), loads the scene from them
/// (engine::LoadScene) and steps it (engine::Step) to its duration. Never throws for what the
/// case does: every exception is the row's outcome. The files stay in `dir`.
DropRow RunDropCase(const DropCase& c, const UnitMesh& unit, const std::string& dir,
                    double cpu_limit_s);

struct DropSweepOptions {
  std::vector<std::string> kinds;      // MeshKindNames and "file" to run; empty: all
  int seeds_per_kind = 120;            // generated cases 0 … n−1 of each kind
  std::vector<std::string> mesh_dirs;  // collection folders, searched recursively
  int poses_per_file = 3;
  std::vector<DropStep> steps = {DropStep::kFixed, DropStep::kScaled};  // each case at each
  int max_files = -1;             // ≥ 0: only the first files in path order
  std::vector<std::string> only;  // case keys: run these (and nothing else)
  double cpu_limit_s = 300;       // per case
  std::string scratch_dir;        // where cases write their files (emptied as they pass)
  std::string failures_dir;       // where a failed case's files are moved
  int shard_index = 1, shard_count = 1;
  std::function<void(const std::string&)> progress;
};

/// The files a sweep tries from `dirs`, in path order: every regular file but images, material
/// libraries, text and binary buffers (a mesh's companions).
/// @throws InputError naming a folder that does not exist.
std::vector<std::string> CollectionFiles(const std::vector<std::string>& dirs);

/// The sweep's cases cut into groups, in order: each generated mesh with its step sizes, each
/// collection file with all its poses and step sizes (loaded once).
using DropPlan = std::vector<std::vector<DropCase>>;

/// The plan of `options`' sweep, every option checked (no mesh is made or loaded): a caller
/// that runs other work first (ecpsim bench) rejects a bad option before any of it.
/// @throws InputError for an unknown kind in options.kinds, a bad key in options.only or a
///         collection folder that does not exist.
DropPlan PlanDropSweep(const DropSweepOptions& options);

/// Runs this shard's part of `plan` (PlanDropSweep(options) unless given): group g (0-based)
/// belongs to shard (g mod N) + 1. A file that does not load or is not closed gives one
/// kSkipped row. The files of every failed case end up in options.failures_dir.
/// @throws InputError as PlanDropSweep.
std::vector<DropRow> RunDropSweep(const DropSweepOptions& options);
std::vector<DropRow> RunDropSweep(const DropSweepOptions& options, const DropPlan& plan);

/// Rows in the sweep's order (generated kinds in AllMeshKinds order by seed, then files by
/// path and pose; fixed before scaled), e.g. after a merge.
void SortDropRows(std::vector<DropRow>& rows);

std::string DropSweepCsv(const std::vector<DropRow>& rows);
/// @throws InputError naming file, line and column for a malformed file.
std::vector<DropRow> ReadDropSweepCsv(const std::string& path);

}  // namespace ecpsim::evaluation
