#pragma once
// The ranges of scene values, each derived from what the engine computes from it; shared by the
// YAML loader, ValidateScene, `ecpsim drop` and the CLI's option checks (docs/scene_format.md).

#include <string>

#include "geometry/mesh_bounds.h"

namespace ecpsim::engine {

/// Every physical scale and every quantity derived from them (volume, mass, inertia, impulse) is
/// squared somewhere in the engine (residual norms, |r|², ω·Iω); its square stays a finite,
/// normal double while |x| lies in [sqrt(DBL_MIN), sqrt(DBL_MAX)] ≈ [1.5e-154, 1.3e154]. These
/// are the round bounds inside that interval.
inline constexpr double kMinMagnitude = 1e-150;
inline constexpr double kMaxMagnitude = 1e150;

/// m: one range for every length of a scene, meshes (geometry/mesh_bounds.h, where the reason is:
/// L¹⁰ within 1e±200) and primitives alike.
inline constexpr double kMinLength = geometry::kMinMeshSize;
inline constexpr double kMaxLength = geometry::kMaxMeshSize;

/// Mesh unit conversions (`scale`, `--scale`): micrometres (1e-6) to thousands of kilometres
/// (1e6) per mesh unit, every unit a mesh file is written in; wider factors only turn a wrong
/// unit into coordinates that overflow.
inline constexpr double kMinMeshScale = 1e-6;
inline constexpr double kMaxMeshScale = 1e6;

/// The engine's time after k steps is t = k·h (engine::State::steps), one rounding of an exact
/// integer times h, not a sum of k roundings; below 2^52 steps consecutive times stay distinct
/// (fl((k+1)h) − fl(kh) ≥ h − (2k+1)·2^-53·h > 0). A run that long would take years.
inline constexpr long kMaxSteps = 1L << 52;

/// A body's vertices in world coordinates carry a round-off of ε·|p|; within 1e6 body sizes of
/// the origin that is ≤ 2.2e-10 of its size, below the engine's geometric tolerances (1e-9 of
/// the size, hull_model.cpp, multipatch_model.cpp).
inline constexpr double kMaxDistanceInSizes = 1e6;

/// × the body's size (bounding-box diagonal): an initial pose whose mesh reaches deeper into an
/// obstacle is an error unless allowed. Bodies placed by on_ground, by hand to 6 significant
/// digits, or from single-precision mesh files (relative error 6e-8) stay within it; a deeper
/// overlap is a placement error that the first step would undo with an impulse.
inline constexpr double kInitialPenetrationTolerance = 1e-6;

/// m: `hull`, `drop` and scenes warn about meshes whose bounding-box diagonal lies outside
/// [1 mm, 10 m]: a part file in the wrong unit (mm read as m is 1000× too large).
inline constexpr double kMinPlausibleMeshSize = 1e-3;
inline constexpr double kMaxPlausibleMeshSize = 10;

/// Newton iterations per attempt: quadratic convergence needs tens; 1e4 bounds the time a
/// failing step can stall a run and keeps the models' iteration budgets (a small multiple of
/// it) far inside int.
inline constexpr int kMaxSolverIterations = 10'000;
/// Vertex rings around the support vertex: 1000 rings span every hull of fewer than about a
/// million faces (use_window: false takes all faces of any hull); bounded so ring counts stay
/// far inside int.
inline constexpr int kMaxWindowRings = 1'000;

/// Body and obstacle names prefix CSV columns: letters, digits, '_' and '-', not empty.
bool IsValidName(const std::string& name);
inline constexpr const char* kNameExpected =
    "a name of letters, digits, '_' and '-' (it prefixes CSV columns)";

/// A closed range [min, max] of a positive quantity, for checks and messages.
struct PositiveRange {
  const char* noun;  // "mass"
  const char* unit;  // "kg"; empty for dimensionless
  double min;
  double max;
};

inline constexpr PositiveRange kMassRange{"mass", "kg", kMinMagnitude, kMaxMagnitude};
inline constexpr PositiveRange kDensityRange{"density", "kg/m³", kMinMagnitude, kMaxMagnitude};
inline constexpr PositiveRange kLengthRange{"length", "m", kMinLength, kMaxLength};
inline constexpr PositiveRange kTimeRange{"time", "s", kMinMagnitude, kMaxMagnitude};
inline constexpr PositiveRange kInertiaRange{"principal moment of inertia", "kg·m²", kMinMagnitude,
                                             kMaxMagnitude};
inline constexpr PositiveRange kMagnitudeRange{"value", "", kMinMagnitude, kMaxMagnitude};
inline constexpr PositiveRange kMeshScaleRange{"scale", "", kMinMeshScale, kMaxMeshScale};

/// "" when `value` lies in `range` (NaN never does), else what was expected, e.g.
/// "a mass in [1e-150, 1e150] kg".
std::string OutOfRange(double value, const PositiveRange& range);

/// "" when |value| ≤ kMaxMagnitude (NaN never is), else "a finite number within ±1e150".
std::string OutOfMagnitude(double value);

/// The number of steps a run of `duration` takes with step `h` (both > 0): ceil(duration / h),
/// a ratio within 1e-9 of an integer counting as that integer (0.5 / 0.01 is 50 steps).
/// Precondition: duration / h ≤ kMaxSteps (ValidateScene), so the count fits a long.
long PlannedSteps(double duration, double h);

/// "" when a run of `duration` with step `h` (finite, > 0) takes 1..kMaxSteps steps, else what
/// was expected, naming the step count.
std::string StepCountProblem(double duration, double h);

}  // namespace ecpsim::engine
