#include "evaluation/method.h"

#include <algorithm>

#include <fmt/format.h>

#include "common/errors.h"
#include "engine/report/contact_wrench.h"
#include "engine/scene_io/scene_validation.h"
#include "engine/time_step.h"

namespace ecpsim::evaluation {
namespace {

// The hull model's residual tolerances a sweep tries: the default, and two looser ones that
// trade accuracy for Newton iterations.
constexpr double kHullTolerances[] = {1e-12, 1e-8, 1e-5};

class EcpsimStepper final : public Stepper {
 public:
  EcpsimStepper(const Method& method, const engine::Scene& scene) : scene_(scene) {
    scene_.model = method.model;
    scene_.solver.tolerance = method.tolerance;
    scene_.solver.selection = method.selection;
    state_ = engine::InitialState(scene_);
  }
  void Step() override { iterations_ = engine::Step(scene_, state_, workspace_).iterations; }
  void StopOn(const CancelFlag* flag) override { engine::StopStepsOn(workspace_, flag); }
  const engine::State& state() const override { return state_; }
  int iterations() const override { return iterations_; }
  Eigen::Vector3d ContactForce(int body, int other) const override {
    // each pair's force on its G side, the opposite on its F side
    Eigen::Vector3d force = Eigen::Vector3d::Zero();
    for (size_t k = 0; k < scene_.contacts.size(); ++k) {
      const engine::ContactPair& pair = scene_.contacts[k];
      if (!pair.WithBody()) continue;
      const double sign = pair.other_body == body && pair.body == other   ? 1
                          : pair.other_body == other && pair.body == body ? -1
                                                                          : 0;
      if (sign != 0) {
        force += sign * engine::WrenchOnOther(scene_, state_, static_cast<int>(k), scene_.h).force;
      }
    }
    return force;
  }

 private:
  engine::Scene scene_;
  engine::State state_;
  engine::StepWorkspace workspace_;
  int iterations_ = 0;
};

class ExternalStepper final : public Stepper {
 public:
  ExternalStepper(const Method& method, const engine::Scene& scene)
      : simulation_(baselines::MakeExternalSimulation(method.engine, method.setting, scene)) {}
  void Step() override { simulation_->Step(); }
  void StopOn(const CancelFlag*) override {}
  const engine::State& state() const override { return simulation_->state(); }
  int iterations() const override { return 0; }
  Eigen::Vector3d ContactForce(int body, int other) const override {
    return simulation_->ContactForce(body, other);
  }

 private:
  std::unique_ptr<baselines::ExternalSimulation> simulation_;
};

}  // namespace

std::vector<Method> AllMethods() {
  std::vector<Method> methods;
  for (double tolerance : kHullTolerances) {
    Method hull;
    hull.model = engine::ContactModel::kHull;
    hull.tolerance = tolerance;
    hull.name = tolerance == kHullTolerances[0] ? "hull" : fmt::format("hull-tol{:.0e}", tolerance);
    methods.push_back(hull);
  }
  // the default model: the hull model's answer at the cheapest model's cost per step
  Method automatic;
  automatic.model = engine::ContactModel::kAuto;
  automatic.tolerance = kHullTolerances[0];
  automatic.name = engine::ContactModelName(engine::ContactModel::kAuto);
  methods.push_back(automatic);
  // and with `solver.selection: least_energy`: where contacts between bodies share a load or a
  // moment statically indeterminately, the exact solution of least elastic energy
  // (engine/README.md, "Steps whose solutions form a set")
  Method least_energy = automatic;
  least_energy.selection = engine::Selection::kLeastEnergy;
  least_energy.in_default_set = false;
  least_energy.name = "auto-least-energy";
  methods.push_back(least_energy);
  for (engine::ContactModel model :
       {engine::ContactModel::kPlanar, engine::ContactModel::kMultiPatch,
        engine::ContactModel::kPoint}) {
    Method method;
    method.model = model;
    method.name = engine::ContactModelName(model);
    methods.push_back(method);
  }
  for (baselines::ExternalEngine engine :
       {baselines::ExternalEngine::kMujoco, baselines::ExternalEngine::kBullet,
        baselines::ExternalEngine::kOde}) {
    if (!baselines::IsAvailable(engine)) continue;
    for (baselines::FrictionSetting setting :
         {baselines::FrictionSetting::kDefault, baselines::FrictionSetting::kCoulomb}) {
      Method method;
      method.external = true;
      method.engine = engine;
      method.setting = setting;
      method.name =
          fmt::format("{}-{}", baselines::ExternalEngineName(engine),
                      setting == baselines::FrictionSetting::kDefault ? "default" : "coulomb");
      methods.push_back(method);
    }
  }
  return methods;
}

std::vector<Method> DefaultMethods() {
  std::vector<Method> methods = AllMethods();
  methods.erase(std::remove_if(methods.begin(), methods.end(),
                               [](const Method& m) { return !m.in_default_set; }),
                methods.end());
  return methods;
}

Method FindMethod(const std::string& name) {
  std::string choices;
  for (const Method& method : AllMethods()) {
    if (method.name == name) return method;
    choices += (choices.empty() ? "" : ", ") + method.name;
  }
  throw InputError(fmt::format("method '{}': expected one of {}", name, choices));
}

std::unique_ptr<Stepper> MakeStepper(const Method& method, const engine::Scene& scene) {
  // a sweep edits the scenes it was given (h per run, a shorter duration): the edited one is the
  // scene that runs, so it is the one checked
  engine::ValidateScene(scene);
  if (method.external) return std::make_unique<ExternalStepper>(method, scene);
  return std::make_unique<EcpsimStepper>(method, scene);
}

}  // namespace ecpsim::evaluation
