// Bullet (double precision, libbullet-dev 3.24 via pkg-config bullet-float64) stepping an ecpsim
// scene: btDiscreteDynamicsWorld with the sequential-impulse solver, each body a btConvexHullShape
// of its mesh vertices in its principal-axes frame, or a btCompoundShape of its parts' hulls where
// its pairs touch its parts (a kinematic body a kinematic object moved to its prescribed pose
// before every step), each half-space a btStaticPlaneShape; the scene's contact pairs, body–body
// ones included, with their friction (settings and measurements: baselines/bullet.md).

#include <cmath>
#include <memory>
#include <optional>
#include <vector>

#include <btBulletDynamicsCommon.h>
#include <fmt/format.h>

#include <Eigen/Eigenvalues>

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

/// kCoulomb's margin, m: the convex–plane algorithm places the contact at the support point plus
/// the margin, so the hull rests this high above the plane; 0 puts it on the plane, and GJK (whose
/// robustness the margin buys) never runs for the half-space pairs these scenes hold.
constexpr double kCoulombMargin = 0;
/// kCoulomb's solver sweeps: the resting box drifts 4.5e-4 m in 1 s with 10, 7.6e-6 m with 20 and
/// 2e-14 m with 50, where the desk's 4 s run equals 200 sweeps' to the printed 4 digits
/// (baselines/bullet.md).
constexpr int kCoulombIterations = 50;

/// What the two settings change (baselines/bullet.md gives the sources and measurements).
struct BulletSettings {
  // m; Bullet inflates a btConvexHullShape by this margin (its CONVEX_DISTANCE_MARGIN default)
  double margin = 0.04;
  int iterations = 10;  // sequential-impulse sweeps per step (btContactSolverInfo default)
  // convex–plane manifold filled by perturbation at once (else it collects a point per step)
  bool multipoint_plane = false;
  // empty every contact manifold before the step's collision detection (see Step)
  bool fresh_manifolds = false;
  // hull–hull contact by Bullet's polyhedral clipping (btPolyhedralContactClipping: the clipped
  // face polygon, up to 4 points at once) instead of GJK/EPA's one point per step
  bool polyhedral_hulls = false;
};

BulletSettings SettingsFor(FrictionSetting setting) {
  BulletSettings s;
  if (setting == FrictionSetting::kCoulomb) {
    s.margin = kCoulombMargin;
    s.iterations = kCoulombIterations;
    s.multipoint_plane = true;
    s.fresh_manifolds = true;
    s.polyhedral_hulls = true;
  }
  return s;
}

/// Bullet keeps user indices on collision objects: which body or obstacle a manifold touches.
constexpr int kBodyTag = 0;
constexpr int kObstacleTag = 1;

/// A body's principal-axes frame P: I_B = R_BP diag(principal) R_BPᵀ with det R_BP = +1. A
/// diagonal inertia keeps R_BP = identity exactly, so such bodies carry no round-off rotation.
struct PrincipalAxes {
  Matrix3d R_BP = Matrix3d::Identity();
  Vector3d principal = Vector3d::Ones();  // kg·m²
};

PrincipalAxes ComputePrincipalAxes(const Matrix3d& inertia) {
  PrincipalAxes axes;
  const Matrix3d off_diagonal = inertia - Matrix3d(inertia.diagonal().asDiagonal());
  if (off_diagonal.isZero(0)) {
    axes.principal = inertia.diagonal();
    return axes;
  }
  const Eigen::SelfAdjointEigenSolver<Matrix3d> solver(inertia);
  axes.R_BP = solver.eigenvectors();
  if (axes.R_BP.determinant() < 0) axes.R_BP.col(2) *= -1;
  axes.principal = solver.eigenvalues();
  return axes;
}

btVector3 ToBt(const Vector3d& v) { return btVector3(v.x(), v.y(), v.z()); }
Vector3d FromBt(const btVector3& v) { return Vector3d(v.x(), v.y(), v.z()); }
btQuaternion ToBt(const Quaterniond& q) { return btQuaternion(q.x(), q.y(), q.z(), q.w()); }
Quaterniond FromBt(const btQuaternion& q) { return Quaterniond(q.w(), q.x(), q.y(), q.z()); }

/// The discrete world with the scene's per-pair friction: Bullet combines two objects' friction
/// by a product, which cannot hold a table of pairs, so each contact point's coefficients are
/// overwritten just before the solve, and pairs the scene does not list are dropped.
class PairFrictionWorld final : public btDiscreteDynamicsWorld {
 public:
  PairFrictionWorld(btDispatcher* dispatcher, btBroadphaseInterface* broadphase,
                    btConstraintSolver* solver, btCollisionConfiguration* configuration,
                    PairFrictionTable friction)
      : btDiscreteDynamicsWorld(dispatcher, broadphase, solver, configuration),
        friction_(std::move(friction)) {}

 protected:
  void solveConstraints(btContactSolverInfo& solver_info) override {
    btDispatcher* dispatcher = getDispatcher();
    for (int m = 0; m < dispatcher->getNumManifolds(); ++m) {
      btPersistentManifold* manifold = dispatcher->getManifoldByIndexInternal(m);
      const btCollisionObject* a = manifold->getBody0();
      const btCollisionObject* b = manifold->getBody1();
      if (a->getUserIndex2() == kObstacleTag) std::swap(a, b);
      const std::optional<engine::Friction>& friction =
          b->getUserIndex2() == kObstacleTag
              ? friction_.WithObstacle(a->getUserIndex(), b->getUserIndex())
              : friction_.WithBody(a->getUserIndex(), b->getUserIndex());
      if (!friction) {
        manifold->clearManifold();
        continue;
      }
      const int n = manifold->getNumContacts();
      for (int k = 0; k < n; ++k) {
        btManifoldPoint& point = manifold->getContactPoint(k);
        point.m_combinedFriction = friction->mu;
        point.m_combinedRestitution = 0;
        point.m_combinedRollingFriction = 0;
        // no torsion row: Coulomb friction at the several contact points already resists a
        // spin through their lever arms (ecpsim's e_r models the same resistance for one ECP)
        point.m_combinedSpinningFriction = 0;
      }
    }
    btDiscreteDynamicsWorld::solveConstraints(solver_info);
  }

 private:
  PairFrictionTable friction_;
};

class BulletSimulation final : public ExternalSimulation {
 public:
  BulletSimulation(FrictionSetting setting, const engine::Scene& scene)
      : scene_(scene), settings_(SettingsFor(setting)) {
    configuration_ = std::make_unique<btDefaultCollisionConfiguration>();
    if (settings_.multipoint_plane) configuration_->setPlaneConvexMultipointIterations();
    dispatcher_ = std::make_unique<btCollisionDispatcher>(configuration_.get());
    broadphase_ = std::make_unique<btDbvtBroadphase>();
    solver_ = std::make_unique<btSequentialImpulseConstraintSolver>();
    world_ =
        std::make_unique<PairFrictionWorld>(dispatcher_.get(), broadphase_.get(), solver_.get(),
                                            configuration_.get(), PairFrictionTable(scene));
    world_->setGravity(ToBt(scene.gravity));
    // the polyhedral clipping of two hulls starts from the separating axis found by SAT (else
    // from GJK's, found only once the hulls overlap: a stack resting face on face at margin 0
    // would have no contact)
    world_->getDispatchInfo().m_enableSatConvex = settings_.polyhedral_hulls;
    btContactSolverInfo& info = world_->getSolverInfo();
    info.m_numIterations = settings_.iterations;
    // ecpsim's contacts are inelastic
    info.m_restitution = 0;

    // obstacles: static planes colliding with bodies only (no obstacle–obstacle contact)
    for (int o = 0; o < static_cast<int>(scene.obstacles.size()); ++o) {
      const HalfSpacePlane plane = HalfSpaceOf(scene, o, "Bullet");
      // Bullet's plane n·x = c has its solid side below, as ecpsim's n·y ≤ d
      shapes_.push_back(std::make_unique<btStaticPlaneShape>(ToBt(plane.normal), plane.offset));
      btRigidBody::btRigidBodyConstructionInfo ci(0, nullptr, shapes_.back().get());
      ci.m_friction = 1;
      ci.m_restitution = 0;
      rigid_bodies_.push_back(std::make_unique<btRigidBody>(ci));
      btRigidBody* rigid = rigid_bodies_.back().get();
      rigid->setUserIndex(o);
      rigid->setUserIndex2(kObstacleTag);
      world_->addRigidBody(rigid, btBroadphaseProxy::StaticFilter,
                           btBroadphaseProxy::DefaultFilter);
    }

    // bodies: the hull of the mesh vertices in the principal-axes frame P (origin at the CM), or
    // the parts its pairs touch. A collision object has one shape, so such a body meets
    // half-spaces through its parts too: where the parts' union is the body, at the hull's
    // lowest points (baselines/bullet.md)
    const std::vector<std::vector<int>> touched = TouchedParts(scene);
    const engine::State initial_state = engine::InitialState(scene);
    for (int b = 0; b < static_cast<int>(scene.bodies.size()); ++b) {
      const engine::Body& body = scene.bodies[static_cast<size_t>(b)];
      const PrincipalAxes axes = ComputePrincipalAxes(body.inertia);
      R_BP_.push_back(axes.R_BP);
      btCollisionShape* shape = nullptr;
      if (touched[static_cast<size_t>(b)].empty()) {
        shape = AddHullShape(
            geometry::ComputeConvexHull(
                body.mesh.vertices, fmt::format("{}: bodies[{}] '{}'", scene.source, b, body.name))
                .vertices,
            axes.R_BP);
      } else {
        // the children's vertices are in P already: each sits at the compound's origin
        auto compound = std::make_unique<btCompoundShape>();
        for (int part : touched[static_cast<size_t>(b)]) {
          compound->addChildShape(btTransform::getIdentity(),
                                  AddHullShape(PartHull(scene, b, part).vertices, axes.R_BP));
        }
        shape = compound.get();
        shapes_.push_back(std::move(compound));
      }
      // a kinematic object has mass 0 (Bullet: infinite) and is moved by the adapter (Step)
      const bool kinematic = body.IsKinematic();
      btRigidBody::btRigidBodyConstructionInfo ci(
          kinematic ? 0 : body.mass, nullptr, shape,
          kinematic ? btVector3(0, 0, 0) : ToBt(axes.principal));
      const engine::BodyState& initial = initial_state.bodies[static_cast<size_t>(b)];
      ci.m_startWorldTransform = PoseOf(b, initial.p_WB, initial.Q_WB);
      ci.m_friction = 1;
      ci.m_restitution = 0;
      rigid_bodies_.push_back(std::make_unique<btRigidBody>(ci));
      btRigidBody* rigid = rigid_bodies_.back().get();
      rigid->setUserIndex(b);
      rigid->setUserIndex2(kBodyTag);
      // sleeping would freeze a body that a later load should move: the scene's loads act at
      // any time, and applying a force does not wake a Bullet body (nor is a sleeping kinematic
      // object moved)
      rigid->setActivationState(DISABLE_DEACTIVATION);
      if (kinematic) {
        rigid->setCollisionFlags(rigid->getCollisionFlags() |
                                 btCollisionObject::CF_KINEMATIC_OBJECT);
        // kinematic objects touch dynamic bodies only
        world_->addRigidBody(rigid, btBroadphaseProxy::KinematicFilter,
                             btBroadphaseProxy::DefaultFilter);
      } else {
        rigid->setLinearVelocity(ToBt(initial.v_WB));
        rigid->setAngularVelocity(ToBt(initial.w_WB));
        world_->addRigidBody(rigid, btBroadphaseProxy::DefaultFilter, btBroadphaseProxy::AllFilter);
      }
      bodies_.push_back(rigid);
    }
    state_ = initial_state;
    state_.contacts.clear();
  }

  ~BulletSimulation() override {
    for (auto& rigid : rigid_bodies_) world_->removeRigidBody(rigid.get());
  }

  void Step() override {
    const double h = scene_.h;
    // the scene's loads as a constant wrench at the CM over the step (forces are cleared by
    // stepSimulation after each step)
    for (size_t b = 0; b < bodies_.size(); ++b) {
      if (scene_.bodies[b].IsKinematic()) {
        // Bullet's kinematic objects: the step starts from the pose set here, the one at t + h,
        // and saveKinematicState turns the move from the last pose (at t) into the velocities
        // the contacts see during the step; the collision runs at the end pose
        const KinematicStep step = KinematicStepOf(scene_.bodies[b], state_.t, h);
        bodies_[b]->setWorldTransform(PoseOf(static_cast<int>(b), step.end.p, step.end.q));
        continue;
      }
      const Matrix3d R_WB = state_.bodies[b].Q_WB.toRotationMatrix();
      const Eigen::Matrix<double, 6, 1> impulse = engine::AppliedImpulse(
          scene_.loads, scene_.impulses, static_cast<int>(b), state_.t, h, R_WB);
      bodies_[b]->applyCentralForce(ToBt(impulse.head<3>() / h));
      bodies_[b]->applyTorque(ToBt(impulse.tail<3>() / h));
    }
    // a persistent manifold keeps last step's points, so the convex–plane algorithm, which fills
    // it by perturbation only while it holds fewer than 3, adds one point; the refresh then drops
    // the old points a sliding hull has left behind (> 3 mm), and every other step solves with a
    // single corner (measured: the sliding box loses friction on alternate steps)
    if (settings_.fresh_manifolds) {
      for (int m = 0; m < dispatcher_->getNumManifolds(); ++m) {
        dispatcher_->getManifoldByIndexInternal(m)->clearManifold();
      }
    }
    // maxSubSteps = 0: exactly one internal step of h, no interpolation
    world_->stepSimulation(h, 0);
    engine::AdvanceTime(h, state_);
    for (size_t b = 0; b < bodies_.size(); ++b) {
      const btTransform& X_WP = bodies_[b]->getWorldTransform();
      engine::BodyState& body = state_.bodies[b];
      body.p_WB = FromBt(X_WP.getOrigin());
      body.Q_WB = (FromBt(X_WP.getRotation()) * Quaterniond(R_BP_[b].transpose())).normalized();
      body.v_WB = FromBt(bodies_[b]->getLinearVelocity());
      body.w_WB = FromBt(bodies_[b]->getAngularVelocity());
    }
    RequireFiniteState("bullet", state_, [this](std::size_t b) { return scene_.bodies[b].name; });
  }

  const engine::State& state() const override { return state_; }

  Vector3d ContactForce(int body, int other) const override {
    // the manifolds of the step just taken, with the solver's impulses written back: on body A
    // along the normal on B (pointing towards A) and along the two friction directions
    Vector3d impulse = Vector3d::Zero();
    for (int m = 0; m < dispatcher_->getNumManifolds(); ++m) {
      const btPersistentManifold* manifold = dispatcher_->getManifoldByIndexInternal(m);
      const btCollisionObject* a = manifold->getBody0();
      const btCollisionObject* b = manifold->getBody1();
      if (a->getUserIndex2() != kBodyTag || b->getUserIndex2() != kBodyTag) continue;
      const double sign = a->getUserIndex() == body && b->getUserIndex() == other   ? 1
                          : b->getUserIndex() == body && a->getUserIndex() == other ? -1
                                                                                    : 0;
      if (sign == 0) continue;
      for (int k = 0; k < manifold->getNumContacts(); ++k) {
        const btManifoldPoint& pt = manifold->getContactPoint(k);
        impulse += sign * (FromBt(pt.m_normalWorldOnB) * pt.getAppliedImpulse() +
                           FromBt(pt.m_lateralFrictionDir1) * pt.m_appliedImpulseLateral1 +
                           FromBt(pt.m_lateralFrictionDir2) * pt.m_appliedImpulseLateral2);
      }
    }
    return impulse / scene_.h;
  }

 private:
  // a btConvexHullShape of `vertices_B` (body frame) in the principal-axes frame P, with the
  // setting's margin and features, owned by shapes_
  btConvexHullShape* AddHullShape(const std::vector<Vector3d>& vertices_B, const Matrix3d& R_BP) {
    auto hull = std::make_unique<btConvexHullShape>();
    for (const Vector3d& v_B : vertices_B) hull->addPoint(ToBt(R_BP.transpose() * v_B), false);
    hull->recalcLocalAabb();
    hull->setMargin(settings_.margin);
    if (settings_.polyhedral_hulls) hull->initializePolyhedralFeatures();
    shapes_.push_back(std::move(hull));
    return static_cast<btConvexHullShape*>(shapes_.back().get());
  }

  // body b's transform X_WP (principal axes P) for its body frame at (p, Q_WB), Q_WB unit
  btTransform PoseOf(int b, const Vector3d& p, const Quaterniond& Q_WB) const {
    const Quaterniond Q_WP = Q_WB * Quaterniond(R_BP_[static_cast<size_t>(b)]);
    return btTransform(ToBt(Q_WP), ToBt(p));
  }

  const engine::Scene scene_;  // a copy: the caller's scene may go away
  BulletSettings settings_;
  std::unique_ptr<btDefaultCollisionConfiguration> configuration_;
  std::unique_ptr<btCollisionDispatcher> dispatcher_;
  std::unique_ptr<btBroadphaseInterface> broadphase_;
  std::unique_ptr<btSequentialImpulseConstraintSolver> solver_;
  std::unique_ptr<PairFrictionWorld> world_;
  std::vector<std::unique_ptr<btCollisionShape>> shapes_;
  std::vector<std::unique_ptr<btRigidBody>> rigid_bodies_;  // obstacles, then bodies
  std::vector<btRigidBody*> bodies_;                        // the scene's bodies, in order
  std::vector<Matrix3d> R_BP_;                              // principal axes of each body
  engine::State state_;
};

}  // namespace

std::unique_ptr<ExternalSimulation> MakeBulletSimulation(FrictionSetting setting,
                                                         const engine::Scene& scene) {
  return std::make_unique<BulletSimulation>(setting, scene);
}

}  // namespace ecpsim::baselines
