// ODE (libode-dev 0.16.2, double precision) stepping an ecpsim scene: each body a dBody at its CM
// with the full inertia tensor and a dCreateConvex geom of its hull, and one of each part its
// pairs touch (a kinematic body a dBodySetKinematic body set to its prescribed pose and twist
// before every step), each half-space a dCreatePlane, contact joints made in the near callback of
// every step for the scene's contact pairs, body–body and part ones included (settings and
// measurements: baselines/ode.md).

#include <cmath>
#include <cstdarg>
#include <cstdio>
#include <deque>
#include <memory>
#include <mutex>
#include <optional>
#include <stdexcept>
#include <vector>

#include <fmt/format.h>
#include <ode/ode.h>

#include "baselines/adapter_inputs.h"
#include "baselines/engine_adapters.h"
#include "common/errors.h"
#include "engine/loads.h"
#include "engine/step_report.h"
#include "geometry/convex_hull.h"

namespace ecpsim::baselines {
namespace {

using Eigen::Matrix3d;
using Eigen::Quaterniond;
using Eigen::Vector3d;

/// Contacts dCollide may return per body–obstacle pair: a hull on a plane gets one per vertex
/// under it, and no hull of these scenes has more than 16 vertices on one face (a box 4, the
/// desk's support square 4, the T-bar's and dumbbell's flat faces fewer than 16).
constexpr int kMaxContacts = 16;

/// Predicted slip speed below which a kCoulomb contact keeps ODE's two default friction directions
/// (μ each), m/s: a contact with no tangential tendency has no slip direction to align with, and
/// below 1e-9 m/s (1e-11 m per 0.01 s step) the direction is round-off.
constexpr double kSlipDirectionSpeed = 1e-9;

/// What the two settings change (baselines/ode.md gives the sources and measurements).
struct OdeSettings {
  bool dantzig_step = false;     // dWorldStep (Dantzig LCP) instead of dWorldQuickStep
  bool slip_aligned = false;     // one friction direction, along the contact's predicted slip
  bool finite_rotation = false;  // Q⁺ = Exp(h ω) Q (ecpsim's update), not ODE's first order
};

OdeSettings SettingsFor(FrictionSetting setting) {
  OdeSettings s;
  if (setting == FrictionSetting::kCoulomb) {
    s.dantzig_step = true;
    s.slip_aligned = true;
    s.finite_rotation = true;
  }
  return s;
}

/// What a geom stands for, reached through dGeomGetData in the near callback.
struct GeomTag {
  bool is_body = false;
  int index = 0;  // into scene.bodies or scene.obstacles
  int part = -1;  // a body's: −1 its hull, else Body::parts[part]
};

/// The hull arrays dCreateConvex points into (ODE does not copy them).
struct ConvexArrays {
  std::vector<dReal> planes;       // a, b, c, d per face: a x + b y + c z = d
  std::vector<dReal> points;       // x, y, z per vertex, body frame
  std::vector<unsigned> polygons;  // per face: its vertex count, then its vertex indices
};

ConvexArrays MakeConvexArrays(const geometry::ConvexHull& hull) {
  ConvexArrays arrays;
  for (size_t f = 0; f < hull.faces.size(); ++f) {
    arrays.planes.insert(arrays.planes.end(), {hull.normals[f].x(), hull.normals[f].y(),
                                               hull.normals[f].z(), hull.offsets[f]});
    arrays.polygons.push_back(static_cast<unsigned>(hull.faces[f].size()));
    for (int v : hull.faces[f]) arrays.polygons.push_back(static_cast<unsigned>(v));
  }
  for (const Vector3d& v : hull.vertices)
    arrays.points.insert(arrays.points.end(), {v.x(), v.y(), v.z()});
  return arrays;
}

// ODE reports an internal error (a failed internal assertion: "ODE INTERNAL ERROR 1: assertion
// "!bSafeNormalize4Fault" failed in dxNormalize4()", a body's quaternion that blew up on
// tbar_push at small h) by aborting the process; its handlers throw this instead, so a run that
// blows ODE up is a failed run of the benchmark, not a crash of it
class OdeInternalError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

[[noreturn]] void ThrowOdeError(int number, const char* format, va_list arguments) {
  char text[512];
  std::vsnprintf(text, sizeof text, format, arguments);
  throw OdeInternalError(fmt::format("ODE internal error {}: {}", number, text));
}

void InitOdeOnce() {
  static std::once_flag once;
  std::call_once(once, [] {
    dInitODE2(0);
    dSetErrorHandler(&ThrowOdeError);
    dSetDebugHandler(&ThrowOdeError);
  });
}

class OdeSimulation final : public ExternalSimulation {
 public:
  OdeSimulation(FrictionSetting setting, const engine::Scene& scene)
      : scene_(scene), settings_(SettingsFor(setting)), friction_(scene) {
    InitOdeOnce();
    // planes first: an obstacle the adapter cannot model is reported before any ODE object exists
    std::vector<HalfSpacePlane> planes;
    for (int o = 0; o < static_cast<int>(scene.obstacles.size()); ++o) {
      planes.push_back(HalfSpaceOf(scene, o, "ODE"));
    }
    std::vector<geometry::ConvexHull> hulls;
    for (size_t b = 0; b < scene.bodies.size(); ++b) {
      const engine::Body& body = scene.bodies[b];
      hulls.push_back(geometry::ComputeConvexHull(
          body.mesh.vertices, fmt::format("{}: bodies[{}] '{}'", scene.source, b, body.name)));
    }
    // a body made of parts also gets a geom per part its pairs touch, on the same dBody: which
    // geoms meet is the scene's pairs' choice (Collide), hull or part
    const std::vector<std::vector<int>> touched = TouchedParts(scene);
    std::size_t pieces = scene.bodies.size();
    for (const std::vector<int>& parts : touched) pieces += parts.size();

    world_ = dWorldCreate();
    space_ = dSimpleSpaceCreate(nullptr);
    contact_group_ = dJointGroupCreate(0);
    dWorldSetGravity(world_, scene.gravity.x(), scene.gravity.y(), scene.gravity.z());

    tags_.reserve(planes.size() + pieces);
    for (int o = 0; o < static_cast<int>(planes.size()); ++o) {
      // ODE's plane a x + b y + c z = d bounds the solid half-space below, as ecpsim's n·y ≤ d
      const HalfSpacePlane& p = planes[static_cast<size_t>(o)];
      dGeomID geom = dCreatePlane(space_, p.normal.x(), p.normal.y(), p.normal.z(), p.offset);
      tags_.push_back(GeomTag{false, o});
      dGeomSetData(geom, &tags_.back());
    }
    convex_arrays_.reserve(pieces);
    const engine::State initial_state = engine::InitialState(scene);
    for (int b = 0; b < static_cast<int>(scene.bodies.size()); ++b) {
      const engine::Body& body = scene.bodies[static_cast<size_t>(b)];
      dBodyID id = dBodyCreate(world_);
      if (body.IsKinematic()) {
        // infinite mass, no gravity: it moves with the velocity set before each step (Step)
        dBodySetKinematic(id);
      } else {
        // the body frame is ecpsim's (origin at the CM), so the full tensor goes in as given
        dMass mass;
        dMassSetParameters(&mass, body.mass, 0, 0, 0, body.inertia(0, 0), body.inertia(1, 1),
                           body.inertia(2, 2), body.inertia(0, 1), body.inertia(0, 2),
                           body.inertia(1, 2));
        dBodySetMass(id, &mass);
      }
      const engine::BodyState& initial = initial_state.bodies[static_cast<size_t>(b)];
      SetPose(id, initial.p_WB, initial.Q_WB);
      dBodySetLinearVel(id, initial.v_WB.x(), initial.v_WB.y(), initial.v_WB.z());
      dBodySetAngularVel(id, initial.w_WB.x(), initial.w_WB.y(), initial.w_WB.z());
      if (settings_.finite_rotation) dBodySetFiniteRotationMode(id, 1);

      AddConvexGeom(id, hulls[static_cast<size_t>(b)], GeomTag{true, b, -1});
      for (int part : touched[static_cast<size_t>(b)]) {
        // ODE's convex–convex collider takes the geom's origin to lie inside it (dCreateConvex
        // warns "Plane does not contain the origin", and the peg was thrown out of its hole):
        // each part's geom is centred on its vertices' mean and offset to it on the body
        const geometry::ConvexHull hull = PartHull(scene, b, part);
        Vector3d centre = Vector3d::Zero();
        for (const Vector3d& v : hull.vertices)
          centre += v / static_cast<double>(hull.vertices.size());
        dGeomID geom =
            AddConvexGeom(id, geometry::TranslateHull(hull, -centre), GeomTag{true, b, part});
        dGeomSetOffsetPosition(geom, centre.x(), centre.y(), centre.z());
      }
      bodies_.push_back(id);
    }
    v_predicted_.assign(bodies_.size(), Vector3d::Zero());
    w_predicted_.assign(bodies_.size(), Vector3d::Zero());
    state_ = engine::InitialState(scene);
    state_.contacts.clear();
  }

  ~OdeSimulation() override {
    dJointGroupDestroy(contact_group_);
    dSpaceDestroy(space_);  // destroys its geoms too (ODE's default cleanup mode)
    dWorldDestroy(world_);
  }

  OdeSimulation(const OdeSimulation&) = delete;
  OdeSimulation& operator=(const OdeSimulation&) = delete;

  void Step() override {
    const double h = scene_.h;
    // the scene's loads as a constant wrench at the CM over the step (ODE clears the
    // accumulators after each step)
    for (size_t b = 0; b < bodies_.size(); ++b) {
      const engine::Body& model = scene_.bodies[b];
      if (model.IsKinematic()) {
        // the prescribed pose at t and the step's twist, which ODE's update c + h v (and, with
        // finite rotation, Exp(h ω) R) carries to the pose at t + h
        const KinematicStep step = KinematicStepOf(model, state_.t, h);
        SetPose(bodies_[b], step.start.p, step.start.q);
        dBodySetLinearVel(bodies_[b], step.twist.v.x(), step.twist.v.y(), step.twist.v.z());
        dBodySetAngularVel(bodies_[b], step.twist.w.x(), step.twist.w.y(), step.twist.w.z());
        v_predicted_[b] = step.twist.v;
        w_predicted_[b] = step.twist.w;
        continue;
      }
      const Matrix3d R_WB = state_.bodies[b].Q_WB.toRotationMatrix();
      const Eigen::Matrix<double, 6, 1> impulse = engine::AppliedImpulse(
          scene_.loads, scene_.impulses, static_cast<int>(b), state_.t, h, R_WB);
      const Vector3d force = impulse.head<3>() / h;
      const Vector3d torque = impulse.tail<3>() / h;
      dBodyAddForce(bodies_[b], force.x(), force.y(), force.z());
      // the velocities without contact at the end of the step, for the slip directions
      const engine::BodyState& body = state_.bodies[b];
      const Matrix3d I_W = R_WB * scene_.bodies[b].inertia * R_WB.transpose();
      v_predicted_[b] = body.v_WB + h * (scene_.gravity + force / scene_.bodies[b].mass);
      w_predicted_[b] = body.w_WB + h * I_W.ldlt().solve(torque);
      dBodyAddTorque(bodies_[b], torque.x(), torque.y(), torque.z());
    }
    feedback_.clear();
    try {
      dSpaceCollide(space_, this, &OdeSimulation::NearCallback);
      if (settings_.dantzig_step) {
        dWorldStep(world_, h);
      } else {
        dWorldQuickStep(world_, h);
      }
    } catch (const OdeInternalError& error) {
      dJointGroupEmpty(contact_group_);
      throw engine::SolverFailure(
          fmt::format("{}: {} at t = {} s", scene_.source, error.what(), state_.t));
    }
    dJointGroupEmpty(contact_group_);
    engine::AdvanceTime(h, state_);
    for (size_t b = 0; b < bodies_.size(); ++b) {
      engine::BodyState& body = state_.bodies[b];
      const dReal* p = dBodyGetPosition(bodies_[b]);
      const dReal* q = dBodyGetQuaternion(bodies_[b]);
      const dReal* v = dBodyGetLinearVel(bodies_[b]);
      const dReal* w = dBodyGetAngularVel(bodies_[b]);
      body.p_WB = Vector3d(p[0], p[1], p[2]);
      body.Q_WB = Quaterniond(q[0], q[1], q[2], q[3]).normalized();
      body.v_WB = Vector3d(v[0], v[1], v[2]);
      body.w_WB = Vector3d(w[0], w[1], w[2]);
    }
    RequireFiniteState("ode", state_, [this](std::size_t b) { return scene_.bodies[b].name; });
  }

  const engine::State& state() const override { return state_; }

  Vector3d ContactForce(int body, int other) const override {
    Vector3d force = Vector3d::Zero();
    for (const ContactFeedback& c : feedback_) {
      const dReal* f = c.body1 == body && c.body2 == other   ? c.forces.f1
                       : c.body2 == body && c.body1 == other ? c.forces.f2
                                                             : nullptr;
      if (f != nullptr) force += Vector3d(f[0], f[1], f[2]);
    }
    return force;
  }

 private:
  // the forces of one contact joint between two bodies in the last step (ODE writes them)
  struct ContactFeedback {
    int body1, body2;  // scene body indices of the joint's bodies 1 and 2
    dJointFeedback forces;
  };

  // a dCreateConvex geom of `hull` (the geom's frame, at the body's origin until offset) on body
  // `id`, standing for `tag`
  dGeomID AddConvexGeom(dBodyID id, const geometry::ConvexHull& hull, const GeomTag& tag) {
    convex_arrays_.push_back(MakeConvexArrays(hull));
    ConvexArrays& arrays = convex_arrays_.back();
    dGeomID geom =
        dCreateConvex(space_, arrays.planes.data(), static_cast<unsigned>(arrays.planes.size() / 4),
                      arrays.points.data(), static_cast<unsigned>(arrays.points.size() / 3),
                      arrays.polygons.data());
    dGeomSetBody(geom, id);
    tags_.push_back(tag);
    dGeomSetData(geom, &tags_.back());
    return geom;
  }

  static void SetPose(dBodyID id, const Vector3d& p, const Quaterniond& q_WB) {
    dBodySetPosition(id, p.x(), p.y(), p.z());
    const Quaterniond q = q_WB.normalized();
    const dQuaternion q_ode = {q.w(), q.x(), q.y(), q.z()};
    dBodySetQuaternion(id, q_ode);
  }

  static void NearCallback(void* data, dGeomID o1, dGeomID o2) {
    static_cast<OdeSimulation*>(data)->Collide(o1, o2);
  }

  // the velocity at world point x, without contact at the end of the step, of the body a geom
  // belongs to (a fixed obstacle: 0)
  Vector3d PredictedVelocity(const GeomTag& tag, const Vector3d& x) const {
    if (!tag.is_body) return Vector3d::Zero();
    const size_t b = static_cast<size_t>(tag.index);
    return v_predicted_[b] + w_predicted_[b].cross(x - state_.bodies[b].p_WB);
  }

  /// Contact joints between two geoms the scene pairs (a body's hull or part and an obstacle, or
  /// two bodies' hulls or parts); any other pair never touches.
  void Collide(dGeomID o1, dGeomID o2) {
    const auto* t1 = static_cast<const GeomTag*>(dGeomGetData(o1));
    const auto* t2 = static_cast<const GeomTag*>(dGeomGetData(o2));
    if (!t1->is_body && !t2->is_body) return;
    const std::optional<engine::Friction> friction =
        t1->is_body && t2->is_body
            ? friction_.PieceWithPiece(t1->index, t1->part, t2->index, t2->part)
        : t1->is_body ? friction_.PieceWithObstacle(t1->index, t1->part, t2->index)
                      : friction_.PieceWithObstacle(t2->index, t2->part, t1->index);
    if (!friction) return;

    dContact contacts[kMaxContacts];
    const int n = dCollide(o1, o2, kMaxContacts, &contacts[0].geom, sizeof(dContact));
    for (int k = 0; k < n; ++k) {
      dContact& c = contacts[k];
      c.surface = dSurfaceParameters{};
      // μ as a Coulomb coefficient (friction ≤ μ × the contact's normal force); without
      // dContactApprox1 ODE reads mu as a force limit in newtons
      c.surface.mode = dContactApprox1;
      c.surface.mu = friction->mu;
      c.surface.bounce = 0;
      if (settings_.slip_aligned) {
        // friction along the slip the contact would have without it (Bullet's default): one
        // direction bounded by μ λ_n, so a sliding contact feels μ λ_n opposite its slip, as in
        // Coulomb's cone, not up to √2 μ λ_n from the pyramid's two independent directions
        const Vector3d x(c.geom.pos[0], c.geom.pos[1], c.geom.pos[2]);
        const Vector3d normal(c.geom.normal[0], c.geom.normal[1], c.geom.normal[2]);
        Vector3d slip = PredictedVelocity(*t1, x) - PredictedVelocity(*t2, x);
        slip -= slip.dot(normal) * normal;
        if (slip.norm() > kSlipDirectionSpeed) {
          slip.normalize();
          c.surface.mode |= dContactFDir1 | dContactMu2;
          c.surface.mu2 = 0;
          c.fdir1[0] = slip.x();
          c.fdir1[1] = slip.y();
          c.fdir1[2] = slip.z();
        }
      }
      // no torsion row: Coulomb friction at the several contact points already resists a spin
      // through their lever arms (ecpsim's e_r models the same resistance for one ECP)
      dJointID joint = dJointCreateContact(world_, contact_group_, &c);
      dJointAttach(joint, dGeomGetBody(o1), dGeomGetBody(o2));
      // between two bodies: ODE reports the joint's force on each (ContactForce)
      if (t1->is_body && t2->is_body) {
        feedback_.push_back({t1->index, t2->index, dJointFeedback{}});
        dJointSetFeedback(joint, &feedback_.back().forces);
      }
    }
  }

  const engine::Scene scene_;  // a copy: the caller's scene may go away
  OdeSettings settings_;
  PairFrictionTable friction_;
  dWorldID world_ = nullptr;
  dSpaceID space_ = nullptr;
  dJointGroupID contact_group_ = nullptr;
  std::vector<GeomTag> tags_;                // reserved up front: geoms point into it
  std::vector<ConvexArrays> convex_arrays_;  // reserved up front: convex geoms point into it
  std::vector<dBodyID> bodies_;
  std::vector<Vector3d> v_predicted_, w_predicted_;  // m/s, rad/s, world: no-contact end velocities
  std::deque<ContactFeedback> feedback_;  // this step's, at stable addresses (ODE writes into them)
  engine::State state_;
};

}  // namespace

std::unique_ptr<ExternalSimulation> MakeOdeSimulation(FrictionSetting setting,
                                                      const engine::Scene& scene) {
  return std::make_unique<OdeSimulation>(setting, scene);
}

}  // namespace ecpsim::baselines
