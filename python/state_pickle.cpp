#include "python/state_pickle.h"

#include <string>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "common/errors.h"
#include "engine/report/state_record.h"

namespace ecpsim::python {
namespace {

namespace py = pybind11;

constexpr const char* kTag = "ecpsim.State";
// the tuple's layout; a change of it or of the record (say, a new field of State) takes the next
// number, so an old pickle is refused by name rather than read wrongly
constexpr int kVersion = 3;  // 3: the state as a state record (engine/report/state_record.h)

}  // namespace

py::tuple StateToTuple(const engine::State& state) {
  return py::make_tuple(kTag, kVersion, engine::StateRecord(state).dump());
}

engine::State StateFromTuple(const py::tuple& data) {
  if (data.size() != 3 || !py::isinstance<py::str>(data[0]) ||
      data[0].cast<std::string>() != kTag || !py::isinstance<py::int_>(data[1]) ||
      data[1].cast<int>() != kVersion || !py::isinstance<py::str>(data[2])) {
    throw InputError(fmt::format(
        "State pickle {}: expected ('{}', {}, record) as pickled by this version of ecpsim",
        py::repr(data[0]).cast<std::string>(), kTag, kVersion));
  }
  nlohmann::json record;
  try {
    record = nlohmann::json::parse(data[2].cast<std::string>());
  } catch (const nlohmann::json::exception& e) {
    throw InputError(fmt::format("State pickle: the record is no JSON ({})", e.what()));
  }
  return engine::StateFromRecord(record, "State pickle: state");
}

}  // namespace ecpsim::python
