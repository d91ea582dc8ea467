#pragma once
// Random numbers that are the same on every platform for a given seed: the generated meshes and
// poses of the drop sweep are named by (kind, seed) and must regenerate bit for bit.

#include <cstdint>
#include <random>
#include <string>

#include <Eigen/Core>
#include <Eigen/Geometry>

namespace ecpsim::evaluation {

/// A 64-bit Mersenne twister (its output is fixed by the C++ standard) with the conversions to
/// reals done here, not by std::uniform_real_distribution (whose algorithm is the library's).
class SeededRandom {
 public:
  /// Independent streams for the same seed: e.g. stream 0 for a case's mesh, 1 for its pose.
  SeededRandom(std::uint64_t seed, std::uint64_t stream);

  /// Uniform in [lo, hi).
  double Uniform(double lo, double hi);
  /// log-uniform in [lo, hi), 0 < lo < hi.
  double LogUniform(double lo, double hi);
  /// Uniform integer in [lo, hi] (inclusive).
  int Integer(int lo, int hi);
  /// Uniform on the unit sphere.
  Eigen::Vector3d UnitVector();
  /// Uniform in the unit ball.
  Eigen::Vector3d InBall();
  /// Uniform over rotations (Shoemake's method), unit quaternion.
  Eigen::Quaterniond Rotation();

 private:
  std::mt19937_64 engine_;
};

/// A stable 64-bit hash of `text` (FNV-1a), to seed streams by a file's name.
std::uint64_t StableHash(const std::string& text);

}  // namespace ecpsim::evaluation
