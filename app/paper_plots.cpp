#include "app/paper_plots.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <optional>
#include <string>
#include <vector>

#include <fmt/format.h>
#include <Eigen/Core>
#include <Eigen/Geometry>
#include <nlohmann/json.hpp>

#include "app/plot_writer.h"
#include "app/trajectory_table.h"
#include "common/atomic_file.h"
#include "common/errors.h"
#include "engine/scene.h"
#include "engine/scene_io/scene_yaml.h"
#include "geometry/contact_patch.h"

namespace ecpsim::app {
namespace {

namespace fs = std::filesystem;
using Eigen::Vector3d;

constexpr double kPi = 3.14159265358979323846;

// The dumbbell's mesh is a 96-gon prism inscribed in its cylinder hull: lying on its side, its
// lowest facet floats up to the sagitta R (1 − cos(π/96)) = 5.35e-5 m above the ground while the
// hull touches it. Its snapshots take the patch within that distance (on top of the default
// tolerance) so that they show the two contact segments rather than nothing.
const double kDumbbellSagitta = 0.1 * (1 - std::cos(kPi / 96));  // m

// the paper's snapshot times of the dumbbell (its figure 9 e–i)
const std::vector<double> kDumbbellSnapshotTimes = {0.01, 0.25, 0.5, 1.75, 2.5};  // s
constexpr int kDeskSnapshots = 6;
constexpr int kMaxModeSnapshots = 8;

// numbers written to data files in shortest round-trip form
std::string Num(double value) { return fmt::format("{}", value); }

// The column names of the first body and its first contact: unprefixed for one body and one
// contact, `<body>.` / `<body>.<obstacle>.` otherwise (docs/scene_format.md).
struct Columns {
  std::string body;                 // prefix of px ... wz
  std::vector<std::string> bodies;  // every body's prefix, in the file's order (body the first)
  std::string contact;  // prefix of a1x ... sigma; empty string also when there is no contact
  bool has_contact = false;
};

Columns FindColumns(const TrajectoryTable& table) {
  Columns columns;
  bool body_found = false;
  for (const std::string& name : table.names) {
    auto ends_with = [&](const std::string& suffix) {
      return name.size() >= suffix.size() &&
             name.compare(name.size() - suffix.size(), suffix.size(), suffix) == 0;
    };
    if (ends_with("px")) {
      columns.bodies.push_back(name.substr(0, name.size() - 2));
      if (!body_found) columns.body = columns.bodies.back();
      body_found = true;
    }
    if (!columns.has_contact && ends_with("a1x")) {
      columns.contact = name.substr(0, name.size() - 3);
      columns.has_contact = true;
    }
  }
  if (!body_found) {
    throw InputError(
        fmt::format("{}: no body position column (px); expected a trajectory.csv of "
                    "`ecpsim run`",
                    table.path));
  }
  return columns;
}

// the pose of the body in `row`
Eigen::Isometry3d PoseAt(const TrajectoryTable& table, const Columns& c, std::size_t row) {
  const auto& col = [&](const char* name) { return table.Column(c.body + name)[row]; };
  Eigen::Quaterniond q(col("qw"), col("qx"), col("qy"), col("qz"));
  if (!(q.norm() > 0.5)) {
    throw InputError(fmt::format("{}: row {}: quaternion of norm {}: expected a unit quaternion",
                                 table.path, row + 2, q.norm()));
  }
  q.normalize();
  Eigen::Isometry3d X = Eigen::Isometry3d::Identity();
  X.linear() = q.toRotationMatrix();
  X.translation() = Vector3d(col("px"), col("py"), col("pz"));
  return X;
}

// --- snapshots -------------------------------------------------------------------------------

struct Snapshot {
  std::size_t row = 0;
  std::string title;
};

// a grid of top-down contact-patch views, one panel per snapshot; the patch is taken within the
// default tolerance plus `gap` (m) of the plane
void PlotSnapshots(PlotWriter& writer, const std::string& png, const TrajectoryTable& table,
                   const Columns& c, const engine::Scene& scene,
                   const std::vector<Snapshot>& snapshots, double gap = 0) {
  if (snapshots.empty()) return;
  const int n = static_cast<int>(snapshots.size());
  const int cols = n <= 3 ? n : (n <= 4 ? 2 : (n <= 6 ? 3 : 4));
  const int rows = (n + cols - 1) / cols;
  writer.BeginPng(png, 400 * cols, 400 * rows + 40);
  writer.Line(
      fmt::format("set multiplot layout {},{} title {}", rows, cols,
                  GnuplotQuote("contact patch (top view): polygons/segments/points black, hull "
                               "dashed red, ECP x, CM projection o")));
  writer.Line("set size ratio -1\nunset key\nset xlabel 'x (m)'\nset ylabel 'y (m)'");
  const geometry::Plane ground{Vector3d::UnitZ(), 0.0};
  for (std::size_t k = 0; k < snapshots.size(); ++k) {
    const std::size_t row = snapshots[k].row;
    const Eigen::Isometry3d X_WB = PoseAt(table, c, row);
    const geometry::ContactPatch patch =
        geometry::ExtractContactPatch(scene.bodies[0].mesh, X_WB, ground,
                                      geometry::ContactPatchTolerance(scene.bodies[0].mesh) + gap);
    const Vector3d cm = X_WB.translation();
    const Vector3d ecp = c.has_contact ? Vector3d(table.Column(c.contact + "a1x")[row],
                                                  table.Column(c.contact + "a1y")[row],
                                                  table.Column(c.contact + "a1z")[row])
                                       : cm;

    // one data file, one block (gnuplot index) per kind of feature; empty kinds are not plotted
    std::string blocks[6];
    for (const auto& polygon : patch.polygons) {
      for (const Vector3d& p : polygon) blocks[0] += Num(p.x()) + " " + Num(p.y()) + "\n";
      blocks[0] += Num(polygon.front().x()) + " " + Num(polygon.front().y()) + "\n\n";
    }
    for (const auto& segment : patch.segments) {
      for (const Vector3d& p : segment) blocks[1] += Num(p.x()) + " " + Num(p.y()) + "\n";
      blocks[1] += "\n";
    }
    for (const Vector3d& p : patch.points) blocks[2] += Num(p.x()) + " " + Num(p.y()) + "\n";
    for (const Vector3d& p : patch.hull) blocks[3] += Num(p.x()) + " " + Num(p.y()) + "\n";
    if (!patch.hull.empty()) {
      blocks[3] += Num(patch.hull.front().x()) + " " + Num(patch.hull.front().y()) + "\n";
    }
    blocks[4] = Num(ecp.x()) + " " + Num(ecp.y()) + "\n";
    blocks[5] = Num(cm.x()) + " " + Num(cm.y()) + "\n";
    // an empty block still gets a (never plotted) line so that the indices stay in place
    std::string content;
    for (const std::string& block : blocks) content += (block.empty() ? "0 0\n" : block) + "\n\n";
    const std::string data = writer.Data(fmt::format("{}_{}", png, k), content);

    // a square window around the CM projection holding every feature, the hull and the ECP
    double half = 0.05;
    auto extend = [&](const Vector3d& p) {
      half = std::max(half, 1.15 * std::max(std::abs(p.x() - cm.x()), std::abs(p.y() - cm.y())));
    };
    for (const Vector3d& p : patch.hull) extend(p);
    for (const Vector3d& p : patch.points) extend(p);
    extend(ecp);
    writer.Line(fmt::format("set xrange [{}:{}]\nset yrange [{}:{}]", cm.x() - half, cm.x() + half,
                            cm.y() - half, cm.y() + half));
    writer.Line(fmt::format("set title {}",
                            GnuplotQuote(fmt::format("{} — {}", snapshots[k].title,
                                                     geometry::ContactModeName(patch.mode)))));
    std::vector<std::string> parts;
    if (!patch.polygons.empty()) {
      parts.push_back(data + " index 0 with filledcurves closed fs solid 0.35 lc rgb 'black'");
      parts.push_back(data + " index 0 with lines lw 2 lc rgb 'black'");
    }
    if (!patch.segments.empty()) parts.push_back(data + " index 1 with lines lw 4 lc rgb 'black'");
    if (!patch.points.empty()) {
      parts.push_back(data + " index 2 with points pt 7 ps 1.5 lc rgb 'black'");
    }
    if (!patch.hull.empty()) {
      parts.push_back(data + " index 3 with linespoints dt 2 lw 2 pt 0 lc rgb 'red'");
    }
    parts.push_back(data + " index 4 with points pt 2 ps 3 lw 3 lc rgb 'red'");
    parts.push_back(data + " index 5 with points pt 6 ps 3 lw 2 lc rgb 'black'");
    writer.Line("plot " + fmt::format("{}", fmt::join(parts, ", \\\n     ")));
  }
  writer.EndPng();
}

// the row whose time is nearest `t`
std::size_t RowNear(const std::vector<double>& times, double t) {
  std::size_t best = 0;
  for (std::size_t i = 1; i < times.size(); ++i) {
    if (std::abs(times[i] - t) < std::abs(times[best] - t)) best = i;
  }
  return best;
}

// --- time plots ------------------------------------------------------------------------------

// a table of columns as a whitespace-separated data file (one row per time)
std::string Columnar(const std::vector<const std::vector<double>*>& columns) {
  std::string text;
  for (std::size_t r = 0; r < columns.front()->size(); ++r) {
    for (std::size_t i = 0; i < columns.size(); ++i) {
      text += (i ? " " : "") + Num((*columns[i])[r]);
    }
    text += "\n";
  }
  return text;
}

// stacked panels sharing the time axis: panel i plots column i + 2 (1-based; column 1 is t)
// panels of several bodies' curves: `data` holds t, then per label one column per body (their
// names in `bodies`, the legend's titles: "box", not the column prefix "box."); one body: one
// curve per panel, no legend
void PlotStackedBodies(PlotWriter& writer, const std::string& png, const std::string& data,
                       const std::vector<std::string>& labels,
                       const std::vector<std::string>& bodies, const std::string& title) {
  static const char* const kColours[] = {"#1f5fbf", "#d62728", "#2ca02c", "#ff7f0e",
                                         "#9467bd", "#8c564b", "#e377c2", "#17becf"};
  writer.BeginPng(png, 1000, 300 * static_cast<int>(labels.size()) + 40);
  writer.Line(
      fmt::format("set multiplot layout {},1 title {}", labels.size(), GnuplotQuote(title)));
  writer.Line(bodies.size() > 1 ? "set key outside right noenhanced" : "unset key");
  for (std::size_t i = 0; i < labels.size(); ++i) {
    writer.Line(fmt::format("set ylabel {}", GnuplotQuote(labels[i])));
    writer.Line(i + 1 == labels.size() ? "set xlabel 't (s)'" : "unset xlabel");
    std::string plot;
    for (std::size_t j = 0; j < bodies.size(); ++j) {
      const std::string name = bodies[j].empty() || bodies[j].back() != '.'
                                   ? bodies[j]
                                   : bodies[j].substr(0, bodies[j].size() - 1);
      plot +=
          fmt::format("{}{} using 1:{} with lines lw 2 lc rgb '{}'", plot.empty() ? "plot " : ", ",
                      data, 2 + i * bodies.size() + j, kColours[j % std::size(kColours)]);
      if (bodies.size() > 1) plot += " title " + GnuplotQuote(name.empty() ? "body" : name);
    }
    writer.Line(plot);
  }
  writer.EndPng();
}

// panels of one curve each: `data` holds t, then one column per label
void PlotStacked(PlotWriter& writer, const std::string& png, const std::string& data,
                 const std::vector<std::string>& labels, const std::string& title) {
  PlotStackedBodies(writer, png, data, labels, {""}, title);
}

std::optional<TrajectoryTable> ReadSibling(const std::string& dir, const std::string& name,
                                           const std::vector<double>& times) {
  const fs::path path = fs::path(dir) / name;
  if (!fs::exists(path)) return std::nullopt;
  TrajectoryTable table = ReadTrajectoryTable(path.string());
  const std::vector<double>& t = table.Column("t");
  bool same = t.size() == times.size();
  for (std::size_t i = 0; same && i < t.size(); ++i) same = std::abs(t[i] - times[i]) <= 1e-9;
  if (!same) {
    throw InputError(
        fmt::format("{}: {} rows at times that differ from trajectory.csv's {} "
                    "rows; expected the same scene run with another --model",
                    path.string(), t.size(), times.size()));
  }
  return table;
}

void PlotDeskVelocities(PlotWriter& writer, const std::string& dir, const TrajectoryTable& table,
                        const Columns& c) {
  const std::vector<double>& t = table.Column("t");
  const std::vector<double>& vx = table.Column(c.body + "vx");
  const std::vector<double>& wz = table.Column(c.body + "wz");
  struct Other {
    std::string label;
    std::vector<double> vx, wz, dvx, dwz;
  };
  std::vector<Other> others;
  for (const auto& [file, label] :
       {std::pair<std::string, std::string>{"trajectory_planar.csv", "planar sliding"},
        {"trajectory_multipatch.csv", "multi-patch"}}) {
    const std::optional<TrajectoryTable> sibling = ReadSibling(dir, file, t);
    if (!sibling) continue;
    const Columns sc = FindColumns(*sibling);
    Other other{label, sibling->Column(sc.body + "vx"), sibling->Column(sc.body + "wz"), {}, {}};
    for (std::size_t i = 0; i < t.size(); ++i) {
      other.dvx.push_back(vx[i] - other.vx[i]);
      other.dwz.push_back(wz[i] - other.wz[i]);
    }
    others.push_back(std::move(other));
  }
  std::vector<const std::vector<double>*> columns = {&t, &vx, &wz};
  for (const Other& o : others) {
    for (const auto* column : {&o.vx, &o.wz, &o.dvx, &o.dwz}) columns.push_back(column);
  }
  const std::string data = writer.Data("desk_velocity", Columnar(columns));

  const bool compare = !others.empty();
  writer.BeginPng("desk_velocity.png", 1400, compare ? 900 : 500);
  writer.Line(fmt::format("set multiplot layout {},2 title {}", compare ? 2 : 1,
                          GnuplotQuote(compare ? "desk: hull-ECP model (*) and the earlier models"
                                               : "desk: hull-ECP model")));
  writer.Line("set xlabel 't (s)'");
  const char* colors[] = {"#d62728", "#2ca02c"};
  for (int quantity = 0; quantity < 2; ++quantity) {
    writer.Line(
        fmt::format("set ylabel {}", GnuplotQuote(quantity == 0 ? "v_x (m/s)" : "w_z (rad/s)")));
    std::string plot = fmt::format("plot {} using 1:{} with lines lw 3 lc rgb '#1f5fbf' title {}",
                                   data, 2 + quantity, GnuplotQuote("hull ECP (*)"));
    for (std::size_t k = 0; k < others.size(); ++k) {
      plot += fmt::format(", {} using 1:{} with lines lw 1.5 dt 2 lc rgb '{}' title {}", data,
                          4 + 4 * k + quantity, colors[k], GnuplotQuote(others[k].label));
    }
    writer.Line(plot);
  }
  if (compare) {
    for (int quantity = 0; quantity < 2; ++quantity) {
      writer.Line(fmt::format("set ylabel {}", GnuplotQuote(quantity == 0 ? "v_x* - v_x (m/s)"
                                                                          : "w_z* - w_z (rad/s)")));
      writer.Line("set format y '%.1e'");
      std::string plot = "plot ";
      for (std::size_t k = 0; k < others.size(); ++k) {
        plot += fmt::format("{}{} using 1:{} with lines lw 1.5 lc rgb '{}' title {}", k ? ", " : "",
                            data, 6 + 4 * k + quantity, colors[k],
                            GnuplotQuote("hull ECP - " + others[k].label));
      }
      writer.Line(plot);
    }
  }
  writer.EndPng();
}

// --- the scene --------------------------------------------------------------------------------

struct RunInfo {
  std::string scene_path;  // as summary.json names it ("" when there is no summary)
};

RunInfo ReadSummary(const std::string& dir) {
  const fs::path path = fs::path(dir) / "summary.json";
  RunInfo info;
  if (!fs::exists(path)) return info;
  std::ifstream in(path);
  nlohmann::json json;
  try {
    json = nlohmann::json::parse(in);
  } catch (const nlohmann::json::exception& e) {
    throw InputError(
        fmt::format("{}: not valid JSON ({}); expected the summary.json of `ecpsim "
                    "run`",
                    path.string(), e.what()));
  }
  if (json.contains("scene") && json["scene"].is_string()) {
    info.scene_path = json["scene"].get<std::string>();
  }
  return info;
}

engine::Scene LoadRunScene(const std::string& dir, const RunInfo& info) {
  const std::string summary = (fs::path(dir) / "summary.json").string();
  if (info.scene_path.empty()) {
    throw InputError(
        fmt::format("{}: no \"scene\" key (or no file); expected the summary.json "
                    "of `ecpsim run`, which names the scene the snapshots need",
                    summary));
  }
  if (!fs::exists(info.scene_path)) {
    throw InputError(
        fmt::format("{}: scene = \"{}\": file not found from the current folder; "
                    "run `ecpsim plot` from the folder `ecpsim run` ran in",
                    summary, info.scene_path));
  }
  return engine::LoadScene(info.scene_path).scene;
}

PlotKind KindFromScene(const RunInfo& info) {
  const std::string stem = fs::path(info.scene_path).stem().string();
  if (stem == "desk") return PlotKind::kDesk;
  if (stem == "tbar") return PlotKind::kTBar;
  if (stem == "dumbbell") return PlotKind::kDumbbell;
  return PlotKind::kGeneric;
}

}  // namespace

PlotKind ParsePlotKind(const std::string& name) {
  if (name == "auto") return PlotKind::kAuto;
  if (name == "desk") return PlotKind::kDesk;
  if (name == "tbar") return PlotKind::kTBar;
  if (name == "dumbbell") return PlotKind::kDumbbell;
  if (name == "generic") return PlotKind::kGeneric;
  throw InputError(
      fmt::format("--scene = {}: expected desk, tbar, dumbbell, generic or auto", name));
}

std::vector<std::string> PlotRun(const std::string& dir, PlotKind kind) {
  const TrajectoryTable table = ReadTrajectoryTable((fs::path(dir) / "trajectory.csv").string());
  const Columns c = FindColumns(table);
  const RunInfo info = ReadSummary(dir);
  if (kind == PlotKind::kAuto) kind = KindFromScene(info);
  const std::vector<double>& t = table.Column("t");
  PlotWriter writer(dir);

  switch (kind) {
    case PlotKind::kDesk: {
      PlotDeskVelocities(writer, dir, table, c);
      const engine::Scene scene = LoadRunScene(dir, info);
      std::vector<Snapshot> snapshots;
      for (int k = 0; k < kDeskSnapshots; ++k) {
        const double time = t.front() + (t.back() - t.front()) * k / (kDeskSnapshots - 1);
        const std::size_t row = RowNear(t, time);
        snapshots.push_back({row, fmt::format("t = {:.2f} s", t[row])});
      }
      PlotSnapshots(writer, "desk_patches.png", table, c, scene, snapshots);
      break;
    }
    case PlotKind::kTBar: {
      const engine::Scene scene = LoadRunScene(dir, info);
      const std::vector<double>& ax = table.Column(c.contact + "a1x");
      const std::vector<double>& ay = table.Column(c.contact + "a1y");
      const std::vector<double>& az = table.Column(c.contact + "a1z");
      const std::vector<double>& qz = table.Column(c.body + "pz");
      const std::vector<double>& vz = table.Column(c.body + "vz");
      PlotStacked(writer, "tbar_ecp.png", writer.Data("tbar_ecp", Columnar({&t, &ax, &ay, &az})),
                  {"a_x (m)", "a_y (m)", "a_z (m)"}, "T-bar: equivalent contact point");
      PlotStacked(writer, "tbar_qz.png", writer.Data("tbar_qz", Columnar({&t, &qz})), {"q_z (m)"},
                  "T-bar: height of the centre of mass");

      // contact modes of the mesh at every row; the rows where the mode changes
      const geometry::Plane ground{Vector3d::UnitZ(), 0.0};
      std::vector<std::size_t> changes;
      geometry::ContactMode previous = geometry::ContactMode::kNone;
      for (std::size_t row = 0; row < table.rows(); ++row) {
        const geometry::ContactMode mode =
            geometry::ExtractContactPatch(scene.bodies[0].mesh, PoseAt(table, c, row), ground).mode;
        if (row > 0 && mode != previous) changes.push_back(row);
        previous = mode;
      }
      std::string marks;
      for (std::size_t row : changes) {
        marks += Num(t[row]) + " " + Num(vz[row]) + " " + Num(ax[row]) + "\n";
      }
      const std::string data = writer.Data("tbar_vz_ax", Columnar({&t, &vz, &ax}));
      const std::string mark_data = marks.empty() ? "" : writer.Data("tbar_mode_changes", marks);
      writer.BeginPng("tbar_vz_ax.png", 1000, 700);
      writer.Line(GnuplotQuote("T-bar: v_z above a_x; red dots: contact-mode changes")
                      .insert(0, "set multiplot layout 2,1 title "));
      writer.Line("unset key");
      for (int panel = 0; panel < 2; ++panel) {
        writer.Line(
            fmt::format("set ylabel {}", GnuplotQuote(panel == 0 ? "v_z (m/s)" : "a_x (m)")));
        writer.Line(panel == 1 ? "set xlabel 't (s)'" : "unset xlabel");
        std::string plot =
            fmt::format("plot {} using 1:{} with lines lw 2 lc rgb '#1f5fbf'", data, 2 + panel);
        if (!mark_data.empty()) {
          plot += fmt::format(", {} using 1:{} with points pt 7 ps 1 lc rgb 'red'", mark_data,
                              2 + panel);
        }
        writer.Line(plot);
      }
      writer.EndPng();

      // snapshots at (up to eight, evenly chosen) mode changes
      std::vector<Snapshot> snapshots;
      const std::size_t count = std::min<std::size_t>(changes.size(), kMaxModeSnapshots);
      for (std::size_t k = 0; k < count; ++k) {
        const std::size_t row = changes[count == 1 ? 0 : k * (changes.size() - 1) / (count - 1)];
        snapshots.push_back({row, fmt::format("t = {:.2f} s", t[row])});
      }
      PlotSnapshots(writer, "tbar_patches.png", table, c, scene, snapshots);
      break;
    }
    case PlotKind::kDumbbell: {
      const engine::Scene scene = LoadRunScene(dir, info);
      const std::vector<double>& px = table.Column(c.body + "px");
      const std::vector<double>& py = table.Column(c.body + "py");
      const std::vector<double>& pz = table.Column(c.body + "pz");
      PlotStacked(writer, "dumbbell_cm.png",
                  writer.Data("dumbbell_cm", Columnar({&t, &px, &py, &pz})),
                  {"q_x (m)", "q_y (m)", "q_z (m)"}, "dumbbell: centre of mass");
      std::vector<Snapshot> snapshots;
      for (double time : kDumbbellSnapshotTimes) {
        if (time > t.back() + 1e-9) continue;
        const std::size_t row = RowNear(t, time);
        snapshots.push_back({row, fmt::format("t = {:.2f} s", t[row])});
      }
      PlotSnapshots(writer, "dumbbell_patches.png", table, c, scene, snapshots, kDumbbellSagitta);
      break;
    }
    case PlotKind::kGeneric:
    case PlotKind::kAuto: {
      // every body (a legend when there are several)
      std::vector<const std::vector<double>*> position = {&t}, velocity = {&t};
      for (const char* name : {"px", "py", "pz"})
        for (const std::string& body : c.bodies) position.push_back(&table.Column(body + name));
      for (const char* name : {"vx", "vy", "vz", "wx", "wy", "wz"})
        for (const std::string& body : c.bodies) velocity.push_back(&table.Column(body + name));
      const std::string title = c.bodies.size() > 1 ? "centres of mass" : "centre of mass";
      PlotStackedBodies(writer, "position.png", writer.Data("position", Columnar(position)),
                        {"p_x (m)", "p_y (m)", "p_z (m)"}, c.bodies, title);
      PlotStackedBodies(
          writer, "velocity.png", writer.Data("velocity", Columnar(velocity)),
          {"v_x (m/s)", "v_y (m/s)", "v_z (m/s)", "w_x (rad/s)", "w_y (rad/s)", "w_z (rad/s)"},
          c.bodies, "velocity (world frame)");
      break;
    }
  }
  return writer.Run();
}

}  // namespace ecpsim::app
