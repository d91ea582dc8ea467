#pragma once
// `model: auto`: per island and step the cheapest model whose answer is the hull model's —
// closed-form free flight, the planar sliding model where its solution provably solves the hull
// MNCP, else the hull MNCP (engine/README.md, "model: auto").

#include "engine/contact_model.h"
#include "engine/models/hull_model.h"
#include "engine/scene.h"
#include "engine/step_workspace.h"

namespace ecpsim::engine {

class AutoModel final : public ContactModelStepper {
 public:
  AutoModel(const Scene& scene, StepWorkspace& workspace)
      : scene_(scene), workspace_(workspace), hull_(scene, workspace) {}
  /// The planar step when the island is one body lying flat on one plane obstacle and moving in
  /// it (AcceptsPlanarStep), and its solution keeps the ECP on the support face; otherwise the
  /// hull model's step with `effort` (which takes free flight in closed form by itself).
  AdvanceResult Advance(const Island& island, double t, double h, IslandState& state,
                        Effort effort) const override;
  bool HasLastResort() const override { return true; }

 private:
  const Scene& scene_;
  StepWorkspace& workspace_;
  HullModel hull_;
};

}  // namespace ecpsim::engine
