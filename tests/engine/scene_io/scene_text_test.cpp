// LoadSceneText: the scene format given as text no file holds (the Python module's dicts), read by
// the file's loader and checks, its messages naming the key path instead of a line:col.

#include <filesystem>
#include <fstream>
#include <string>

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include "common/errors.h"
#include "engine/scene_io/scene_yaml.h"

namespace ecpsim::engine {
namespace {

namespace fs = std::filesystem;
using ::testing::AllOf;
using ::testing::HasSubstr;
using ::testing::Not;
using ::testing::StartsWith;

// a box on the ground and a box above it, in the flow style the Python module writes
constexpr const char* kTwoBoxes =
    R"({"duration": 1, "h": 0.01, "ground": {"friction": {"mu": 0.4, "e_r": 0.05}},
        "bodies": [{"name": "low", "shape": {"box": {"size": [0.2, 0.2, 0.1]}}, "mass": 2,
                    "position": [0, 0, 0.05]},
                   {"name": "high", "mesh": "cube.obj", "mass": 1, "position": [0, 0, 1]}]})";

class SceneTextTest : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() /
           ("ecpsim_scene_text_" +
            std::string(::testing::UnitTest::GetInstance()->current_test_info()->name()));
    fs::create_directories(dir_);
    // a 0.1 m cube about its centre
    std::ofstream(dir_ / "cube.obj") << "v -0.05 -0.05 -0.05\nv 0.05 -0.05 -0.05\n"
                                        "v 0.05 0.05 -0.05\nv -0.05 0.05 -0.05\n"
                                        "v -0.05 -0.05 0.05\nv 0.05 -0.05 0.05\n"
                                        "v 0.05 0.05 0.05\nv -0.05 0.05 0.05\n"
                                        "f 1 4 3\nf 1 3 2\nf 5 6 7\nf 5 7 8\nf 1 2 6\nf 1 6 5\n"
                                        "f 2 3 7\nf 2 7 6\nf 3 4 8\nf 3 8 7\nf 4 1 5\nf 4 5 8\n";
    std::ofstream(dir_ / "scene.yaml") << kTwoBoxes;
  }
  void TearDown() override { fs::remove_all(dir_); }

  fs::path dir_;
};

TEST_F(SceneTextTest, ReadsAsTheSameTextInAFile) {
  const LoadedScene text = LoadSceneText(kTwoBoxes, "dict", dir_.string(), {"bodies.1.mass=3"});
  const LoadedScene file = LoadScene((dir_ / "scene.yaml").string(), {"bodies.1.mass=3"});
  ASSERT_EQ(text.scene.bodies.size(), file.scene.bodies.size());
  for (size_t b = 0; b < file.scene.bodies.size(); ++b) {
    EXPECT_EQ(text.scene.bodies[b].name, file.scene.bodies[b].name);
    EXPECT_EQ(text.scene.bodies[b].mass, file.scene.bodies[b].mass);
    EXPECT_EQ(text.scene.bodies[b].inertia, file.scene.bodies[b].inertia);
    EXPECT_EQ(text.scene.bodies[b].p0, file.scene.bodies[b].p0);
  }
  EXPECT_EQ(text.scene.bodies[1].mass, 3);
  EXPECT_EQ(text.scene.contacts.size(), file.scene.contacts.size());
  EXPECT_EQ(text.scene.source, "dict");
}

TEST_F(SceneTextTest, MessagesNameTheSourceAndKeyWithoutALine) {
  // a reader's error, a --set's, ValidateScene's (an overlap), YAML's
  const auto message = [&](const std::string& text, const std::vector<std::string>& overrides) {
    try {
      LoadSceneText(text, "dict", dir_.string(), overrides);
    } catch (const InputError& e) {
      return std::string(e.what());
    }
    return std::string("(no error)");
  };
  std::string bad = kTwoBoxes;
  bad.replace(bad.find("\"mass\": 2"), 9, "\"mass\": -2");
  EXPECT_THAT(message(bad, {}), StartsWith("dict: bodies[0].mass = -2: expected a finite mass"));
  EXPECT_THAT(message(kTwoBoxes, {"bodies.1.mass=[1]"}),
              StartsWith("dict: --set bodies.1.mass=[1]: bodies[1].mass = [1]: expected"));
  EXPECT_THAT(message(kTwoBoxes, {"bodies.1.position=[0, 0, 0.1]"}),
              StartsWith("dict: bodies[0].position = [0, 0, 0.05]: expected an initial pose of "
                         "body \"low\" apart from body \"high\""));
  std::string sunk = kTwoBoxes;
  sunk.replace(sunk.find("[0, 0, 0.05]"), 12, "[0, 0, -0.5]");
  EXPECT_THAT(message(sunk, {}), AllOf(StartsWith("dict: bodies[0].position = "),
                                       HasSubstr("inside"), Not(HasSubstr("dict:1:"))));
  EXPECT_THAT(message("{duration: [", {}), StartsWith("dict: not a YAML tree"));
  EXPECT_THAT(message("", {}), StartsWith("dict: the scene is empty"));
}

}  // namespace
}  // namespace ecpsim::engine
