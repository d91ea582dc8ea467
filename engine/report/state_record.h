#pragma once
// A State as JSON, exactly: the one serialization of a state, which checkpoints
// (app/checkpoint.h) and Python's pickles (python/state_pickle.h) both embed. Every double is a
// C99 hexadecimal float, which reads back to the same bits; warm starts are typed by the model
// that wrote them.

#include <string>

#include <Eigen/Core>
#include <nlohmann/json.hpp>

#include "engine/state.h"

namespace ecpsim::engine {

/// `value` as a C99 hexadecimal float ("0x1.999999999999ap-4"), which reads back to the same
/// bits, infinities and NaN included: the exact form of every double of a record.
nlohmann::json ExactJson(double value);
/// `values` as a list of ExactJson numbers.
nlohmann::json ExactJson(const Eigen::VectorXd& values);

/// The double of an ExactJson number.
/// @throws InputError `<key> = "<text>": expected a hexadecimal float`.
double ReadExact(const nlohmann::json& node, const std::string& key);

/// The `size` doubles (any number for size −1) of an ExactJson list.
/// @throws InputError `<key>: expected a list of <size> hexadecimal floats`, or ReadExact's.
Eigen::VectorXd ReadExactVector(const nlohmann::json& node, const std::string& key,
                                Eigen::Index size);

/// {"t", "steps", "bodies": [{p_WB, Q_WB_wxyz, v_WB, w_WB}], "contacts": [{a1, a2, p_n, p_t,
/// p_o, p_r, sigma, n, t, o, warm_start}], "rest": {steps, models, residuals, in_step}}, a warm start null,
/// {"model": "hull", s, l_g, window, l, other_window, trend} or {"model": "multipatch", parts};
/// `rest` is the sleep rule's memory (RestRecord), its models by StepModelName.
nlohmann::json StateRecord(const State& state);

/// The State of a StateRecord. Whether it fits a scene is the caller's check (its counts of
/// bodies and contacts, the sizes of its warm starts).
/// @throws InputError naming the key under `where` (e.g. "state.contacts[0].warm_start.l") and
///         what was expected: a missing key, a value of the wrong type, a number that is no
///         hexadecimal float, a list of another length, an unknown warm-start model.
State StateFromRecord(const nlohmann::json& record, const std::string& where);

}  // namespace ecpsim::engine
