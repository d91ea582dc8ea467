#pragma once
// A State's bodies and contacts as numpy arrays and Python dicts for the `ecpsim` module, and
// arrays written back into a State.

#include <string>

#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>

#include "engine/scene.h"
#include "engine/state.h"
#include "engine/step_report.h"

namespace ecpsim::python {

/// A contact's name, "<body>.<other>" (the other a body or an obstacle), as trajectory.csv's
/// columns name it; a side that touches with one of its parts carries its index, "cube.cup[2]".
std::string ContactName(const engine::Scene& scene, const engine::ContactPair& pair);

/// A per-body quantity of the state.
enum class BodyField { kPosition, kQuaternion, kVelocity, kAngularVelocity };

/// Its name as the module's attribute ("positions", "quaternions", ...).
const char* FieldName(BodyField field);

/// `field` of every body: an (n, 3) array, (n, 4) as w, x, y, z for quaternions.
pybind11::array_t<double> BodyArray(const engine::State& state, BodyField field);

/// Requires `state`'s bodies apart from the obstacles and from each other (engine::FindOverlap,
/// the check of a scene's initial poses).
/// @throws InputError "WHERE: body 'A' is D m inside obstacle|body 'B' ..." naming the pair, the
///         depth and how to allow it.
void RequireApart(const engine::Scene& scene, const engine::State& state, const std::string& where);

/// Writes an (n, 3) or (n, 4) array into the state's dynamic bodies; kinematic bodies' rows must
/// equal their current values (their motion sets them), and new poses be apart (RequireApart).
/// @throws InputError naming the field, the row and what was expected.
void SetBodyArray(const engine::Scene& scene, engine::State& state, BodyField field,
                  const pybind11::handle& value);

/// The step's report as a dict (converged, iterations, residual, retries, substeps, models).
pybind11::dict ReportDict(const engine::Scene& scene, const engine::StepReport& report);

/// What a force/torque sensor on kinematic body `body` read over the last step (engine::
/// SensorWrench): a (6,) array, force (N) and moment (N·m) about the body's reference point,
/// world axes — trajectory.csv's `<K>.fx … mz`.
pybind11::array_t<double> SensorArray(const engine::Scene& scene, const engine::State& state,
                                      int body);

/// Every contact of the state as one dict of arrays, a row per contact in the scene's order:
/// the numbers of ContactList stacked ((k,) or (k, 3)), names, modes and models as lists.
pybind11::dict ContactArrays(const engine::Scene& scene, const engine::State& state,
                             const engine::StepReport& report);

/// Every contact of the state as a dict: its name, mode, ECPs, impulses and forces.
pybind11::list ContactList(const engine::Scene& scene, const engine::State& state,
                           const engine::StepReport& report);

}  // namespace ecpsim::python
