#pragma once
// Frames of a simulation: a FrameInput from an engine::Scene and its engine::State, with each
// contact's actual patch extracted against its plane obstacle.

#include <memory>
#include <optional>
#include <vector>

#include "engine/scene.h"
#include "engine/state.h"
#include "engine/step_report.h"
#include "render/frame_input.h"

namespace ecpsim::render {

/// Holds the scene's display geometry (mesh copies, hull and obstacle tessellations) so that the
/// renderer's GPU buffers are made once, and builds one FrameInput per state. The scene must
/// outlive the builder and not change.
class SceneFrameBuilder {
 public:
  explicit SceneFrameBuilder(const engine::Scene& scene);

  /// The frame at `state`: bodies posed by (p_WB, Q_WB); for each contact with a plane obstacle
  /// (one linear constraint, e.g. MakeHalfSpace, or a one-face polyhedron) the actual patch of
  /// the body's mesh (geometry::ExtractContactPatch: the vertices within 1e-6 of the body's
  /// bounding radius of the plane, plus the gap to a declared hull primitive), the centre of mass
  /// projected on the plane;
  /// for every contact in touch (p_n > 0 or a non-empty patch) the ECP a1 and the force
  /// (p_n n + p_t t + p_o o)/h. Other obstacles are drawn as fixed grey bodies. `iterations`
  /// (< 0: unknown) and what solved each body's step (`models`, per body; empty: unknown) go
  /// to the text overlay.
  /// @throws InputError if the state does not match the scene (counts) or is not finite.
  FrameInput Build(const engine::State& state, int iterations = -1,
                   const std::vector<engine::StepModel>& models = {}) const;

 private:
  // the patch tolerance for `body` at pose X_WB: geometry::ContactPatchTolerance plus the gap
  // between its hull's and its mesh's lowest points
  double PatchTolerance(int body, const Eigen::Isometry3d& X_WB,
                        const geometry::Plane& plane) const;

  const engine::Scene& scene_;
  std::vector<std::shared_ptr<const geometry::TriangleMesh>> meshes_;  // per body, body frame
  std::vector<std::shared_ptr<const HullGeometry>> hulls_;             // per body, body frame
  std::vector<std::optional<geometry::Plane>> planes_;                 // per obstacle
  std::vector<std::shared_ptr<const geometry::TriangleMesh>> obstacle_meshes_;  // non-planes
  double force_scale_ = 0;                                                      // m/N
};

}  // namespace ecpsim::render
