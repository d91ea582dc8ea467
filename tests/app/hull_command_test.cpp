// Runs the built `ecpsim hull` command (a separate process) and checks its JSON and its errors.

#include <sys/wait.h>

#include <array>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <string>

#include <fmt/format.h>
#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "tests/geometry/test_meshes.h"

namespace ecpsim::geometry {
namespace {

using testing::FixturePath;
using ::testing::HasSubstr;

// the box fixture's numbers are exact in binary: only summation round-off remains
constexpr double kRoundOff = 1e-12;

const std::string kBinary = std::string(ECPSIM_BINARY_DIR) + "/app/ecpsim";

struct Result {
  int exit_code = -1;
  std::string output;
};

// runs `ecpsim ARGS` and collects stdout (and stderr too when `merge_stderr`)
Result RunEcpsim(const std::string& args, bool merge_stderr) {
  const std::string command =
      "'" + kBinary + "' " + args + (merge_stderr ? " 2>&1" : " 2>/dev/null");
  Result result;
  std::FILE* pipe = popen(command.c_str(), "r");
  if (pipe == nullptr) return result;
  std::array<char, 4096> buffer;
  std::size_t n;
  while ((n = std::fread(buffer.data(), 1, buffer.size(), pipe)) > 0)
    result.output.append(buffer.data(), n);
  const int status = pclose(pipe);
  result.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  return result;
}

std::string Quote(const std::string& path) { return "'" + path + "'"; }

class HullCommandTest : public ::testing::Test {
 protected:
  void SetUp() override {
    // a missing binary is a failure, not a skip: the command is part of what is tested
    ASSERT_TRUE(std::filesystem::exists(kBinary)) << kBinary << " is missing; build target ecpsim";
  }
};

TEST_F(HullCommandTest, JsonForTheBoxFixture) {
  const Result r =
      RunEcpsim("hull " + Quote(FixturePath("box.obj")) + " --json --density 2", false);
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const nlohmann::json j = nlohmann::json::parse(r.output);
  for (const char* key :
       {"vertices", "triangles", "closed", "oriented", "volume", "mass", "center_of_mass",
        "inertia", "principal_moments", "principal_axes", "mass_source", "hull"}) {
    EXPECT_TRUE(j.contains(key)) << key;
  }
  EXPECT_EQ(j["vertices"], 8);
  EXPECT_EQ(j["triangles"], 12);
  EXPECT_EQ(j["closed"], true);
  EXPECT_EQ(j["oriented"], true);
  EXPECT_EQ(j["mass_source"], "mesh");
  EXPECT_NEAR(j["volume"].get<double>(), 6.0, kRoundOff);
  EXPECT_NEAR(j["mass"].get<double>(), 12.0, kRoundOff);
  const Eigen::Vector3d centre(0.5, 1.0, 1.5);
  for (int a = 0; a < 3; ++a)
    EXPECT_NEAR(j["center_of_mass"][a].get<double>(), centre[a], kRoundOff);
  // 12 kg box 1 × 2 × 3: I = m/12 (b² + c², a² + c², a² + b²) = (13, 10, 5) kg·m²
  const Eigen::Vector3d moments(13.0, 10.0, 5.0);
  for (int row = 0; row < 3; ++row) {
    for (int c = 0; c < 3; ++c) {
      EXPECT_NEAR(j["inertia"][row][c].get<double>(), row == c ? moments[row] : 0.0, kRoundOff);
    }
  }

  // the hull in the body frame: the box centred at the origin, six faces n·y ≤ |n|·half size
  const nlohmann::json& hull = j["hull"];
  EXPECT_EQ(hull["vertices"].size(), 8u);
  EXPECT_EQ(hull["faces"].size(), 6u);
  ASSERT_EQ(hull["halfspaces"].size(), 6u);
  const Eigen::Vector3d half(0.5, 1.0, 1.5);
  for (const nlohmann::json& h : hull["halfspaces"]) {
    const Eigen::Vector3d n(h[0].get<double>(), h[1].get<double>(), h[2].get<double>());
    EXPECT_NEAR(n.norm(), 1.0, kRoundOff);
    EXPECT_NEAR(h[3].get<double>(), n.cwiseAbs().dot(half), kRoundOff);
  }
  for (const nlohmann::json& v : hull["vertices"]) {
    const Eigen::Vector3d y(v[0].get<double>(), v[1].get<double>(), v[2].get<double>());
    EXPECT_LE((y.cwiseAbs() - half).norm(), kRoundOff);
  }
}

TEST_F(HullCommandTest, OpenMeshFallsBackToItsHullWithAWarning) {
  const Result r =
      RunEcpsim("hull " + Quote(FixturePath("open_box.obj")) + " --json --mass 3", false);
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const nlohmann::json j = nlohmann::json::parse(r.output);
  EXPECT_EQ(j["closed"], false);
  EXPECT_EQ(j["mass_source"], "convex hull (mesh is open)");
  // the hull of the lidless box is the whole box
  EXPECT_NEAR(j["volume"].get<double>(), 6.0, kRoundOff);
  EXPECT_NEAR(j["mass"].get<double>(), 3.0, kRoundOff);
  EXPECT_NEAR(j["center_of_mass"][2].get<double>(), 1.5, kRoundOff);

  const Result merged = RunEcpsim("hull " + Quote(FixturePath("open_box.obj")), true);
  EXPECT_EQ(merged.exit_code, 0);
  EXPECT_THAT(merged.output, HasSubstr("warning"));
  EXPECT_THAT(merged.output, HasSubstr("convex hull (mesh is open)"));
}

// one line on stderr, naming what is wrong, and exit code 1
void ExpectOneLineError(const std::string& args, const std::string& expected) {
  const Result r = RunEcpsim(args, true);
  EXPECT_EQ(r.exit_code, 1) << args;
  EXPECT_THAT(r.output, HasSubstr(expected)) << args;
  ASSERT_FALSE(r.output.empty());
  EXPECT_EQ(r.output.find('\n'), r.output.size() - 1) << r.output;
}

TEST_F(HullCommandTest, BadInputGivesOneLineAndExitCodeOne) {
  const std::string missing = FixturePath("no_such_mesh.obj");
  ExpectOneLineError("hull " + Quote(missing), missing);
  ExpectOneLineError("hull " + Quote(missing), "no such mesh file");
  ExpectOneLineError("hull " + Quote(FixturePath("random_bytes.stl")), "random_bytes.stl");
  ExpectOneLineError("hull " + Quote(FixturePath("flat_tetrahedron.obj")), "flat_tetrahedron.obj");
  ExpectOneLineError("hull " + Quote(FixturePath("box.obj")) + " --scale -1", "--scale = -1");
  ExpectOneLineError("hull " + Quote(FixturePath("box.obj")) + " --mass 0", "--mass = 0");
  ExpectOneLineError("hull " + Quote(FixturePath("box.obj")) + " --density nan", "--density");
}

TEST_F(HullCommandTest, NumericOptionsOutsideTheirRangesAreRejected) {
  const std::string box = "hull " + Quote(FixturePath("box.obj"));
  // coordinates 1e200 times the file's would overflow the mass properties
  ExpectOneLineError(box + " --scale 1e200", "--scale = 1e200: expected a scale in [1e-06, 1e+06]");
  ExpectOneLineError(box + " --scale nan", "--scale = nan: expected a finite scale > 0");
  ExpectOneLineError(box + " --mass 1e151",
                     "--mass = 1e151: expected a mass in [1e-150, 1e+150] kg");
  ExpectOneLineError(box + " --density -inf", "--density = -inf: expected a finite density > 0");
  ExpectOneLineError(box + " --units ft", "--units = ft: expected one of mm, cm, m, in");
  ExpectOneLineError(box + " --units mm --scale 0.01",
                     "--scale = 0.01 and --units = mm (0.001 m per unit) disagree");
}

TEST_F(HullCommandTest, UnitsScaleTheMesh) {
  // the 1 × 2 × 3 box in centimetres: 6 cm³; --scale agreeing with --units is accepted
  for (const char* options : {" --units cm", " --units cm --scale 0.01"}) {
    const Result r = RunEcpsim("hull " + Quote(FixturePath("box.obj")) + " --json" + options, true);
    ASSERT_EQ(r.exit_code, 0) << r.output;
    const nlohmann::json j = nlohmann::json::parse(r.output);
    EXPECT_EQ(j["scale"].get<double>(), 0.01);
    EXPECT_NEAR(j["volume"].get<double>(), 6e-6, 6e-6 * kRoundOff);
  }
}

TEST_F(HullCommandTest, MeshOfImplausibleSizeWarnsAboutItsUnits) {
  // the box read as millimetres scaled by 100: 374 m across
  const Result large = RunEcpsim("hull " + Quote(FixturePath("box.obj")) + " --scale 100", true);
  ASSERT_EQ(large.exit_code, 0) << large.output;
  EXPECT_THAT(large.output,
              HasSubstr(fmt::format("ecpsim: warning: {} is 374 m across; if it is in metres use "
                                    "--units m (or --scale 1)\n",
                                    FixturePath("box.obj"))));
  // the box scaled to 0.47 m across: no warning
  const Result plausible =
      RunEcpsim("hull " + Quote(FixturePath("box.obj")) + " --scale 0.125", true);
  ASSERT_EQ(plausible.exit_code, 0) << plausible.output;
  EXPECT_THAT(plausible.output, ::testing::Not(HasSubstr("warning")));
}

TEST_F(HullCommandTest, MassAndDensityAreMutuallyExclusive) {
  const Result r =
      RunEcpsim("hull " + Quote(FixturePath("box.obj")) + " --mass 1 --density 2", true);
  EXPECT_NE(r.exit_code, 0);
  EXPECT_THAT(r.output, HasSubstr("excludes"));
}

TEST_F(HullCommandTest, TextOutputListsTheHalfSpaces) {
  const Result r = RunEcpsim("hull " + Quote(FixturePath("box_binary.stl")), false);
  ASSERT_EQ(r.exit_code, 0);
  EXPECT_THAT(r.output, HasSubstr("volume           6 m³"));
  EXPECT_THAT(r.output, HasSubstr("mass             6000 kg"));
  EXPECT_THAT(r.output, HasSubstr("n = (0, 0, 1)  d = 1.5 m"));
}

}  // namespace
}  // namespace ecpsim::geometry
