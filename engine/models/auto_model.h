#pragma once
// `model: auto`: per island and step the cheapest model whose answer is the hull model's —
// closed-form free flight, the planar sliding model where its solution provably solves the hull
// MNCP, else the hull MNCP (engine/README.md, "model: auto").

#include "engine/contact_model.h"
#include "engine/models/hull_model.h"
#include "engine/scene.h"

namespace ecpsim::engine {

class AutoModel final : public ContactModelStepper {
 public:
  explicit AutoModel(const Scene& scene) : scene_(scene), hull_(scene) {}
  /// The planar step when the island is one body lying flat on one plane obstacle and moving in
  /// it (AcceptsPlanarStep), and its solution keeps the ECP on the support face; otherwise the
  /// hull model's step with `effort` (which takes free flight in closed form by itself).
  AdvanceResult Advance(const Island& island, double t, double h, IslandState& state,
                        Effort effort) const override;
  bool HasLastResort() const override { return true; }

 private:
  const Scene& scene_;
  HullModel hull_;
};

}  // namespace ecpsim::engine
