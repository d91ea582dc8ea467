// Writes the table of tests/engine/trajectory_hash_test.cpp to standard output:
// `ecpsim_trajectory_hashes SCENES_DIR` (scripts/bless_trajectory_hashes.sh writes the file).

#include <exception>
#include <iostream>

#include "tests/engine/trajectory_hash.h"

int main(int argc, char** argv) {
  if (argc != 2) {
    std::cerr << "usage: ecpsim_trajectory_hashes SCENES_DIR\n";
    return 2;
  }
  try {
    std::cout << "# scene model step hash: the state's bits after each step "
                 "(tests/engine/trajectory_hash.h)\n"
              << "# written by scripts/bless_trajectory_hashes.sh; do not edit by hand\n";
    for (const auto& c : ecpsim::engine::testing::AllTrajectoryCases(argv[1])) {
      for (const auto& line : ecpsim::engine::testing::TrajectoryRecord(argv[1], c)) {
        std::cout << line << '\n';
      }
    }
  } catch (const std::exception& e) {
    std::cerr << "ecpsim_trajectory_hashes: " << e.what() << '\n';
    return 1;
  }
  return std::cout ? 0 : 1;
}
