#include "geometry/weld_vertices.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <vector>

#include "common/errors.h"
#include "geometry/mesh_bounds.h"

namespace ecpsim::geometry {
namespace {

// fraction of the bounding-box diagonal under which two vertices are the same point: files store
// single precision (relative resolution 6e-8), so one corner written twice by a tool that computed
// it twice can differ by a float ulp or two; 1e-7 of the model size is far below any physical
// feature (0.1 µm on a 1 m body)
constexpr double kWeldFraction = 1e-7;

// a cell edge smaller than this many ulps of the largest coordinate cannot separate points, so the
// grid never gets finer than the coordinates themselves (and cell indices stay far inside int64)
constexpr double kMinCellUlps = 16.0 * std::numeric_limits<double>::epsilon();

// the cell edge is this many tolerances, so a point has to look into a neighbour cell along an
// axis only when it lies within one tolerance of that face (1 in 8 per axis: usually one cell is
// probed); with the default tolerance a cell is still far smaller than any edge of the mesh
constexpr double kCellsPerTolerance = 16.0;

// log2 of the entries of the recent-positions cache: 2¹⁴ × 32 B = 512 KiB stays in L2, and a soup
// (STL) repeats each corner within a few hundred triangles of its first use
constexpr int kRecentBits = 14;

struct CellKey {
  std::int64_t i, j, k;
  bool operator==(const CellKey& o) const { return i == o.i && j == o.j && k == o.k; }
};

// splitmix64's finalizer: every input bit affects every output bit, so the low bits used as the
// table index are well mixed even for neighbouring cells
std::uint64_t Mix(std::uint64_t x) {
  x ^= x >> 30;
  x *= 0xBF58476D1CE4E5B9ull;
  x ^= x >> 27;
  x *= 0x94D049BB133111EBull;
  x ^= x >> 31;
  return x;
}

std::uint64_t HashCell(const CellKey& c) {
  return Mix(static_cast<std::uint64_t>(c.i) +
             Mix(static_cast<std::uint64_t>(c.j) + Mix(static_cast<std::uint64_t>(c.k))));
}

// open-addressing map cell → first representative vertex in that cell (representatives of one
// cell are chained through a separate `next` array); std::unordered_map is several times slower
// at 10⁶ entries. Linear probing, kept at most half full.
class CellTable {
 public:
  explicit CellTable(std::size_t expected) { Allocate(expected); }

  // head of the representative chain in `cell`, or -1
  int Find(const CellKey& cell) const {
    for (std::size_t s = HashCell(cell) & mask_;; s = (s + 1) & mask_) {
      if (slots_[s].head < 0) return -1;
      if (slots_[s].key == cell) return slots_[s].head;
    }
  }

  // makes `head` the chain head of `cell` (which must be ≥ 0); returns the previous head or -1
  int Exchange(const CellKey& cell, int head) {
    if (2 * (size_ + 1) > slots_.size()) Grow();
    Slot& slot = Probe(cell);
    const int previous = slot.head;
    if (previous < 0) {
      slot.key = cell;
      ++size_;
    }
    slot.head = head;
    return previous;
  }

 private:
  struct Slot {
    CellKey key{0, 0, 0};
    int head = -1;  // -1: empty slot
  };

  void Allocate(std::size_t expected) {
    std::size_t capacity = 1024;
    while (capacity < 2 * expected) capacity *= 2;
    slots_.assign(capacity, Slot{});
    mask_ = capacity - 1;
    size_ = 0;
  }

  Slot& Probe(const CellKey& cell) {
    for (std::size_t s = HashCell(cell) & mask_;; s = (s + 1) & mask_) {
      if (slots_[s].head < 0 || slots_[s].key == cell) return slots_[s];
    }
  }

  void Grow() {
    std::vector<Slot> old;
    old.swap(slots_);
    Allocate(old.size());
    for (const Slot& slot : old) {
      if (slot.head >= 0) {
        Probe(slot.key) = slot;
        ++size_;
      }
    }
  }

  std::vector<Slot> slots_;
  std::size_t mask_ = 0;
  std::size_t size_ = 0;
};

}  // namespace

double DefaultWeldTolerance(const TriangleMesh& mesh) {
  return kWeldFraction * ComputeMeshBounds(mesh.vertices).diagonal;
}

TriangleMesh WeldVertices(const TriangleMesh& mesh, double tolerance) {
  ECPSIM_DEMAND(std::isfinite(tolerance) && tolerance >= 0.0);
  const int n = static_cast<int>(mesh.vertices.size());

  // cell edge: kCellsPerTolerance tolerances, but never below the coordinates' own resolution
  double max_abs = 0.0;
  for (const Eigen::Vector3d& v : mesh.vertices)
    max_abs = std::max(max_abs, v.cwiseAbs().maxCoeff());
  const double cell = std::max(
      {kCellsPerTolerance * tolerance, kMinCellUlps * max_abs, std::numeric_limits<double>::min()});
  const double inv_cell = 1.0 / cell;
  const double tolerance_sq = tolerance * tolerance;

  TriangleMesh welded;
  std::vector<int> remap(n, -1);
  std::vector<int> next;  // next representative in the same cell, -1 ends the chain
  // sized for a soup (each vertex ~6 times); the table grows when a mesh has more
  CellTable table(static_cast<std::size_t>(n) / 4);
  welded.vertices.reserve(n / 4);
  next.reserve(n / 4);

  // first representative of `cell` within the tolerance of `p`, or -1
  auto find_in_cell = [&](const CellKey& c, const Eigen::Vector3d& p) {
    for (int r = table.Find(c); r >= 0; r = next[r]) {
      const Eigen::Vector3d& q = welded.vertices[r];
      if (q == p || (tolerance > 0.0 && (q - p).squaredNorm() <= tolerance_sq)) return r;
    }
    return -1;
  };

  auto cell_of = [inv_cell](const Eigen::Vector3d& p) {
    const Eigen::Vector3d scaled = p * inv_cell;
    return CellKey{static_cast<std::int64_t>(std::floor(scaled.x())),
                   static_cast<std::int64_t>(std::floor(scaled.y())),
                   static_cast<std::int64_t>(std::floor(scaled.z()))};
  };

  // a direct-mapped cache of recently seen exact positions: the cell table is far larger than
  // the CPU caches, and skipping it for repeated corners welds a 1M-triangle STL soup ~1.5× faster
  struct Recent {
    Eigen::Vector3d position;
    int rep = -1;
  };
  std::vector<Recent> recent(std::size_t{1} << kRecentBits);
  auto recent_slot = [&recent](const Eigen::Vector3d& p) -> Recent& {
    std::uint64_t bits[3];
    std::memcpy(bits, p.data(), sizeof(bits));
    return recent[Mix(bits[0] + Mix(bits[1] + Mix(bits[2]))) >> (64 - kRecentBits)];
  };

  for (int v = 0; v < n; ++v) {
    const Eigen::Vector3d& p = mesh.vertices[v];
    ECPSIM_DEMAND(p.allFinite());
    Recent& seen = recent_slot(p);
    if (seen.rep >= 0 && seen.position == p) {
      remap[v] = seen.rep;
      continue;
    }
    const CellKey home = cell_of(p);
    int rep = find_in_cell(home, p);

    // neighbour cells only along the axes where p lies within one tolerance of a cell face
    if (rep < 0 && tolerance > 0.0) {
      int step[3];
      const std::int64_t home_index[3] = {home.i, home.j, home.k};
      for (int a = 0; a < 3; ++a) {
        const double offset = p[a] - static_cast<double>(home_index[a]) * cell;
        step[a] = offset <= tolerance ? -1 : (cell - offset <= tolerance ? 1 : 0);
      }
      for (int mask = 1; mask < 8 && rep < 0; ++mask) {
        CellKey c = home;
        bool valid = true;
        for (int a = 0; a < 3; ++a) {
          if (!(mask & (1 << a))) continue;
          if (step[a] == 0) valid = false;
        }
        if (!valid) continue;
        if (mask & 1) c.i += step[0];
        if (mask & 2) c.j += step[1];
        if (mask & 4) c.k += step[2];
        rep = find_in_cell(c, p);
      }
    }

    // a new representative heads its cell's chain
    if (rep < 0) {
      rep = static_cast<int>(welded.vertices.size());
      welded.vertices.push_back(p);
      next.push_back(table.Exchange(home, rep));
    }
    remap[v] = rep;
    seen = Recent{p, rep};
  }

  // re-index triangles, dropping those that collapsed to a segment or a point
  welded.triangles.reserve(mesh.triangles.size());
  for (const Eigen::Vector3i& t : mesh.triangles) {
    for (int c = 0; c < 3; ++c) ECPSIM_DEMAND(t[c] >= 0 && t[c] < n);
    const Eigen::Vector3i w(remap[t[0]], remap[t[1]], remap[t[2]]);
    if (w[0] == w[1] || w[1] == w[2] || w[2] == w[0]) continue;
    welded.triangles.push_back(w);
  }
  return welded;
}

}  // namespace ecpsim::geometry
