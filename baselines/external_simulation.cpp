#include "baselines/external_simulation.h"

#include <fmt/format.h>

#include "baselines/engine_adapters.h"
#include "common/errors.h"

namespace ecpsim::baselines {

const char* ExternalEngineName(ExternalEngine engine) {
  switch (engine) {
    case ExternalEngine::kMujoco:
      return "mujoco";
    case ExternalEngine::kBullet:
      return "bullet";
    case ExternalEngine::kOde:
      return "ode";
  }
  return "unknown";
}

bool IsAvailable(ExternalEngine engine) {
  switch (engine) {
    case ExternalEngine::kMujoco:
#ifdef ECPSIM_HAVE_MUJOCO
      return true;
#else
      return false;
#endif
    case ExternalEngine::kBullet:
#ifdef ECPSIM_HAVE_BULLET
      return true;
#else
      return false;
#endif
    case ExternalEngine::kOde:
#ifdef ECPSIM_HAVE_ODE
      return true;
#else
      return false;
#endif
  }
  return false;
}

std::unique_ptr<ExternalSimulation> MakeExternalSimulation(ExternalEngine engine,
                                                           [[maybe_unused]] FrictionSetting setting,
                                                           const engine::Scene& scene) {
  if (!IsAvailable(engine)) {
    throw InputError(fmt::format(
        "{}: this build has no {} (install the Debian package lib{}-dev with scripts/setup.sh "
        "and reconfigure)",
        scene.source, ExternalEngineName(engine), ExternalEngineName(engine)));
  }
  switch (engine) {
#ifdef ECPSIM_HAVE_MUJOCO
    case ExternalEngine::kMujoco:
      return MakeMujocoSimulation(setting, scene);
#endif
#ifdef ECPSIM_HAVE_BULLET
    case ExternalEngine::kBullet:
      return MakeBulletSimulation(setting, scene);
#endif
#ifdef ECPSIM_HAVE_ODE
    case ExternalEngine::kOde:
      return MakeOdeSimulation(setting, scene);
#endif
    default:
      break;
  }
  // IsAvailable said yes, so its factory is compiled in
  ECPSIM_DEMAND(!"an available engine without a factory");
  return nullptr;
}

}  // namespace ecpsim::baselines
