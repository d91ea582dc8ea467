#include "engine/report/trajectory_columns.h"

#include <string_view>

#include "engine/report/contact_groups.h"
#include "engine/report/contact_wrench.h"

namespace ecpsim::engine {
namespace {

const char* const kBodyColumns[] = {"px", "py", "pz", "qw", "qx", "qy", "qz",
                                    "vx", "vy", "vz", "wx", "wy", "wz"};
const char* const kContactColumns[] = {"a1x", "a1y", "a1z",   "a2x", "a2y", "a2z", "pn", "pt",
                                       "po",  "pr",  "sigma", "fn",  "ft",  "fo",  "fr"};
const char* const kWrenchColumns[] = {"fx", "fy", "fz", "mx", "my", "mz"};

void AppendWrench(const Wrench& w, std::vector<double>& values) {
  values.insert(values.end(),
                {w.force.x(), w.force.y(), w.force.z(), w.moment.x(), w.moment.y(), w.moment.z()});
}

// the groups of contacts whose G side is kinematic body `body`: one per body touching it
std::vector<ContactGroup> SensedGroups(const Scene& scene, int body) {
  std::vector<ContactGroup> sensed;
  for (const ContactGroup& group : ContactGroups(scene))
    if (scene.contacts[group.first].other_body == body) sensed.push_back(group);
  return sensed;
}

}  // namespace

std::vector<std::string> TrajectoryColumns(const Scene& scene) {
  std::vector<std::string> columns = {"t"};
  const bool several_bodies = scene.bodies.size() > 1;
  for (const Body& body : scene.bodies) {
    const std::string prefix = several_bodies ? body.name + "." : "";
    for (const char* c : kBodyColumns) columns.push_back(prefix + c);
  }
  const std::vector<ContactGroup> groups = ContactGroups(scene);
  const bool several_contacts = groups.size() > 1;
  for (const ContactGroup& group : groups) {
    const ContactPair& pair = scene.contacts[group.first];
    const std::string prefix = several_contacts
                                   ? scene.bodies[pair.body].name + "." +
                                         (pair.WithBody() ? scene.bodies[pair.other_body].name
                                                          : scene.obstacles[pair.obstacle].name) +
                                         "."
                                   : "";
    for (const char* c : kContactColumns) columns.push_back(prefix + c);
  }
  for (size_t b = 0; b < scene.bodies.size(); ++b) {
    if (!scene.bodies[b].IsKinematic()) continue;
    const std::string& name = scene.bodies[b].name;
    for (const ContactGroup& group : SensedGroups(scene, static_cast<int>(b))) {
      const std::string prefix =
          name + "." + scene.bodies[scene.contacts[group.first].body].name + ".";
      for (const char* c : kWrenchColumns) columns.push_back(prefix + c);
    }
    for (const char* c : kWrenchColumns) columns.push_back(name + "." + c);
  }
  for (const Gripper& gripper : scene.grippers) {
    columns.push_back(gripper.name + ".width");
    columns.push_back(gripper.name + ".force");
  }
  columns.push_back("iters");
  columns.push_back("residual");
  return columns;
}

std::vector<std::string> TrajectoryModelColumns(const Scene& scene) {
  std::vector<std::string> columns;
  for (const Body& body : scene.bodies)
    columns.push_back(scene.bodies.size() > 1 ? body.name + ".model" : "model");
  return columns;
}

std::vector<std::string> TrajectoryModels(const Scene& scene, const StepReport& report) {
  std::vector<std::string> models;
  for (size_t b = 0; b < scene.bodies.size(); ++b)
    models.push_back(report.models.empty() ? "initial" : StepModelName(report.models[b]));
  return models;
}

bool IsModelColumn(const std::string& column) {
  constexpr std::string_view kSuffix = ".model";
  return column == "model" ||
         (column.size() > kSuffix.size() &&
          column.compare(column.size() - kSuffix.size(), kSuffix.size(), kSuffix) == 0);
}

std::vector<double> TrajectoryValues(const Scene& scene, const State& state,
                                     const StepReport& report) {
  std::vector<double> values = {state.t};
  for (const BodyState& b : state.bodies) {
    values.insert(values.end(), {b.p_WB.x(), b.p_WB.y(), b.p_WB.z(), b.Q_WB.w(), b.Q_WB.x(),
                                 b.Q_WB.y(), b.Q_WB.z(), b.v_WB.x(), b.v_WB.y(), b.v_WB.z(),
                                 b.w_WB.x(), b.w_WB.y(), b.w_WB.z()});
  }
  for (const ContactGroup& group : ContactGroups(scene)) {
    const ContactState c = CombinedContact(state, group);
    values.insert(values.end(), {c.a1.x(), c.a1.y(), c.a1.z(), c.a2.x(), c.a2.y(), c.a2.z(), c.p_n,
                                 c.p_t, c.p_o, c.p_r, c.sigma, c.p_n / scene.h, c.p_t / scene.h,
                                 c.p_o / scene.h, c.p_r / scene.h});
  }
  for (size_t b = 0; b < scene.bodies.size(); ++b) {
    if (!scene.bodies[b].IsKinematic()) continue;
    for (const ContactGroup& group : SensedGroups(scene, static_cast<int>(b))) {
      Wrench sum = WrenchOnOther(scene, state, group.first, scene.h);
      for (int k = group.first + 1; k < group.end; ++k) {
        const Wrench w = WrenchOnOther(scene, state, k, scene.h);
        sum.force += w.force;
        sum.moment += w.moment;
      }
      AppendWrench(sum, values);
    }
    AppendWrench(SensorWrench(scene, state, static_cast<int>(b)), values);
  }
  for (const Gripper& gripper : scene.grippers) {
    // the opening: the jaws' centres apart along the frame's closing axis at t; the force of the
    // step that ended at t (the initial row: the first step's)
    const Eigen::Vector3d axis = ClosingAxis(gripper, gripper.motion->PoseAt(state.t));
    values.push_back(
        axis.dot(state.bodies[gripper.jaws[1]].p_WB - state.bodies[gripper.jaws[0]].p_WB));
    values.push_back(gripper.force(state.steps > 0 ? state.t - scene.h : 0.0));
  }
  values.push_back(report.iterations);
  values.push_back(report.residual);
  return values;
}

}  // namespace ecpsim::engine
