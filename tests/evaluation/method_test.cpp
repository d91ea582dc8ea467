// The methods' steppers (evaluation/method.h): MakeStepper checks the scene a sweep hands it
// (a scenario's, edited: its h per run) as every route into a Scene is checked.

#include "evaluation/method.h"

#include <algorithm>
#include <string>

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include "engine/scene_io/scene_validation.h"
#include "evaluation/scenario.h"
#include "evaluation/stability_map.h"
#include "evaluation/trajectory_run.h"
#include "evaluation/work_precision.h"

namespace ecpsim::evaluation {
namespace {

using ::testing::HasSubstr;
using ::testing::ThrowsMessage;

const std::string kScenesDir = std::string(ECPSIM_SOURCE_DIR) + "/scenes";

Scenario SlideScenario() {
  for (Scenario& s : WorkPrecisionScenarios(kScenesDir, 0.5)) {
    if (s.name == "slide") return s;
  }
  ADD_FAILURE() << "no slide scenario";
  return {};
}

TEST(MakeStepperTest, RejectsAZeroTimeStepNamingH) {
  engine::Scene scene = SlideScenario().scene;
  scene.h = 0;
  for (const char* method : {"hull", "point"}) {
    EXPECT_THAT([&] { MakeStepper(FindMethod(method), scene); },
                ThrowsMessage<engine::SceneError>(
                    HasSubstr("h = 0: expected a finite time step > 0 s: a time in")))
        << method;
  }
}

TEST(MakeStepperTest, RejectsANegativeMassNamingTheBody) {
  Scenario slide = SlideScenario();
  slide.scene.bodies[0].mass = -1;
  EXPECT_THAT([&] { MakeStepper(FindMethod("hull"), slide.scene); },
              ThrowsMessage<engine::SceneError>(
                  HasSubstr("bodies[0].mass = -1: expected a mass of body \"box\" that is")));
  // a trajectory run steps through MakeStepper, so it stops there too
  EXPECT_THROW(RunTrajectory(FindMethod("hull"), slide, 0.01), engine::SceneError);
}

// what the sweeps hand MakeStepper: each scenario at each step size of the work–precision sweep
// (its references at a 16th of the smallest), each stability map's scenario at each of its values
TEST(MakeStepperTest, EverySweepScenarioPassesValidationAtEveryStepSize) {
  SweepOptions sweep;
  std::vector<double> steps = sweep.steps;
  steps.push_back(*std::min_element(steps.begin(), steps.end()) / sweep.reference_divisor);
  const std::vector<Scenario> scenarios = WorkPrecisionScenarios(kScenesDir, 0.5);
  EXPECT_EQ(scenarios.size(), WorkPrecisionScenarioNames().size());
  for (const Scenario& scenario : scenarios) {
    for (double h : steps) {
      engine::Scene scene = scenario.scene;
      scene.h = h;
      EXPECT_NO_THROW(engine::ValidateScene(scene)) << scenario.name << " at h = " << h;
    }
  }
  const std::vector<StabilityMapSpec> maps = StabilityMaps(kScenesDir);
  EXPECT_EQ(maps.size(), 4u);  // impact, thin_plate, tbar_mass_ratio, push_speed
  for (const StabilityMapSpec& map : maps) {
    EXPECT_FALSE(map.values.empty()) << map.name;
    for (double value : map.values) {
      const Scenario scenario = map.scenario(value);
      for (double h : sweep.steps) {
        engine::Scene scene = scenario.scene;
        scene.h = h;
        EXPECT_NO_THROW(engine::ValidateScene(scene))
            << map.name << " " << value << " at h = " << h;
      }
    }
  }
}

}  // namespace
}  // namespace ecpsim::evaluation
