#pragma once
// A State as plain Python values and back, for pickle (State.__getstate__/__setstate__): so a
// saved state crosses processes (multiprocessing, Dask) and files bit for bit.

#include <pybind11/pybind11.h>

#include "engine/state.h"

namespace ecpsim::python {

/// The whole of `state` — time, step count, every body's pose and velocities, every contact's
/// solution and its model's warm start — as ("ecpsim.State", version, record): the record is
/// engine/report/state_record.h's JSON as text, whose exact doubles make
/// StateFromTuple(StateToTuple(s)) equal s bit for bit.
pybind11::tuple StateToTuple(const engine::State& state);

/// The State a tuple of StateToTuple describes.
/// @throws InputError naming the part that does not have StateToTuple's form (a tuple not made
///         by this version, a record that is no JSON, a key of the record and what it expected).
///         Whether it fits a scene is Simulation::SetState's check.
engine::State StateFromTuple(const pybind11::tuple& data);

}  // namespace ecpsim::python
