#pragma once
// The per-engine factories behind MakeExternalSimulation (one translation unit per engine, each
// compiled only when its library is found).

#include <memory>

#include "baselines/external_simulation.h"

namespace ecpsim::baselines {

std::unique_ptr<ExternalSimulation> MakeMujocoSimulation(FrictionSetting setting,
                                                         const engine::Scene& scene);
std::unique_ptr<ExternalSimulation> MakeBulletSimulation(FrictionSetting setting,
                                                         const engine::Scene& scene);
std::unique_ptr<ExternalSimulation> MakeOdeSimulation(FrictionSetting setting,
                                                      const engine::Scene& scene);

}  // namespace ecpsim::baselines
