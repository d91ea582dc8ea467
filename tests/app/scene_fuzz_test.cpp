// A deterministic fuzz test of `ecpsim run`: mutations of the shipped scenes (scenes/*.yaml) from
// a fixed seed — numbers replaced by 0, −1, 1e200, 1e-300, .nan, .inf, huge integers, values of
// the wrong type, deleted, duplicated and misspelt keys, NUL bytes, truncation, a changed
// contact model — each run through the built CLI. Every case must end in a defined way: exit code
// 0, 1, 3 or 5 (never a signal, a hang or 4); an error of bad input names file:line:col; no
// output file holds a non-finite number; a successful run completed ceil(duration / h) steps.
// A failing case prints the seed, the case and its mutations, and leaves the scene in
// build/tests/scene_fuzz_failures/ for `ecpsim run` by hand.

#include <fmt/format.h>
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cfloat>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <random>
#include <regex>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include "engine/report/trajectory_columns.h"
#include "tests/cli_test.h"

namespace ecpsim {
namespace {

namespace fs = std::filesystem;

// the fuzzer's seed: every run mutates the same way (std::mt19937_64's sequence is fixed by the
// standard; the test maps it to choices by modulo, not by library-defined distributions)
constexpr std::uint64_t kSeed = 20240614;
// cases per shipped scene (9 scenes, one test each: 540 cases, about 25 s of CPU in all); the
// environment variable ECPSIM_FUZZ_CASES asks for more (a longer search, by hand)
constexpr int kCasesPerScene = 60;
// s: the base scenes are cut to this duration before mutating (5 steps at h = 0.01 s), so a case
// that stays valid runs a few steps; a mutated duration or h can still reach the step limit's
// error, and the values a mutation writes (at most 3.5 s at h = 0.01 s: 350 steps) keep every
// valid case well under a second
constexpr double kBaseDuration = 0.05;
// s of wall time after which a case counts as a hang
constexpr int kTimeoutSeconds = 30;
// steps = ceil(duration / h) with the CLI's slack: a ratio within 1e-9 steps (plus its own
// round-off) of an integer is that integer
constexpr double kStepCountSlack = 1e-9;

const char* const kScenes[] = {"desk",  "dumbbell", "slide",     "tbar",   "tilted_box",
                               "stack", "push_box", "tbar_push", "gripper"};

// values a mutated number takes: zero, negative, overflowing, underflowing, non-finite, integers
// beyond int and long, and a few ordinary ones
const char* const kNumbers[] = {"0",    "-1",   "1e200",      "1e-300",
                                ".nan", ".inf", "-.inf",      "1",
                                "3.5",  "1e-9", "2147483648", "99999999999999999999",
                                "-0",   "0x10"};
// values of the wrong type for a number, a list or a mapping
const char* const kWrongTypes[] = {"heavy", "[1, 2]", "{x: 1}", "''",    "true",
                                   "null",  "[]",     "{}",     "[[1]]", "\"\""};
const char* const kModels[] = {"hull", "planar", "multipatch", "point"};

class Mutator {
 public:
  explicit Mutator(std::uint64_t seed) : rng_(seed) {}

  size_t Below(size_t n) { return n == 0 ? 0 : static_cast<size_t>(rng_() % n); }

  // one random mutation of `text`; its description goes to `log`
  std::string Mutate(const std::string& text, std::vector<std::string>& log) {
    switch (Below(9)) {
      case 0:
      case 1:
        return ReplaceNumber(text, kNumbers[Below(std::size(kNumbers))], log);
      case 2:
        return ReplaceNumber(text, kWrongTypes[Below(std::size(kWrongTypes))], log);
      case 3:
        return EditLine(text, log, /*duplicate=*/false);
      case 4:
        return EditLine(text, log, /*duplicate=*/true);
      case 5:
        return InsertNul(text, log);
      case 6: {
        const size_t cut = Below(text.size());
        log.push_back(fmt::format("truncate at byte {}", cut));
        return text.substr(0, cut);
      }
      case 7:
        return Misspell(text, log);
      default: {
        const char* model = kModels[Below(std::size(kModels))];
        log.push_back(fmt::format("model: {}", model));
        return fmt::format("model: {}\n{}", model, text);
      }
    }
  }

 private:
  // the positions of numbers outside comments
  static std::vector<std::pair<size_t, size_t>> Numbers(const std::string& text) {
    static const std::regex kNumber(
        R"((^|[\s\[,:(*+/-])(-?\d+(\.\d*)?([eE][-+]?\d+)?)(?=[\s\],)*+/]|$))");
    std::vector<std::pair<size_t, size_t>> found;
    size_t line_start = 0;
    while (line_start < text.size()) {
      size_t line_end = text.find('\n', line_start);
      if (line_end == std::string::npos) line_end = text.size();
      const std::string line = text.substr(line_start, line_end - line_start);
      const std::string code = line.substr(0, line.find('#'));
      for (auto it = std::sregex_iterator(code.begin(), code.end(), kNumber);
           it != std::sregex_iterator(); ++it) {
        found.emplace_back(line_start + it->position(2), it->length(2));
      }
      line_start = line_end + 1;
    }
    return found;
  }

  std::string ReplaceNumber(const std::string& text, const std::string& value,
                            std::vector<std::string>& log) {
    const auto numbers = Numbers(text);
    if (numbers.empty()) return text;
    const auto [at, length] = numbers[Below(numbers.size())];
    log.push_back(fmt::format("number {} at byte {} -> {}", text.substr(at, length), at, value));
    return text.substr(0, at) + value + text.substr(at + length);
  }

  // lines with content (not blank, not comment-only)
  static std::vector<std::pair<size_t, size_t>> Lines(const std::string& text) {
    std::vector<std::pair<size_t, size_t>> lines;
    size_t start = 0;
    while (start < text.size()) {
      size_t end = text.find('\n', start);
      if (end == std::string::npos) end = text.size();
      const std::string line = text.substr(start, end - start);
      const size_t first = line.find_first_not_of(' ');
      if (first != std::string::npos && line[first] != '#') lines.emplace_back(start, end);
      start = end + 1;
    }
    return lines;
  }

  std::string EditLine(const std::string& text, std::vector<std::string>& log, bool duplicate) {
    const auto lines = Lines(text);
    if (lines.empty()) return text;
    const auto [start, end] = lines[Below(lines.size())];
    const std::string line = text.substr(start, end - start);
    log.push_back(fmt::format("{} line \"{}\"", duplicate ? "duplicate" : "delete", line));
    const std::string rest = end < text.size() ? text.substr(end + 1) : "";
    return text.substr(0, start) + (duplicate ? line + "\n" + line + "\n" : "") + rest;
  }

  // a raw NUL byte anywhere, or an escaped one ("\0") inside a double-quoted string
  std::string InsertNul(const std::string& text, std::vector<std::string>& log) {
    const size_t quote = text.find("\"", Below(text.size()));
    if (quote != std::string::npos && Below(2) == 0) {
      log.push_back(fmt::format("escaped NUL after the quote at byte {}", quote));
      return text.substr(0, quote + 1) + "\\0" + text.substr(quote + 1);
    }
    const size_t at = Below(text.size());
    log.push_back(fmt::format("raw NUL at byte {}", at));
    return text.substr(0, at) + std::string(1, '\0') + text.substr(at);
  }

  // a key with one letter dropped
  std::string Misspell(const std::string& text, std::vector<std::string>& log) {
    static const std::regex kKey(R"(([A-Za-z_]{2,}):)");
    std::vector<std::pair<size_t, size_t>> keys;
    for (const auto& [start, end] : Lines(text)) {
      const std::string line = text.substr(start, end - start);
      for (auto it = std::sregex_iterator(line.begin(), line.end(), kKey);
           it != std::sregex_iterator(); ++it) {
        keys.emplace_back(start + it->position(1), it->length(1));
      }
    }
    if (keys.empty()) return text;
    const auto [at, length] = keys[Below(keys.size())];
    const size_t drop = at + Below(length);
    log.push_back(fmt::format("misspell key {} (drop byte {})", text.substr(at, length), drop));
    return text.substr(0, drop) + text.substr(drop + 1);
  }

  std::mt19937_64 rng_;
};

std::string ReadText(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  std::stringstream text;
  text << in.rdbuf();
  return text.str();
}

// the scene cut to kBaseDuration: its `duration:` value replaced
std::string ShortScene(const std::string& text) {
  static const std::regex kDuration(R"((^|\n)duration:[ \t]*[0-9.eE+-]+)");
  return std::regex_replace(text, kDuration, fmt::format("$1duration: {}", kBaseDuration));
}

int CasesPerScene() {
  const char* cases = std::getenv("ECPSIM_FUZZ_CASES");
  return cases != nullptr && std::atoi(cases) > 0 ? std::atoi(cases) : kCasesPerScene;
}

class SceneFuzzTest : public testing::CliTest, public ::testing::WithParamInterface<int> {
 protected:
  // every field of every data row parses completely as a finite double, except the model
  // columns', which name a model
  static std::string NonFiniteInCsv(const fs::path& path, long& data_rows, double& last_t) {
    std::ifstream in(path);
    std::string line;
    std::getline(in, line);  // header
    std::vector<bool> text_column;
    {
      std::stringstream header(line);
      for (std::string name; std::getline(header, name, ',');)
        text_column.push_back(engine::IsModelColumn(name));
    }
    const std::set<std::string> models = {"initial",    "free",  "planar",   "hull",
                                          "multipatch", "point", "kinematic", "parts"};
    data_rows = 0;
    while (std::getline(in, line)) {
      ++data_rows;
      std::stringstream stream(line);
      size_t column = 0;
      for (std::string field; std::getline(stream, field, ','); ++column) {
        if (column < text_column.size() && text_column[column]) {
          if (models.count(field) == 0)
            return fmt::format("trajectory.csv row {} column {}: \"{}\" is no model", data_rows,
                               column, field);
          continue;
        }
        char* end = nullptr;
        const double value = std::strtod(field.c_str(), &end);
        if (field.empty() || *end != '\0' || !std::isfinite(value)) {
          return fmt::format("trajectory.csv row {} column {}: \"{}\"", data_rows, column, field);
        }
        if (column == 0) last_t = value;
      }
    }
    return "";
  }

  // every number of summary.json is finite and none is null (nlohmann writes NaN as null)
  static std::string NonFiniteInJson(const nlohmann::json& json) {
    for (const auto& [key, value] : json.items()) {
      if (value.is_null()) return fmt::format("summary.json {} is null", key);
      if (value.is_number() && !std::isfinite(value.get<double>())) {
        return fmt::format("summary.json {} = {}", key, value.dump());
      }
    }
    return "";
  }

  // the problems of one case's outcome, "" when it behaved
  std::string Check(const testing::CliResult& result, const fs::path& out) {
    static const std::regex kLocated(R"(\.yaml:\d+:\d+: |\.yaml: --set )");
    if (result.exit_code != 0 && result.exit_code != 1 && result.exit_code != 3 &&
        result.exit_code != 5) {
      return fmt::format("exit code {} (expected 0, 1, 3 or 5)", result.exit_code);
    }
    if (result.exit_code == 1 && !std::regex_search(result.output, kLocated)) {
      return "a bad-input error without file:line:col";
    }
    long data_rows = 0;
    double last_t = 0;
    if (fs::exists(out / "trajectory.csv")) {
      const std::string bad = NonFiniteInCsv(out / "trajectory.csv", data_rows, last_t);
      if (!bad.empty()) return bad;
    }
    nlohmann::json summary;
    if (fs::exists(out / "summary.json")) {
      std::ifstream in(out / "summary.json");
      summary = nlohmann::json::parse(in, nullptr, /*allow_exceptions=*/false);
      if (summary.is_discarded()) return "summary.json is not valid JSON";
      const std::string bad = NonFiniteInJson(summary);
      if (!bad.empty()) return bad;
    }
    if (result.exit_code != 0) return "";
    if (summary.is_null()) return "exit code 0 without summary.json";
    const double h = summary["h"].get<double>();
    const double duration = summary["duration"].get<double>();
    // ceil(duration / h), a ratio within round-off of an integer counting as that integer
    const double ratio = duration / h;
    const double nearest = std::round(ratio);
    const bool integer = std::abs(ratio - nearest) <= kStepCountSlack + 8 * DBL_EPSILON * ratio;
    const long planned = std::max(1L, static_cast<long>(integer ? nearest : std::ceil(ratio)));
    if (summary["planned_steps"].get<long>() != planned ||
        summary["steps"].get<long>() != planned) {
      return fmt::format("exit code 0 after {} of {} steps; ceil({} / {}) = {}",
                         summary["steps"].get<long>(), summary["planned_steps"].get<long>(),
                         duration, h, planned);
    }
    // the initial state, the written steps and the last one, the last at t_end = steps · h
    if (data_rows != summary["rows"].get<long>() || data_rows < 2) {
      return fmt::format("trajectory.csv has {} rows, summary.json says {}", data_rows,
                         summary["rows"].get<long>());
    }
    // N additions t += h, each rounded by at most ε t_end / 2, and the product N h by one more
    const double t_end = planned * h;
    if (std::abs(last_t - t_end) > (planned + 1) * DBL_EPSILON * t_end) {
      return fmt::format("the last row is at t = {}, expected {} steps of {} s", last_t, planned,
                         h);
    }
    return "";
  }
};

TEST_P(SceneFuzzTest, EveryMutationEndsWithADefinedOutcome) {
  const std::string name = kScenes[GetParam()];
  const fs::path scenes = fs::path(ECPSIM_SOURCE_DIR) / "scenes";
  fs::copy(scenes / "meshes", dir_ / "meshes");
  const std::string base = ShortScene(ReadText(scenes / (name + ".yaml")));
  ASSERT_NE(base.find(fmt::format("duration: {}", kBaseDuration)), std::string::npos) << name;

  const std::uint64_t seed = kSeed + static_cast<std::uint64_t>(GetParam());
  Mutator mutator(seed);
  int outcomes[6] = {};
  const int cases = CasesPerScene();
  for (int c = 0; c < cases; ++c) {
    std::vector<std::string> log;
    std::string text = mutator.Mutate(base, log);
    if (mutator.Below(3) == 0) text = mutator.Mutate(text, log);
    const fs::path scene = dir_ / fmt::format("{}_{}.yaml", name, c);
    const fs::path out = dir_ / fmt::format("out_{}", c);
    std::ofstream(scene, std::ios::binary) << text;
    const testing::CliResult result =
        Run(fmt::format("run '{}' -o '{}'", scene.string(), out.string()),
            fmt::format("timeout {}", kTimeoutSeconds));
    if (result.exit_code >= 0 && result.exit_code <= 5) ++outcomes[result.exit_code];

    const std::string problem = Check(result, out);
    if (!problem.empty()) {
      const fs::path keep = fs::path(ECPSIM_BINARY_DIR) / "tests" / "scene_fuzz_failures";
      fs::create_directories(keep);
      fs::copy_file(scene, keep / scene.filename(), fs::copy_options::overwrite_existing);
      std::string mutations;
      for (const std::string& m : log) mutations += "\n  " + m;
      ADD_FAILURE() << fmt::format(
          "seed {} scene {} case {}: {}\nmutations:{}\nscene kept as {} (from {})\noutput: {}",
          seed, name, c, problem, mutations, (keep / scene.filename()).string(), dir_.string(),
          result.output);
    }
  }
  // the mutations reach all the outcomes that matter: runs that succeed and inputs rejected
  EXPECT_GT(outcomes[0], 0) << name;
  EXPECT_GT(outcomes[1], 0) << name;
  std::printf("%s: %d ok, %d bad input, %d solver failures, %d model invalid of %d cases\n",
              name.c_str(), outcomes[0], outcomes[1], outcomes[3], outcomes[5], cases);
}

INSTANTIATE_TEST_SUITE_P(ShippedScenes, SceneFuzzTest,
                         ::testing::Range(0, static_cast<int>(std::size(kScenes))),
                         [](const auto& param_info) {
                           return std::string(kScenes[param_info.param]);
                         });

}  // namespace
}  // namespace ecpsim
