#include "app/method_style.h"

#include <utility>

#include "evaluation/method.h"

namespace ecpsim::app {

std::vector<std::string> MethodOrder() {
  std::vector<std::string> names;
  for (const evaluation::Method& m : evaluation::AllMethods()) names.push_back(m.name);
  return names;
}

// ecpsim's models in blues and oranges, each engine its own hue, its default settings dashed
std::string MethodLineStyle(const std::string& method) {
  static const std::vector<std::pair<std::string, std::string>> kStyles = {
      {"hull", "lc rgb '#08306b' pt 7"},
      {"hull-tol1e-08", "lc rgb '#2171b5' pt 6"},
      {"hull-tol1e-05", "lc rgb '#6baed6' pt 4"},
      {"auto", "lc rgb '#a50f15' pt 3"},
      {"auto-least-energy", "lc rgb '#41ab5d' pt 8"},
      {"planar", "lc rgb '#ff7f00' pt 9"},
      {"multipatch", "lc rgb '#e6ab02' pt 11"},
      {"point", "lc rgb '#7f3b08' pt 5"},
      {"mujoco-default", "lc rgb '#e7298a' pt 7 dt 2"},
      {"mujoco-coulomb", "lc rgb '#e7298a' pt 7"},
      {"bullet-default", "lc rgb '#1b9e77' pt 13 dt 2"},
      {"bullet-coulomb", "lc rgb '#1b9e77' pt 13"},
      {"ode-default", "lc rgb '#7570b3' pt 15 dt 2"},
      {"ode-coulomb", "lc rgb '#7570b3' pt 15"}};
  for (const auto& [name, style] : kStyles) {
    if (name == method) return style;
  }
  return "lc rgb '#555555' pt 1";
}

}  // namespace ecpsim::app
