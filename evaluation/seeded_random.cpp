#include "evaluation/seeded_random.h"

#include <algorithm>
#include <cmath>

#include "common/errors.h"
#include "common/fnv1a.h"
#include "common/split_mix64.h"

namespace ecpsim::evaluation {
namespace {

constexpr double kPi = 3.14159265358979323846;

}  // namespace

SeededRandom::SeededRandom(std::uint64_t seed, std::uint64_t stream)
    : engine_(SplitMix64(SplitMix64(seed) ^ stream)) {}

double SeededRandom::Uniform(double lo, double hi) {
  // the top 53 bits as a double in [0, 1)
  const double unit = static_cast<double>(engine_() >> 11) * 0x1.0p-53;
  return lo + (hi - lo) * unit;
}

double SeededRandom::LogUniform(double lo, double hi) {
  ECPSIM_DEMAND(lo > 0 && hi > lo);
  return std::exp(Uniform(std::log(lo), std::log(hi)));
}

int SeededRandom::Integer(int lo, int hi) {
  ECPSIM_DEMAND(hi >= lo);
  const auto span = static_cast<std::uint64_t>(hi - lo) + 1;
  // the modulo bias is below 2^-50 for any int range: irrelevant here
  return lo + static_cast<int>(engine_() % span);
}

Eigen::Vector3d SeededRandom::UnitVector() {
  const double z = Uniform(-1, 1);
  const double phi = Uniform(0, 2 * kPi);
  const double r = std::sqrt(std::max(0.0, 1 - z * z));
  return {r * std::cos(phi), r * std::sin(phi), z};
}

Eigen::Vector3d SeededRandom::InBall() { return std::cbrt(Uniform(0, 1)) * UnitVector(); }

Eigen::Quaterniond SeededRandom::Rotation() {
  const double u1 = Uniform(0, 1), u2 = Uniform(0, 2 * kPi), u3 = Uniform(0, 2 * kPi);
  const double a = std::sqrt(1 - u1), b = std::sqrt(u1);
  return Eigen::Quaterniond(b * std::cos(u3), a * std::sin(u2), a * std::cos(u2), b * std::sin(u3));
}

std::uint64_t StableHash(const std::string& text) {
  Fnv1a hash;
  hash.Add(text.data(), text.size());
  return hash.Value();
}

}  // namespace ecpsim::evaluation
