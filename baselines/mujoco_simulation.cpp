// MuJoCo 2.2.2 stepping an ecpsim scene: the scene written as MJCF in memory (one free body per
// ecpsim body with a point geom at each vertex and a mesh geom of each convex piece its pairs
// touch, its hull or its parts; one plane per half-space obstacle; explicit contact pairs for each
// ContactPair: vertices against a plane, and between two bodies each piece's vertices against the
// other piece's mesh), compiled with mj_loadXML from a virtual file system and stepped with
// mj_step; a kinematic body is a heavy free body set to its prescribed pose and twist before every
// step (baselines/mujoco.md).

#include <algorithm>
#include <map>
#include <memory>
#include <mutex>
#include <set>
#include <string>
#include <utility>
#include <vector>

#include <fmt/format.h>
#include <mujoco/mujoco.h>
#include <Eigen/Core>
#include <Eigen/Geometry>

#include "baselines/adapter_inputs.h"
#include "baselines/engine_adapters.h"
#include "common/errors.h"
#include "engine/loads.h"
#include "engine/step_report.h"
#include "geometry/convex_hull.h"
#include "geometry/convex_shape.h"

namespace ecpsim::baselines {
namespace {

using Eigen::Matrix3d;
using Eigen::Quaterniond;
using Eigen::Vector3d;

/// The MuJoCo options and contact parameters of one FrictionSetting (baselines/mujoco.md).
struct MujocoSettings {
  const char* cone = "pyramidal";  // friction cone: "pyramidal" or "elliptic"
  // 3: sliding friction only in both settings; torsion (condim 4) would count twice: the
  // contact points at the hull's vertices already resist a spin through their lever arms
  int condim = 3;
  double impratio = 1;        // friction-to-normal impedance ratio (elliptic cones)
  int noslip_iterations = 0;  // post-solve friction-only iterations that remove soft slip
  // solimp (d0, dmax, width m, midpoint, power); empty: MuJoCo's default "0.9 0.95 0.001 0.5 2".
  std::string solimp;
  // solref time constant, s; 0: MuJoCo's default 0.02. A corner hitting the ground at v sinks
  // about v·τ/e before the soft contact stops it (baselines/mujoco.md, "Transient penetration"),
  // so kCoulomb takes the stiffest τ MuJoCo accepts, 2h (its refsafe floor); damping ratio 1
  double solref_time_constant = 0;
};

// kDefault: everything MuJoCo's documentation lists as default (pyramidal cone, condim 3,
// impratio 1, no noslip, default solref/solimp); the scene sets only h, gravity, geometry, mass
// and μ. kCoulomb: the settings chosen by the measurements in baselines/mujoco.md
MujocoSettings SettingsFor(FrictionSetting setting, double h) {
  MujocoSettings s;
  if (setting == FrictionSetting::kCoulomb) {
    s.cone = "elliptic";
    s.impratio = 10;
    s.noslip_iterations = 10;
    s.solimp = "0.99 0.99 0.001 0.5 2";
    s.solref_time_constant = 2 * h;
  }
  return s;
}

// MuJoCo's default geom friction "1 0.005 0.0001": the torsional and rolling coefficients of
// every contact pair (condim 3 ignores them)
constexpr double kMujocoDefaultTorsion = 0.005;   // m
constexpr double kMujocoDefaultRolling = 0.0001;  // m

// constraint rows per contact: at most 6 (a pyramidal condim-4 contact)
constexpr int kRowsPerContact = 6;
// the contacts a body's share of the buffers holds: a box in a pile touches the floor and three
// neighbours by four vertices each. MuJoCo 2.2 allocates the square of the rows (efc_AR): 24
// boxes' every vertex of every pair (5,376 contacts) could not be allocated, nor 96 boxes at 32
// a body (2.7 GB); a step that fills the buffers fails the run (mjWARN_CONTACTFULL), it never
// drops a contact, and no step of the clutter bins does
constexpr int kMaxContactsPerBody = 16;

// radius of the point geoms at the hull vertices: the body rests this much higher than its hull
// would, far below MuJoCo's soft-contact penetration (~1e-5 m for the 1 kg test box)
constexpr double kVertexRadius = 1e-9;  // m

// a kinematic body's mass and inertia over those of the heaviest dynamic body: the contacts of a
// step change its velocity by F h / M, 1e-6 of what they do to the bodies it pushes, and the
// adapter sets its pose and velocity afresh before every step anyway (baselines/mujoco.md)
constexpr double kKinematicMassRatio = 1e6;

/// MuJoCo's error buffer length for mj_loadXML.
constexpr int kErrorBufferSize = 1024;

/// The virtual file name the MJCF model is compiled from.
constexpr const char* kModelFileName = "ecpsim_scene.xml";

// a vector as MJCF text, every digit of the double kept
std::string Vec(const Vector3d& v) {
  return fmt::format("{:.17g} {:.17g} {:.17g}", v.x(), v.y(), v.z());
}

// mj_loadXML keeps the last parsed model in a global (mj_freeLastXML), so loads are serialized
std::mutex& LoadMutex() {
  static std::mutex mutex;
  return mutex;
}

// MuJoCo's default warning handler appends to MUJOCO_LOG.TXT in the working directory; the
// adapter reads the counters in mjData::warning instead and turns them into exceptions
void IgnoreWarning(const char*) {}

/// Body-frame vertices of the body's convex hull (of its mesh, or of its primitive's tessellation).
std::vector<Vector3d> HullVertices(const engine::Body& body, const std::string& where) {
  if (const auto* poly = body.hull->AsPolyhedron();
      poly != nullptr && !poly->hull().vertices.empty()) {
    return poly->hull().vertices;
  }
  const std::vector<Vector3d> points = body.mesh.vertices.empty() && body.hull
                                           ? body.hull->Tessellate().vertices
                                           : body.mesh.vertices;
  return geometry::ComputeConvexHull(points, where).vertices;
}

/// A convex piece of a body, what one side of a ContactPair touches: (body, part), part −1 the
/// body's hull, else Body::parts[part].
using Piece = std::pair<int, int>;

/// The piece's name in geom and mesh names: "<b>" for the hull, "<b>p<j>" for part j.
std::string PieceName(const Piece& piece) {
  return piece.second < 0 ? fmt::format("{}", piece.first)
                          : fmt::format("{}p{}", piece.first, piece.second);
}

/// Body-frame vertices of the piece: the hull's (HullVertices), or the part's (PartHull).
std::vector<Vector3d> PieceVertices(const engine::Scene& scene, const Piece& piece) {
  if (piece.second >= 0) return PartHull(scene, piece.first, piece.second).vertices;
  const engine::Body& body = scene.bodies[static_cast<size_t>(piece.first)];
  return HullVertices(body,
                      fmt::format("{}: bodies[{}] '{}'", scene.source, piece.first, body.name));
}

/// The scene as MJCF: bodies b<i> (free joint, explicit inertial at the body origin = CM), the
/// vertices of each of their pieces (Piece: every body's hull, and each part a pair touches) as
/// point geoms g<piece>_<k>, a piece that touches another body also as mesh geom h<piece> (mesh
/// m<piece>), planes o<k>, and explicit contact pairs only (contype = conaffinity = 0 disables
/// MuJoCo's automatic pairs, so only the scene's pairs touch). A convex piece meets a half-space
/// exactly where its vertices do, so the vertices carry the whole contact; MuJoCo's own
/// plane–mesh collision reports at most 3 points (maxplanemesh in engine_collision_convex.c), too
/// few for a face resting on a plane, and its mesh–mesh collision (libccd's MPR) one point per
/// pair, too few for a box resting on a box: two pieces touch by each one's vertex points against
/// the other's mesh (baselines/mujoco.md). A body made of parts thus touches another body through
/// each part the scene pairs, as ecpsim's contacts do. A kinematic body gets kKinematicMassRatio ×
/// the heaviest dynamic body's mass and inertia.
std::string MakeMjcf(const engine::Scene& scene, const MujocoSettings& s) {
  // every body's hull, and the parts the pairs touch, in (body, part) order
  std::map<Piece, std::vector<Vector3d>> vertices;
  const auto add_piece = [&](const Piece& piece) -> const std::vector<Vector3d>& {
    auto found = vertices.find(piece);
    if (found == vertices.end()) found = vertices.emplace(piece, PieceVertices(scene, piece)).first;
    return found->second;
  };
  for (size_t b = 0; b < scene.bodies.size(); ++b) add_piece({static_cast<int>(b), -1});
  // contact buffers sized for every vertex of every pair touching at once, up to
  // kMaxContactsPerBody a piece (a bin's every pair would ask for gigabytes)
  int max_contacts = 0;
  std::set<Piece> needs_mesh;
  for (const engine::ContactPair& pair : scene.contacts) {
    if (!PeerModels(pair)) continue;
    const Piece f{pair.body, pair.part};
    max_contacts += static_cast<int>(add_piece(f).size());
    if (!pair.WithBody()) continue;
    const Piece g{pair.other_body, pair.other_part};
    max_contacts += static_cast<int>(add_piece(g).size());
    needs_mesh.insert(f);
    needs_mesh.insert(g);
  }
  max_contacts = std::min(max_contacts, kMaxContactsPerBody * static_cast<int>(vertices.size()));
  double heaviest = 0;
  for (const engine::Body& body : scene.bodies)
    if (!body.IsKinematic()) heaviest = std::max(heaviest, body.mass);
  std::string xml = "<mujoco model=\"ecpsim\">\n";
  xml += "  <compiler angle=\"radian\" inertiafromgeom=\"false\"/>\n";
  xml += fmt::format(
      "  <option timestep=\"{:.17g}\" gravity=\"{}\" integrator=\"Euler\" cone=\"{}\" "
      "impratio=\"{:.17g}\" noslip_iterations=\"{}\"/>\n",
      scene.h, Vec(scene.gravity), s.cone, s.impratio, s.noslip_iterations);
  xml += fmt::format("  <size nconmax=\"{}\" njmax=\"{}\"/>\n", std::max(1, max_contacts),
                     std::max(1, max_contacts * kRowsPerContact));

  // the pieces that touch other bodies, as meshes (MuJoCo takes their convex hull)
  xml += "  <asset>\n";
  for (const Piece& piece : needs_mesh) {
    std::string points;
    for (const Vector3d& v : vertices.at(piece)) points += (points.empty() ? "" : " ") + Vec(v);
    xml += fmt::format("    <mesh name=\"m{}\" vertex=\"{}\"/>\n", PieceName(piece), points);
  }
  xml += "  </asset>\n";

  xml += "  <worldbody>\n";

  // planes: MuJoCo's plane is z ≤ 0 in its frame, placed at the foot point d·n facing n
  for (size_t o = 0; o < scene.obstacles.size(); ++o) {
    const HalfSpacePlane plane = HalfSpaceOf(scene, static_cast<int>(o), "MuJoCo");
    const Quaterniond q = Quaterniond::FromTwoVectors(Vector3d::UnitZ(), plane.normal);
    xml += fmt::format(
        "    <geom name=\"o{}\" type=\"plane\" size=\"0 0 1\" pos=\"{}\" "
        "quat=\"{:.17g} {:.17g} {:.17g} {:.17g}\" contype=\"0\" conaffinity=\"0\"/>\n",
        o, Vec(plane.offset * plane.normal), q.w(), q.x(), q.y(), q.z());
  }

  // bodies at the origin: the initial pose and velocity are written into qpos/qvel in double
  for (size_t b = 0; b < scene.bodies.size(); ++b) {
    const engine::Body& body = scene.bodies[b];
    const double scale = body.IsKinematic() ? kKinematicMassRatio * heaviest / body.mass : 1;
    const Matrix3d I = scale * body.inertia;
    xml += fmt::format("    <body name=\"b{}\">\n      <freejoint/>\n", b);
    xml += fmt::format(
        "      <inertial pos=\"0 0 0\" mass=\"{:.17g}\" fullinertia=\"{:.17g} {:.17g} {:.17g} "
        "{:.17g} {:.17g} {:.17g}\"/>\n",
        scale * body.mass, I(0, 0), I(1, 1), I(2, 2), I(0, 1), I(0, 2), I(1, 2));
    // its pieces: the vertices are in the body frame, so every geom sits at the body's origin
    for (auto it = vertices.lower_bound({static_cast<int>(b), -1});
         it != vertices.end() && it->first.first == static_cast<int>(b); ++it) {
      const std::string name = PieceName(it->first);
      if (needs_mesh.count(it->first) > 0) {
        xml += fmt::format(
            "      <geom name=\"h{}\" type=\"mesh\" mesh=\"m{}\" contype=\"0\" "
            "conaffinity=\"0\"/>\n",
            name, name);
      }
      for (size_t k = 0; k < it->second.size(); ++k) {
        xml += fmt::format(
            "      <geom name=\"g{}_{}\" type=\"sphere\" size=\"{:.17g}\" pos=\"{}\" "
            "contype=\"0\" conaffinity=\"0\"/>\n",
            name, k, kVertexRadius, Vec(it->second[k]));
      }
    }
    xml += "    </body>\n";
  }
  xml += "  </worldbody>\n  <contact>\n";

  // one pair per ecpsim contact pair and vertex, with its μ: the vertices of F's piece against
  // the plane, or against G's piece's mesh and G's piece's vertices against F's
  const auto add_pairs = [&](const std::string& geom1, const Piece& piece,
                             const engine::Friction& f) {
    for (size_t k = 0; k < vertices.at(piece).size(); ++k) {
      xml += fmt::format(
          "    <pair geom1=\"{}\" geom2=\"g{}_{}\" condim=\"{}\" friction=\"{:.17g} {:.17g} "
          "{:.17g} {:.17g} {:.17g}\"",
          geom1, PieceName(piece), k, s.condim, f.mu, f.mu, kMujocoDefaultTorsion,
          kMujocoDefaultRolling, kMujocoDefaultRolling);
      if (!s.solimp.empty()) xml += fmt::format(" solimp=\"{}\"", s.solimp);
      if (s.solref_time_constant > 0) {
        xml += fmt::format(" solref=\"{:.17g} 1\"", s.solref_time_constant);
      }
      xml += "/>\n";
    }
  };
  for (const engine::ContactPair& pair : scene.contacts) {
    if (!PeerModels(pair)) continue;
    const Piece f{pair.body, pair.part};
    if (!pair.WithBody()) {
      add_pairs(fmt::format("o{}", pair.obstacle), f, pair.friction);
      continue;
    }
    const Piece g{pair.other_body, pair.other_part};
    add_pairs("h" + PieceName(g), f, pair.friction);
    add_pairs("h" + PieceName(f), g, pair.friction);
  }
  xml += "  </contact>\n</mujoco>\n";
  return xml;
}

/// Compiles MJCF text from memory.
/// @throws engine::SolverFailure with MuJoCo's compiler message, naming the scene: the MJCF is
///         written from a valid scene, so a model MuJoCo refuses (its data too large to allocate:
///         the square of the constraint rows) is MuJoCo failing on that scene, a failed run in a
///         sweep, not the user's input.
mjModel* CompileMjcf(const std::string& xml, const std::string& source) {
  // mjVFS holds 2000 file names of 1000 bytes: too large for the stack
  auto vfs = std::make_unique<mjVFS>();
  std::lock_guard<std::mutex> lock(LoadMutex());
  if (mju_user_warning == nullptr) mju_user_warning = IgnoreWarning;
  mj_defaultVFS(vfs.get());
  const int size = static_cast<int>(xml.size());
  ECPSIM_DEMAND(mj_makeEmptyFileVFS(vfs.get(), kModelFileName, size) == 0);
  const int index = mj_findFileVFS(vfs.get(), kModelFileName);
  ECPSIM_DEMAND(index >= 0);
  std::copy(xml.begin(), xml.end(), static_cast<char*>(vfs->filedata[index]));
  char error[kErrorBufferSize] = "";
  mjModel* model = mj_loadXML(kModelFileName, vfs.get(), error, kErrorBufferSize);
  mj_deleteVFS(vfs.get());
  if (model == nullptr) {
    throw engine::SolverFailure(
        fmt::format("{}: MuJoCo could not compile the scene's model: {}", source, error));
  }
  return model;
}

class MujocoSimulation final : public ExternalSimulation {
 public:
  MujocoSimulation(const MujocoSettings& settings, const engine::Scene& scene)
      : source_(scene.source),
        h_(scene.h),
        gravity_(scene.gravity),
        loads_(scene.loads),
        impulses_(scene.impulses) {
    for (const engine::Body& body : scene.bodies) {
      names_.push_back(body.name);
      motions_.push_back(body.motion);
    }
    model_ = CompileMjcf(MakeMjcf(scene, settings), scene.source);
    data_ = mj_makeData(model_);
    ECPSIM_DEMAND(data_ != nullptr);

    // initial state in full precision
    const engine::State initial = engine::InitialState(scene);
    state_.t = 0;
    state_.bodies.resize(scene.bodies.size());
    for (size_t b = 0; b < scene.bodies.size(); ++b) {
      const engine::BodyState& s = initial.bodies[b];
      SetJoint(b, s.p_WB, s.Q_WB, s.v_WB, s.w_WB);
    }
    ReadState();
  }

  ~MujocoSimulation() override {
    mj_deleteData(data_);
    mj_deleteModel(model_);
  }
  MujocoSimulation(const MujocoSimulation&) = delete;
  MujocoSimulation& operator=(const MujocoSimulation&) = delete;

  void Step() override {
    // the step's applied impulse as a constant wrench at the CM (xfrc_applied: world frame, at
    // the body's CM, which is the body origin here)
    for (size_t b = 0; b < state_.bodies.size(); ++b) {
      mjtNum* xfrc = data_->xfrc_applied + 6 * BodyId(b);
      if (motions_[b] != nullptr) {
        // a kinematic body: its prescribed pose at t and the step's twist, which MuJoCo's Euler
        // step (p + h v, quaternion integration of ω) carries to the pose at t + h; gravity on
        // its (large) mass cancelled
        const engine::KinematicMotion::Twist twist = motions_[b]->StepTwist(state_.t, h_);
        const engine::KinematicPose start = motions_[b]->PoseAt(state_.t);
        SetJoint(b, start.p, start.q, twist.v, twist.w);
        const Vector3d weight = model_->body_mass[BodyId(b)] * gravity_;
        for (int k = 0; k < 3; ++k) xfrc[k] = -weight[k];
        for (int k = 3; k < 6; ++k) xfrc[k] = 0;
        continue;
      }
      const Matrix3d R_WB = state_.bodies[b].Q_WB.toRotationMatrix();
      const Eigen::Matrix<double, 6, 1> wrench =
          engine::AppliedImpulse(loads_, impulses_, static_cast<int>(b), state_.t, h_, R_WB) / h_;
      for (int k = 0; k < 6; ++k) xfrc[k] = wrench[k];
    }
    const int bad_acc = data_->warning[mjWARN_BADQACC].number;
    mj_step(model_, data_);

    // MuJoCo resets the data on a non-finite acceleration and drops contacts that overflow its
    // buffers, both with only a warning: either would make the comparison meaningless
    if (data_->warning[mjWARN_BADQACC].number != bad_acc) {
      throw engine::SolverFailure(fmt::format(
          "{}: MuJoCo reported a non-finite acceleration at t = {} s and reset its state", source_,
          state_.t));
    }
    if (data_->warning[mjWARN_CONTACTFULL].number > 0 ||
        data_->warning[mjWARN_CNSTRFULL].number > 0) {
      throw engine::SolverFailure(
          fmt::format("{}: MuJoCo's contact buffer overflowed at t = {} s ({} contacts)", source_,
                      state_.t, data_->ncon));
    }
    ReadState();
    engine::AdvanceTime(h_, state_);
    RequireFiniteState("mujoco", state_, [this](std::size_t b) { return names_[b]; });
  }

  const engine::State& state() const override { return state_; }

  Vector3d ContactForce(int body, int other) const override {
    // mj_step's contacts are those of the step just taken; each force is in the contact frame
    // (rows: normal from geom1 to geom2, then the tangents) and acts on geom2, its opposite on
    // geom1
    Vector3d force = Vector3d::Zero();
    const int on = BodyId(static_cast<size_t>(body)), by = BodyId(static_cast<size_t>(other));
    for (int i = 0; i < data_->ncon; ++i) {
      const mjContact& c = data_->contact[i];
      const int body1 = model_->geom_bodyid[c.geom1], body2 = model_->geom_bodyid[c.geom2];
      const double sign = body2 == on && body1 == by ? 1 : body1 == on && body2 == by ? -1 : 0;
      if (sign == 0) continue;
      mjtNum local[6];
      mj_contactForce(model_, data_, i, local);
      for (int k = 0; k < 3; ++k)
        force += sign * local[k] * Vector3d(c.frame[3 * k], c.frame[3 * k + 1], c.frame[3 * k + 2]);
    }
    return force;
  }

  const mjModel* model() const { return model_; }
  const mjData* data() const { return data_; }

 private:
  // MuJoCo's body 0 is the world; ecpsim body b is MuJoCo body b + 1 with joint b
  static int BodyId(size_t b) { return static_cast<int>(b) + 1; }
  static int JointOf(size_t b) { return static_cast<int>(b); }

  // body b's free joint: qpos = (p, q_wxyz), qvel = (v world, ω body), in full precision; Q_WB
  // unit
  void SetJoint(size_t b, const Vector3d& p, const Quaterniond& q, const Vector3d& v,
                const Vector3d& w) {
    const Vector3d w_B = q.toRotationMatrix().transpose() * w;
    mjtNum* qpos = data_->qpos + model_->jnt_qposadr[JointOf(b)];
    mjtNum* qvel = data_->qvel + model_->jnt_dofadr[JointOf(b)];
    for (int k = 0; k < 3; ++k) {
      qpos[k] = p[k];
      qvel[k] = v[k];
      qvel[3 + k] = w_B[k];
    }
    qpos[3] = q.w();
    qpos[4] = q.x();
    qpos[5] = q.y();
    qpos[6] = q.z();
  }

  void ReadState() {
    for (size_t b = 0; b < state_.bodies.size(); ++b) {
      const mjtNum* qpos = data_->qpos + model_->jnt_qposadr[JointOf(b)];
      const mjtNum* qvel = data_->qvel + model_->jnt_dofadr[JointOf(b)];
      engine::BodyState& s = state_.bodies[b];
      s.p_WB = Vector3d(qpos[0], qpos[1], qpos[2]);
      s.Q_WB = Quaterniond(qpos[3], qpos[4], qpos[5], qpos[6]).normalized();
      s.v_WB = Vector3d(qvel[0], qvel[1], qvel[2]);
      s.w_WB = s.Q_WB.toRotationMatrix() * Vector3d(qvel[3], qvel[4], qvel[5]);
    }
  }

  std::string source_;
  double h_;
  Vector3d gravity_;
  std::vector<engine::Load> loads_;
  std::vector<engine::Impulse> impulses_;
  std::vector<std::string> names_;
  // per body: its prescribed motion (null: dynamic)
  std::vector<std::shared_ptr<const engine::KinematicMotion>> motions_;
  mjModel* model_ = nullptr;
  mjData* data_ = nullptr;
  engine::State state_;
};

}  // namespace

std::unique_ptr<ExternalSimulation> MakeMujocoSimulation(FrictionSetting setting,
                                                         const engine::Scene& scene) {
  return std::make_unique<MujocoSimulation>(SettingsFor(setting, scene.h), scene);
}

}  // namespace ecpsim::baselines
