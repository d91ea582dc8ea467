// The state record of checkpoints and pickles: every value back to the same bits, whatever warm
// start a contact holds, and a malformed record refused naming its key.

#include "engine/report/state_record.h"

#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <string>

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include "common/errors.h"
#include "engine/models/hull_warm_start.h"
#include "engine/models/multipatch_warm_start.h"

namespace ecpsim::engine {
namespace {

using ::testing::HasSubstr;

// a state with a body, and contacts holding each kind of warm start; values with every bit used
State MixedState() {
  State state;
  state.t = 0.1 + 0.2;  // not 0.3: its last bits must survive
  state.steps = 30;
  BodyState& body = state.bodies.emplace_back();
  body.p_WB = Eigen::Vector3d(1.0 / 3, -2e-300, 7e300);
  body.Q_WB = Eigen::Quaterniond(0.5, -0.5, 0.5, std::sqrt(0.25));
  body.v_WB = Eigen::Vector3d(std::nextafter(1.0, 2.0), -0.0, 1e-320);  // a subnormal
  body.w_WB = Eigen::Vector3d(3, std::numeric_limits<double>::infinity(), 0.1);
  ContactState& hull = state.contacts.emplace_back();
  hull.a1 = Eigen::Vector3d(0.1, 0.2, 0.3);
  hull.p_n = 0.196;
  hull.sigma = std::numeric_limits<double>::quiet_NaN();
  HullWarmStart& warm = hull.warm_start.Emplace<HullWarmStart>();
  warm.s = 1e-17;
  warm.l_g = Eigen::VectorXd::Constant(1, 1.0);
  warm.window = {0, 3, 7};
  warm.l = Eigen::Vector3d(0.25, 1e-9, 0.75);
  warm.trend.h = 0.01;
  warm.trend.steps = 2;
  warm.trend.first.setConstant(1.0 / 7);
  warm.trend.second.setConstant(-1.0 / 9);
  ContactState& parts = state.contacts.emplace_back();
  parts.warm_start.Set(MultiPatchWarmStart{{Eigen::Vector2d(1, 2), Eigen::Vector3d(3, 4, 5)}});
  state.contacts.emplace_back();  // no warm start
  return state;
}

// the bits of a double, so that NaN and −0 compare as written
std::uint64_t Bits(double x) {
  std::uint64_t bits;
  std::memcpy(&bits, &x, sizeof bits);
  return bits;
}

TEST(StateRecordTest, EveryValueComesBackBitForBit) {
  const State state = MixedState();
  const State back = StateFromRecord(nlohmann::json::parse(StateRecord(state).dump()), "state");
  EXPECT_EQ(Bits(back.t), Bits(state.t));
  EXPECT_EQ(back.steps, state.steps);
  ASSERT_EQ(back.bodies.size(), 1u);
  for (int i = 0; i < 3; ++i) {
    EXPECT_EQ(Bits(back.bodies[0].p_WB[i]), Bits(state.bodies[0].p_WB[i]));
    EXPECT_EQ(Bits(back.bodies[0].v_WB[i]), Bits(state.bodies[0].v_WB[i]));
    EXPECT_EQ(Bits(back.bodies[0].w_WB[i]), Bits(state.bodies[0].w_WB[i]));
  }
  EXPECT_EQ(back.bodies[0].Q_WB.coeffs(), state.bodies[0].Q_WB.coeffs());
  ASSERT_EQ(back.contacts.size(), 3u);
  EXPECT_EQ(back.contacts[0].a1, state.contacts[0].a1);
  EXPECT_EQ(Bits(back.contacts[0].sigma), Bits(state.contacts[0].sigma));
  const auto* warm = back.contacts[0].warm_start.Get<HullWarmStart>();
  ASSERT_NE(warm, nullptr);
  const auto& expected = (*state.contacts[0].warm_start.Get<HullWarmStart>());
  EXPECT_EQ(warm->s, expected.s);
  EXPECT_EQ(warm->window, expected.window);
  EXPECT_EQ(warm->l, expected.l);
  EXPECT_EQ(warm->trend.steps, 2);
  EXPECT_EQ(warm->trend.first, expected.trend.first);
  EXPECT_EQ(warm->trend.second, expected.trend.second);
  const auto* parts = back.contacts[1].warm_start.Get<MultiPatchWarmStart>();
  ASSERT_NE(parts, nullptr);
  ASSERT_EQ(parts->parts.size(), 2u);
  EXPECT_EQ(parts->parts[1], Eigen::Vector3d(3, 4, 5));
  EXPECT_TRUE(back.contacts[2].warm_start.empty());
  // and the record of the state read back is the same text
  EXPECT_EQ(StateRecord(back).dump(), StateRecord(state).dump());
}

TEST(StateRecordTest, AMalformedRecordIsRefusedNamingItsKey) {
  const nlohmann::json record = StateRecord(MixedState());
  nlohmann::json short_vector = record;
  short_vector["bodies"][0]["v_WB"].erase(2);
  EXPECT_THAT([&] { StateFromRecord(short_vector, "state"); },
              ::testing::ThrowsMessage<InputError>(
                  HasSubstr("state.bodies[0].v_WB: expected a list of 3 hexadecimal floats")));
  nlohmann::json words = record;
  words["t"] = "soon";
  EXPECT_THAT([&] { StateFromRecord(words, "state"); },
              ::testing::ThrowsMessage<InputError>(
                  HasSubstr("state.t = \"soon\": expected a hexadecimal float")));
  nlohmann::json multipliers = record;
  multipliers["contacts"][0]["warm_start"]["l"].erase(0);  // fewer than its window's faces
  EXPECT_THAT([&] { StateFromRecord(multipliers, "state"); },
              ::testing::ThrowsMessage<InputError>(HasSubstr(
                  "state.contacts[0].warm_start.l: expected a list of 3 hexadecimal floats")));
  nlohmann::json model = record;
  model["contacts"][1]["warm_start"]["model"] = "nosuch";
  EXPECT_THAT([&] { StateFromRecord(model, "state"); },
              ::testing::ThrowsMessage<InputError>(
                  HasSubstr("state.contacts[1].warm_start.model = \"nosuch\": expected \"hull\" or "
                            "\"multipatch\"")));
  nlohmann::json missing = record;
  missing.erase("contacts");
  EXPECT_THAT([&] { StateFromRecord(missing, "state"); },
              ::testing::ThrowsMessage<InputError>(HasSubstr("state: ")));
}

}  // namespace
}  // namespace ecpsim::engine
