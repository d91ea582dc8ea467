#pragma once
// How every table and chart of `ecpsim bench` shows its methods: in one order (the sweep's) and
// each with one look (line colour, point and dash), so a method reads the same everywhere.

#include <algorithm>
#include <string>
#include <vector>

namespace ecpsim::app {

/// The names of evaluation::AllMethods() in their order (the order the sweeps run them).
std::vector<std::string> MethodOrder();

/// The gnuplot style of `method`'s line ("lc rgb '#08306b' pt 7", dashed for an engine's
/// default settings); a grey one for a name it does not know.
std::string MethodLineStyle(const std::string& method);

/// The distinct values of `field(row)` over `rows`, in the order of `canonical` (the order the
/// sweep runs them), then any others in first-seen order: merged shards interleave their rows.
template <typename Row, typename Field>
std::vector<std::string> InOrder(const std::vector<Row>& rows, Field field,
                                 const std::vector<std::string>& canonical) {
  std::vector<std::string> seen;
  for (const Row& r : rows) {
    if (std::find(seen.begin(), seen.end(), field(r)) == seen.end()) seen.push_back(field(r));
  }
  std::vector<std::string> names;
  for (const std::string& name : canonical) {
    if (std::find(seen.begin(), seen.end(), name) != seen.end()) names.push_back(name);
  }
  for (const std::string& name : seen) {
    if (std::find(names.begin(), names.end(), name) == names.end()) names.push_back(name);
  }
  return names;
}

/// A row's method, for InOrder.
template <typename Row>
std::string MethodOf(const Row& r) {
  return r.method;
}

}  // namespace ecpsim::app
