// Typed readers of YAML nodes and the messages that name where a value came from.

#include <algorithm>
#include <cmath>
#include <set>

#include "engine/scene_io/scene_yaml_reader.h"

namespace ecpsim::engine::yaml {
namespace {

// values shown in messages are cut to this many characters
constexpr size_t kMaxShownValue = 60;

// "bodies[0].mass" → "bodies.0.mass", the spelling of --set keys
std::string Dotted(const std::string& key) {
  std::string out;
  for (char c : key) {
    if (c == '[') {
      out += '.';
    } else if (c != ']') {
      out += c;
    }
  }
  return out;
}

int EditDistance(const std::string& a, const std::string& b) {
  std::vector<int> row(b.size() + 1);
  for (size_t j = 0; j <= b.size(); ++j) row[j] = static_cast<int>(j);
  for (size_t i = 1; i <= a.size(); ++i) {
    int diagonal = row[0];
    row[0] = static_cast<int>(i);
    for (size_t j = 1; j <= b.size(); ++j) {
      const int substitute = diagonal + (a[i - 1] == b[j - 1] ? 0 : 1);
      diagonal = row[j];
      row[j] = std::min({row[j] + 1, row[j - 1] + 1, substitute});
    }
  }
  return row[b.size()];
}

std::string JoinKeys(const std::vector<std::string>& keys) {
  std::string out;
  for (const std::string& k : keys) {
    out += (out.empty() ? "" : ", ") + k;
  }
  return out;
}

// "a.b[2].c" → {"a", "b", "2", "c"}
std::vector<std::string> SplitKey(const std::string& key) {
  std::vector<std::string> parts;
  std::string part;
  for (char c : key) {
    if (c == '.' || c == '[' || c == ']') {
      if (!part.empty()) parts.push_back(part);
      part.clear();
    } else {
      part += c;
    }
  }
  if (!part.empty()) parts.push_back(part);
  return parts;
}

}  // namespace

// ---- messages --------------------------------------------------------------------------------

std::string Where(const Context& ctx, const YAML::Node& node, const std::string& key) {
  const std::string dotted = Dotted(key);
  for (const Override& o : ctx.overrides) {
    if (dotted == o.dotted_key || dotted.rfind(o.dotted_key + ".", 0) == 0) {
      return fmt::format("{}: --set {}", ctx.file, o.text);
    }
  }
  const YAML::Mark mark = node.IsDefined() ? node.Mark() : YAML::Mark::null_mark();
  if (mark.is_null() || !ctx.has_lines) {
    return ctx.file;
  }
  return fmt::format("{}:{}:{}", ctx.file, mark.line + 1, mark.column + 1);
}

std::string Printable(const std::string& text) {
  std::string out;
  for (char c : text) {
    if (static_cast<unsigned char>(c) < 0x20 || c == 0x7f) {
      out += fmt::format("\\x{:02x}", static_cast<unsigned char>(c));
    } else {
      out += c;
    }
  }
  return out;
}

std::string Show(const YAML::Node& node) {
  if (!node.IsDefined()) {
    return "(missing)";
  }
  std::string text;
  if (node.IsNull()) {
    text = "null";
  } else if (node.IsScalar()) {
    text = node.Scalar();
  } else {
    YAML::Emitter out;
    out.SetSeqFormat(YAML::Flow);
    out.SetMapFormat(YAML::Flow);
    out << node;
    text = out.c_str();
  }
  text = Printable(text);
  if (text.size() > kMaxShownValue) {
    text = text.substr(0, kMaxShownValue - 3) + "...";
  }
  return text;
}

void Fail(const Context& ctx, const YAML::Node& node, const std::string& key,
          const std::string& expected) {
  throw InputError(
      fmt::format("{}: {} = {}: expected {}", Where(ctx, node, key), key, Show(node), expected));
}

std::string Child(const std::string& key, const std::string& child) {
  return key.empty() ? child : key + "." + child;
}

std::string Index(const std::string& key, size_t i) { return fmt::format("{}[{}]", key, i); }

YAML::Node FindNode(const YAML::Node& root, const std::string& key) {
  YAML::Node node;
  node.reset(root);
  for (const std::string& part : SplitKey(key)) {
    YAML::Node child;
    if (node.IsSequence()) {
      size_t index = 0;
      if (part.find_first_not_of("0123456789") != std::string::npos)
        return YAML::Node(YAML::NodeType::Undefined);
      index = std::stoul(part);
      if (index >= node.size()) return YAML::Node(YAML::NodeType::Undefined);
      child = node[index];
    } else if (node.IsMap()) {
      child = node[part];
      if (!child) return YAML::Node(YAML::NodeType::Undefined);
    } else {
      return YAML::Node(YAML::NodeType::Undefined);
    }
    node.reset(child);
  }
  return node;
}

// ---- overrides -------------------------------------------------------------------------------

void ApplyOverride(const Context& ctx, YAML::Node& root, const std::string& text,
                   std::vector<Override>& applied) {
  const size_t eq = text.find('=');
  if (eq == std::string::npos || eq == 0) {
    throw InputError(
        fmt::format("{}: --set {}: expected key=value, e.g. h=0.005 or "
                    "bodies.0.mass=3",
                    ctx.file, text));
  }
  const std::string dotted = text.substr(0, eq);
  YAML::Node value;
  try {
    value = YAML::Load(text.substr(eq + 1));
  } catch (const YAML::Exception& e) {
    throw InputError(
        fmt::format("{}: --set {}: the value is not valid YAML ({})", ctx.file, text, e.msg));
  }
  std::vector<std::string> parts;
  for (size_t start = 0;;) {
    const size_t dot = dotted.find('.', start);
    parts.push_back(dotted.substr(start, dot - start));
    if (dot == std::string::npos) break;
    start = dot + 1;
  }
  YAML::Node node;
  node.reset(root);
  std::string prefix;
  for (size_t i = 0; i < parts.size(); ++i) {
    const std::string& part = parts[i];
    const bool last = i + 1 == parts.size();
    if (part.empty()) {
      throw InputError(
          fmt::format("{}: --set {}: empty key component in \"{}\"", ctx.file, text, dotted));
    }
    if (node.IsSequence()) {
      int index = -1;
      if (!YAML::convert<int>::decode(YAML::Node(part), index) || index < 0 ||
          index >= static_cast<int>(node.size())) {
        throw InputError(fmt::format(
            "{}: --set {}: {} is a list of {} entries; expected an "
            "index 0..{} instead of \"{}\"",
            ctx.file, text, prefix, node.size(), static_cast<int>(node.size()) - 1, part));
      }
      if (last) {
        node[index] = value;
      } else {
        YAML::Node child = node[index];
        node.reset(child);
      }
    } else if (node.IsMap() || node.IsNull()) {
      if (last) {
        node[part] = value;
      } else {
        if (!node[part]) node[part] = YAML::Node(YAML::NodeType::Map);
        YAML::Node child = node[part];
        node.reset(child);
      }
    } else {
      throw InputError(
          fmt::format("{}: --set {}: {} = {} is a value, not a mapping or list; "
                      "key \"{}\" cannot go inside it",
                      ctx.file, text, prefix, Show(node), part));
    }
    prefix = prefix.empty() ? part : prefix + "." + part;
  }
  applied.push_back({dotted, text});
}

// ---- typed readers ---------------------------------------------------------------------------

MapNode::MapNode(const Context& ctx, const YAML::Node& node, std::string key,
                 const std::vector<std::string>& allowed)
    : ctx_(ctx), node_(node), key_(std::move(key)) {
  if (!node.IsMap()) {
    Fail(ctx, node, key_.empty() ? "(scene)" : key_,
         fmt::format("a mapping with keys {}", JoinKeys(allowed)));
  }
  std::set<std::string> seen;
  for (auto it = node.begin(); it != node.end(); ++it) {
    const YAML::Node& k = it->first;
    const std::string name = k.IsScalar() ? k.Scalar() : Show(k);
    const std::string full = Printable(Child(key_, name));
    if (std::find(allowed.begin(), allowed.end(), name) == allowed.end()) {
      std::string best;
      int best_distance = 3;  // suggest only near misses (up to two edits)
      for (const std::string& a : allowed) {
        const int d = EditDistance(name, a);
        if (d < best_distance) {
          best_distance = d;
          best = a;
        }
      }
      const std::string hint = best.empty() ? "" : fmt::format(" (did you mean \"{}\"?)", best);
      throw InputError(fmt::format("{}: {}: unknown key{}; expected one of {}", Where(ctx, k, full),
                                   full, hint, JoinKeys(allowed)));
    }
    if (!seen.insert(name).second) {
      throw InputError(
          fmt::format("{}: {}: duplicate key; expected each key once", Where(ctx, k, full), full));
    }
  }
}

YAML::Node MapNode::Require(const std::string& k, const std::string& expected) const {
  const YAML::Node value = node_[k];
  if (!value) {
    throw InputError(
        fmt::format("{}: {} = (missing): expected {}", Where(ctx_, node_, key_), Key(k), expected));
  }
  return value;
}

void MapNode::FailAt(const std::string& k, const std::string& expected) const {
  if (Has(k)) {
    Fail(ctx_, Get(k), Key(k), expected);
  }
  throw InputError(
      fmt::format("{}: {} = (missing): expected {}", Where(ctx_, node_, key_), Key(k), expected));
}

double ReadNumber(const Context& ctx, const YAML::Node& node, const std::string& key,
                  const std::string& expected) {
  double value = 0;
  if (!node.IsScalar() || !YAML::convert<double>::decode(node, value) || !std::isfinite(value)) {
    Fail(ctx, node, key, expected);
  }
  const std::string magnitude = OutOfMagnitude(value);
  if (!magnitude.empty()) {
    Fail(ctx, node, key,
         fmt::format("{}; each {} (larger values overflow when squared)", expected, magnitude));
  }
  return value;
}

double ReadPositive(const Context& ctx, const YAML::Node& node, const std::string& key,
                    const PositiveRange& range, const std::string& expected) {
  double value = 0;
  if (!node.IsScalar() || !YAML::convert<double>::decode(node, value) || !std::isfinite(value) ||
      !(value > 0)) {
    Fail(ctx, node, key, expected);
  }
  const std::string in_range = OutOfRange(value, range);
  if (!in_range.empty()) Fail(ctx, node, key, in_range);
  return value;
}

int ReadInt(const Context& ctx, const YAML::Node& node, const std::string& key,
            const std::string& expected) {
  int value = 0;
  if (!node.IsScalar() || !YAML::convert<int>::decode(node, value)) {
    Fail(ctx, node, key, expected);
  }
  return value;
}

bool ReadBool(const Context& ctx, const YAML::Node& node, const std::string& key) {
  bool value = false;
  if (!node.IsScalar() || !YAML::convert<bool>::decode(node, value)) {
    Fail(ctx, node, key, "true or false");
  }
  return value;
}

std::string ReadString(const Context& ctx, const YAML::Node& node, const std::string& key,
                       const std::string& expected) {
  // a NUL would cut the text short where it is used as a C string (paths, muparser)
  if (!node.IsScalar() || node.Scalar().empty() || node.Scalar().find('\0') != std::string::npos) {
    Fail(ctx, node, key, fmt::format("{}, without NUL characters", expected));
  }
  return node.Scalar();
}

std::string ReadName(const Context& ctx, const YAML::Node& node, const std::string& key) {
  if (!node.IsScalar() || !IsValidName(node.Scalar())) {
    Fail(ctx, node, key, kNameExpected);
  }
  return node.Scalar();
}

Eigen::VectorXd ReadNumbers(const Context& ctx, const YAML::Node& node, const std::string& key,
                            size_t count, const std::string& expected) {
  if (!node.IsSequence() || node.size() != count) {
    Fail(ctx, node, key, expected);
  }
  Eigen::VectorXd values(count);
  for (size_t i = 0; i < count; ++i) {
    values[i] = ReadNumber(ctx, node[i], Index(key, i), expected);
  }
  return values;
}

Eigen::Vector3d ReadVector3(const Context& ctx, const YAML::Node& node, const std::string& key,
                            const std::string& unit) {
  return ReadNumbers(ctx, node, key, 3,
                     fmt::format("a list of 3 finite numbers [x, y, z] ({})", unit));
}

Eigen::Vector3d ReadLengths3(const Context& ctx, const YAML::Node& node, const std::string& key,
                             const std::string& expected) {
  if (!node.IsSequence() || node.size() != 3) {
    Fail(ctx, node, key, expected);
  }
  Eigen::Vector3d values;
  for (size_t i = 0; i < 3; ++i) {
    double value = 0;
    if (!node[i].IsScalar() || !YAML::convert<double>::decode(node[i], value) ||
        !std::isfinite(value) || !(value > 0)) {
      Fail(ctx, node, key, expected);
    }
    const std::string in_range = OutOfRange(value, kLengthRange);
    if (!in_range.empty()) Fail(ctx, node, key, fmt::format("{}, each {}", expected, in_range));
    values[i] = value;
  }
  return values;
}

}  // namespace ecpsim::engine::yaml
