#include "evaluation/auto_cost.h"

#include <algorithm>
#include <map>
#include <utility>

#include "evaluation/median.h"

namespace ecpsim::evaluation {
namespace {

// CPU per simulated second of a run that completed and measured some time, else nothing
bool Measured(const WorkPrecisionRow& r) { return !r.failed && r.cpu_per_sim_s > 0; }

}  // namespace

std::vector<AutoCost> CompareAutoWithHull(const std::vector<WorkPrecisionRow>& rows) {
  std::vector<std::string> scenarios;
  // (scenario, h) → the hull model's CPU per simulated second
  std::map<std::pair<std::string, double>, double> hull;
  for (const WorkPrecisionRow& r : rows) {
    if (std::find(scenarios.begin(), scenarios.end(), r.scenario) == scenarios.end())
      scenarios.push_back(r.scenario);
    if (r.method == "hull" && Measured(r)) hull[{r.scenario, r.h}] = r.cpu_per_sim_s;
  }
  std::vector<AutoCost> costs;
  for (const std::string& scenario : scenarios) {
    AutoCost cost;
    cost.scenario = scenario;
    std::vector<double> ratios;
    for (const WorkPrecisionRow& r : rows) {
      if (r.scenario != scenario || r.method != "auto" || !Measured(r)) continue;
      const auto it = hull.find({scenario, r.h});
      if (it == hull.end()) continue;
      const double ratio = r.cpu_per_sim_s / it->second;
      ratios.push_back(ratio);
      if (ratio > cost.largest) {
        cost.largest = ratio;
        cost.largest_h = r.h;
      }
    }
    if (ratios.empty()) continue;
    cost.steps = static_cast<int>(ratios.size());
    cost.median = Median(std::move(ratios));
    costs.push_back(cost);
  }
  return costs;
}

}  // namespace ecpsim::evaluation
