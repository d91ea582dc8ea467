// model: auto is the hull model on the stability maps' scenarios too (issue 11): at every value
// of every map, at the coarsest and a fine step, the two run step for step to the same outcome —
// both complete, or both fail at the same step — with trajectories equal to the solver's
// tolerance (tests/engine/auto_model_test.cpp does the shipped scenes).

#include <cmath>
#include <string>

#include <gtest/gtest.h>

#include "evaluation/stability_map.h"
#include "tests/engine/auto_comparison.h"

namespace ecpsim::evaluation {
namespace {

// m, m/s, rad, rad/s: as tests/engine/auto_model_test.cpp's kAgreement (both solve the same
// MNCP to the relative tolerance 1e-12; 1e-10 leaves two orders for a run's steps to add up).
// The impact map's bodies reach 100 m/s, so its velocities are compared relative to the speed
constexpr double kAgreement = 1e-10;
// s: the steps compared, the coarsest of the maps' and a fine one
constexpr double kSteps[] = {0.01, 0.002};

TEST(StabilityMapAutoTest, AutoReachesTheHullModelsOutcomeAndTrajectoryOnEveryMapValue) {
  for (const StabilityMapSpec& map : StabilityMaps(std::string(ECPSIM_SOURCE_DIR) + "/scenes")) {
    for (const double value : map.values) {
      for (const double h : kSteps) {
        Scenario scenario = map.scenario(value);
        scenario.scene.h = h;
        const long steps = std::lround(scenario.scene.duration / h);
        // a push couples the pusher and the box: from there the hull model's own answer is
        // determined only to its creep's resolution (engine/README.md, "Bodies and contacts")
        const bool coupled = map.name == "push_speed";
        const engine::testing::AutoHullComparison c =
            engine::testing::CompareAutoWithHull(scenario.scene, steps, coupled);
        const std::string where =
            map.name + " " + std::to_string(value) + " h = " + std::to_string(h);
        EXPECT_EQ(c.auto_failed_at, c.hull_failed_at) << where;
        EXPECT_LE(c.difference, kAgreement) << where;
        if (!coupled && c.hull_failed_at < 0) {
          EXPECT_EQ(c.steps, steps) << where;
        }
      }
    }
  }
}

}  // namespace
}  // namespace ecpsim::evaluation
