// railvib/soil: the node-stencil stiffness kernel (KernelKind::Stencil).
//
// The element stiffness depends only on the level and the mesh is uniform in x
// and y, so the assembled K_box acting at a node is a 27-point stencil of 3 x 3
// blocks that depends only on the node plane k and on which of the node's 8
// elements lie in the box: in x and y the node is on the box's low face, inside
// or on its high face (3 x 3 classes), in z the levels above and below it are
// in the box or not (known per plane). The kernel keeps these tables per node
// plane (computed in double from boxElementStiffness, then rounded once) and
// computes every node's force as one sum in a fixed order:
//   (K w)_c(n) = sum_o sum_d T[o][c][d] w_d(n + o),  o = (di, dj, dk) in {-1, 0, 1}^3.
// Inside the box the trilinear element's coupling between two components
// vanishes wherever the stencil does not move along both of their directions
// (the 1D "N' N" integrals have a zero centre on a uniform line), so only 153
// of the 243 coefficients are non-zero; at a material interface plane the z
// centre no longer cancels and 177 are. The hot loop applies exactly those,
// vectorised along x in blocks of two native vectors (enough independent
// accumulators to hide the FMA latency), with the tail of a row done as a
// full block whose extra lanes are not stored. Nodes on the box's faces use
// the full 243-coefficient table of their class (missing neighbours read the
// node itself with a zero coefficient, so nothing outside the box is read);
// the nodes on the x faces, which are not contiguous, run along y with gathers.
//
// Each node is written once by one thread: no write conflicts, no barrier, and
// the result does not depend on the thread count.
#include <omp.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <memory>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "railvib/common/force_inline.hpp"
#include "railvib/soil/kernel.hpp"

namespace railvib::soil {

namespace {

// Below this many nodes per step the work does not pay for the OpenMP fork/join: run serially.
constexpr size_t kMinParallelNodes = 20000;

constexpr int kOffsets = 27;
constexpr int kTableSize = kOffsets * 9;  // [o][c][d]

// Which coefficients a line applies. Interior: inside the box, homogeneous plane
// (153 non-zero); Interface: inside the box at a plane between two materials
// (177); Full: all 243 (box faces).
enum class Pattern : uint8_t { Interior, Interface, Full };

constexpr int offsetDi(int o) { return o % 3 - 1; }
constexpr int offsetDj(int o) { return (o / 3) % 3 - 1; }
constexpr int offsetDk(int o) { return o / 9 - 1; }

constexpr bool inPattern(Pattern p, int o, int c, int d) {
  if (p == Pattern::Full || c == d) return true;
  const bool mx = offsetDi(o) != 0, my = offsetDj(o) != 0;
  const bool mz = offsetDk(o) != 0 || p == Pattern::Interface;
  switch (c + d) {
    case 1:  // x-y
      return mx && my;
    case 2:  // x-z
      return mx && mz;
    default:  // y-z
      return my && mz;
  }
}

constexpr int patternSize(Pattern p) {
  int n = 0;
  for (int o = 0; o < kOffsets; ++o) {
    for (int c = 0; c < 3; ++c) {
      for (int d = 0; d < 3; ++d) n += inPattern(p, o, c, d) ? 1 : 0;
    }
  }
  return n;
}
static_assert(patternSize(Pattern::Interior) == 153 && patternSize(Pattern::Interface) == 177 &&
                  patternSize(Pattern::Full) == 243,
              "stencil patterns");

// A run of nodes with one table: along x (stride 1) or along y (stride sx).
struct Line {
  size_t first = 0;
  size_t count = 0;
  ptrdiff_t stride = 1;
  uint32_t table = 0;
  Pattern pattern = Pattern::Full;
};

template <class Real>
struct Tables {
  const Real* coef;              // 243 per table
  const ptrdiff_t* offsets;      // 27 per table: node index offset of each neighbour (0 if its block is zero)
  const ptrdiff_t* max_offsets;  // per table: the largest offset
};

// One native vector of the instruction set (kBytes) and the blocks of kHalves of them that a line is cut into.
template <class Real, size_t kBytes, size_t kHalves = 2>
struct Lanes {
  typedef Real Vec __attribute__((vector_size(kBytes)));
  // The same vector at the alignment of one Real, for unaligned loads and stores (GCC vector types alias
  // their elements). Vectors go by reference: by value they would change the ABI between instruction sets.
  typedef Real UnalignedVec __attribute__((vector_size(kBytes), aligned(sizeof(Real))));
  static constexpr size_t kLanes = kBytes / sizeof(Real);
  static constexpr size_t kBlock = kHalves * kLanes;
  using OneVector = Lanes<Real, kBytes, 1>;
  static RAILVIB_FORCE_INLINE void load(Vec& v, const Real* p) { v = *reinterpret_cast<const UnalignedVec*>(p); }
  static RAILVIB_FORCE_INLINE void store(Real* p, const Vec& v) { *reinterpret_cast<UnalignedVec*>(p) = v; }
};

// The terms of one neighbour o: acc[c][o & 1] += T[o][c][d] w_d(n + o) for the pattern's (c, d).
// Two partial sums per component (even / odd o) halve the FMA dependency chains.
template <Pattern P, int O, class Acc, class Real>
RAILVIB_FORCE_INLINE void neighbourTerms(Acc (&acc)[3][2], const Acc (&v)[3], const Real* t) {
  constexpr int p = O & 1;
  if constexpr (inPattern(P, O, 0, 0)) acc[0][p] += t[O * 9 + 0] * v[0];
  if constexpr (inPattern(P, O, 0, 1)) acc[0][p] += t[O * 9 + 1] * v[1];
  if constexpr (inPattern(P, O, 0, 2)) acc[0][p] += t[O * 9 + 2] * v[2];
  if constexpr (inPattern(P, O, 1, 0)) acc[1][p] += t[O * 9 + 3] * v[0];
  if constexpr (inPattern(P, O, 1, 1)) acc[1][p] += t[O * 9 + 4] * v[1];
  if constexpr (inPattern(P, O, 1, 2)) acc[1][p] += t[O * 9 + 5] * v[2];
  if constexpr (inPattern(P, O, 2, 0)) acc[2][p] += t[O * 9 + 6] * v[0];
  if constexpr (inPattern(P, O, 2, 1)) acc[2][p] += t[O * 9 + 7] * v[1];
  if constexpr (inPattern(P, O, 2, 2)) acc[2][p] += t[O * 9 + 8] * v[2];
}

// Neighbour O of the native vector of nodes from m - off[O].
template <class L, Pattern P, size_t O, class Real>
RAILVIB_FORCE_INLINE void vectorNeighbour(typename L::Vec (&acc)[3][2], const Real* t, const Real* const* w, size_t m) {
  typename L::Vec v[3];
  L::load(v[0], w[0] + m);
  L::load(v[1], w[1] + m);
  L::load(v[2], w[2] + m);
  neighbourTerms<P, static_cast<int>(O)>(acc, v, t);
}

// Neighbour O of the block of nodes from n: each half (native vector) in turn.
template <class L, Pattern P, size_t O, class Real, size_t... H>
RAILVIB_FORCE_INLINE void contiguousNeighbour(typename L::Vec (&acc)[sizeof...(H)][3][2], const Real* t,
                                              const ptrdiff_t* off, const Real* const* w, size_t n,
                                              std::index_sequence<H...>) {
  const size_t m = n + static_cast<size_t>(off[O]);
  (vectorNeighbour<L, P, O>(acc[H], t, w, m + H * L::kLanes), ...);
}

// One block of L::kBlock consecutive nodes from n (lanes >= len are computed but not stored).
template <class L, Pattern P, class Real, size_t... O>
RAILVIB_FORCE_INLINE void contiguousBlock(const Real* __restrict t, const ptrdiff_t* off, const Real* const* w,
                                          Real* const* f, size_t n, size_t len, std::index_sequence<O...>) {
  using Vec = typename L::Vec;
  constexpr size_t kHalves = L::kBlock / L::kLanes;
  Vec acc[kHalves][3][2] = {};
  (contiguousNeighbour<L, P, O>(acc, t, off, w, n, std::make_index_sequence<kHalves>{}), ...);
  for (size_t h = 0; h < kHalves; ++h) {
    for (int c = 0; c < 3; ++c) {
      const Vec k = acc[h][c][0] + acc[h][c][1];
      Real* dst = f[c] + n + h * L::kLanes;
      if (len == L::kBlock) {
        Vec old;
        L::load(old, dst);
        L::store(dst, old - k);
      } else {
        for (size_t l = 0; l < L::kLanes && h * L::kLanes + l < len; ++l) dst[l] -= k[l];
      }
    }
  }
}

// Neighbour O of one node n.
template <class Real, Pattern P, size_t O>
RAILVIB_FORCE_INLINE void nodeNeighbour(Real (&acc)[3][2], const Real* t, const ptrdiff_t* off,
                                        const Real* __restrict w0, const Real* __restrict w1, const Real* __restrict w2,
                                        size_t n) {
  const size_t m = n + static_cast<size_t>(off[O]);
  const Real v[3] = {w0[m], w1[m], w2[m]};
  neighbourTerms<P, static_cast<int>(O)>(acc, v, t);
}

// Nodes first + s stride, s < count, one lane per node (gathers for stride > 1).
template <class Real, Pattern P, size_t... O>
RAILVIB_FORCE_INLINE void stridedLine(const Real* __restrict t, const ptrdiff_t* off, const Real* const* w,
                                      Real* const* f, size_t first, ptrdiff_t stride, size_t count,
                                      std::index_sequence<O...>) {
  const Real* __restrict w0 = w[0];
  const Real* __restrict w1 = w[1];
  const Real* __restrict w2 = w[2];
  Real* __restrict f0 = f[0];
  Real* __restrict f1 = f[1];
  Real* __restrict f2 = f[2];
#pragma omp simd
  for (size_t s = 0; s < count; ++s) {
    const size_t n = first + s * static_cast<size_t>(stride);
    Real acc[3][2] = {};
    (nodeNeighbour<Real, P, O>(acc, t, off, w0, w1, w2, n), ...);
    f0[n] -= acc[0][0] + acc[0][1];
    f1[n] -= acc[1][0] + acc[1][1];
    f2[n] -= acc[2][0] + acc[2][1];
  }
}

template <class L, Pattern P, class Real>
RAILVIB_FORCE_INLINE void runLine(const Line& line, const Tables<Real>& tab, const Real* const* w, Real* const* f,
                                  size_t node_count) {
  const Real* t = tab.coef + static_cast<size_t>(line.table) * kTableSize;
  const ptrdiff_t* off = tab.offsets + static_cast<size_t>(line.table) * kOffsets;
  constexpr auto seq = std::make_index_sequence<kOffsets>{};
  // Lines along y (x faces) are Full; the rare fallback below uses the Full code too: the pattern's zero
  // coefficients are zeros of its table, and one strided instance per precision keeps the code small.
  if (line.stride != 1) {
    stridedLine<Real, Pattern::Full>(t, off, w, f, line.first, line.stride, line.count, seq);
    return;
  }
  constexpr size_t kBlock = L::kBlock;
  const size_t max_off = static_cast<size_t>(tab.max_offsets[line.table]);
  size_t s = 0;
  for (; s + kBlock <= line.count; s += kBlock) contiguousBlock<L, P>(t, off, w, f, line.first + s, kBlock, seq);
  if (s == line.count) return;
  const size_t n = line.first + s, len = line.count - s;
  // The tail as one block (of one vector if that is enough) if its extra lanes still read inside the arrays
  // (all but the last rows of the mesh).
  using L1 = typename L::OneVector;
  if (len <= L1::kBlock && n + L1::kBlock + max_off <= node_count) {
    contiguousBlock<L1, P>(t, off, w, f, n, len, seq);
  } else if (n + kBlock + max_off <= node_count) {
    contiguousBlock<L, P>(t, off, w, f, n, len, seq);
  } else {
    stridedLine<Real, Pattern::Full>(t, off, w, f, n, 1, len, seq);
  }
}

template <class L, class Real>
RAILVIB_FORCE_INLINE void runLinesBody(const Line* lines, size_t n_lines, const Tables<Real>& tab, const Real* const* w,
                                       Real* const* f, size_t node_count) {
  for (size_t q = 0; q < n_lines; ++q) {
    const Line& line = lines[q];
    switch (line.pattern) {
      case Pattern::Interior:
        runLine<L, Pattern::Interior>(line, tab, w, f, node_count);
        break;
      case Pattern::Interface:
        runLine<L, Pattern::Interface>(line, tab, w, f, node_count);
        break;
      case Pattern::Full:
        runLine<L, Pattern::Full>(line, tab, w, f, node_count);
        break;
    }
  }
}

// One entry per instruction set; a block is two native vectors.
template <class Real>
using RunLines = void (*)(const Line*, size_t, const Tables<Real>&, const Real* const*, Real* const*, size_t);

__attribute__((target("avx512f"))) void runLinesAvx512(const Line* l, size_t nl, const Tables<float>& t,
                                                       const float* const* w, float* const* f, size_t nn) {
  runLinesBody<Lanes<float, 64>>(l, nl, t, w, f, nn);
}
__attribute__((target("avx512f"))) void runLinesAvx512(const Line* l, size_t nl, const Tables<double>& t,
                                                       const double* const* w, double* const* f, size_t nn) {
  runLinesBody<Lanes<double, 64>>(l, nl, t, w, f, nn);
}
__attribute__((target("avx2,fma"))) void runLinesAvx2(const Line* l, size_t nl, const Tables<float>& t,
                                                      const float* const* w, float* const* f, size_t nn) {
  runLinesBody<Lanes<float, 32>>(l, nl, t, w, f, nn);
}
__attribute__((target("avx2,fma"))) void runLinesAvx2(const Line* l, size_t nl, const Tables<double>& t,
                                                      const double* const* w, double* const* f, size_t nn) {
  runLinesBody<Lanes<double, 32>>(l, nl, t, w, f, nn);
}
void runLinesDefault(const Line* l, size_t nl, const Tables<float>& t, const float* const* w, float* const* f,
                     size_t nn) {
  runLinesBody<Lanes<float, 16>>(l, nl, t, w, f, nn);
}
void runLinesDefault(const Line* l, size_t nl, const Tables<double>& t, const double* const* w, double* const* f,
                     size_t nn) {
  runLinesBody<Lanes<double, 16>>(l, nl, t, w, f, nn);
}

// The widest instruction set of this CPU, or the one asked for (tests).
template <class Real>
RunLines<Real> selectRunLines(const std::string& instruction_set) {
  const std::vector<std::string> available = stencilInstructionSets();
  const std::string use = instruction_set.empty() ? available.front() : instruction_set;
  if (std::find(available.begin(), available.end(), use) == available.end()) {
    throw std::invalid_argument("stencil kernel: instruction set '" + use + "' not available on this CPU");
  }
  if (use == "avx512f") return static_cast<RunLines<Real>>(runLinesAvx512);
  if (use == "avx2+fma") return static_cast<RunLines<Real>>(runLinesAvx2);
  return static_cast<RunLines<Real>>(runLinesDefault);
}

// Where a node sits in one direction of the box: which of its two neighbouring
// elements (low side, high side) are in the box.
enum FaceClass : int { kInside = 0, kLowFace = 1, kHighFace = 2 };

// The stencil of a node from the element matrices of the levels above and below it (nullptr: not in the box).
std::array<double, kTableSize> nodeStencil(const std::array<double, 576>* above, const std::array<double, 576>* below,
                                           int x_class, int y_class) {
  std::array<double, kTableSize> t{};
  for (int ez = 0; ez < 2; ++ez) {
    const std::array<double, 576>* ke = ez == 0 ? above : below;
    if (!ke) continue;
    for (int ey = 0; ey < 2; ++ey) {
      if ((ey == 0 && y_class == kLowFace) || (ey == 1 && y_class == kHighFace)) continue;
      for (int ex = 0; ex < 2; ++ex) {
        if ((ex == 0 && x_class == kLowFace) || (ex == 1 && x_class == kHighFace)) continue;
        // The node is corner a of element (ex, ey, ez) (0: the element on its low side); corner b is neighbour o.
        const int a = (1 - ex) + 2 * (1 - ey) + 4 * (1 - ez);
        for (int b = 0; b < 8; ++b) {
          const int di = (b & 1) + ex - 1, dj = ((b >> 1) & 1) + ey - 1, dk = ((b >> 2) & 1) + ez - 1;
          const int o = (di + 1) + 3 * (dj + 1) + 9 * (dk + 1);
          for (int c = 0; c < 3; ++c) {
            for (int d = 0; d < 3; ++d) t[o * 9 + c * 3 + d] += (*ke)[(3 * a + c) * 24 + 3 * b + d];
          }
        }
      }
    }
  }
  return t;
}

// The sparsest pattern an inside-the-box table fits; coefficients outside it must be round-off of the element sums.
Pattern insidePattern(std::array<double, kTableSize>& t) {
  double scale = 0.0;
  for (double c : t) scale = std::max(scale, std::abs(c));
  const double negligible = 1e-13 * scale;
  for (Pattern p : {Pattern::Interior, Pattern::Interface}) {
    bool fits = true;
    for (int q = 0; q < kTableSize && fits; ++q) {
      if (!inPattern(p, q / 9, (q % 9) / 3, q % 3)) fits = std::abs(t[q]) <= negligible;
    }
    if (fits) {
      for (int q = 0; q < kTableSize; ++q) {
        if (!inPattern(p, q / 9, (q % 9) / 3, q % 3)) t[q] = 0.0;
      }
      return p;
    }
  }
  return Pattern::Full;
}

// The coefficient tables of a box, shared by the kernel of the whole box and its parts.
template <class Real>
struct StencilTables {
  std::vector<Real> coef;              // 243 per table, 9 tables per node plane of the box
  std::vector<ptrdiff_t> offsets;      // 27 per table
  std::vector<ptrdiff_t> max_offsets;  // per table
};

template <class Real>
class StencilKernel final : public StiffnessKernel<Real> {
 public:
  StencilKernel(const StructuredMesh& mesh, const ElementBox& box, int threads, const std::string& instruction_set)
      : mesh_(mesh), threads_(std::max(1, threads)), run_(selectRunLines<Real>(instruction_set)) {
    auto tables = std::make_shared<StencilTables<Real>>();
    tables_ = tables;
    if (box.empty()) return;
    const size_t sx = mesh.nx + 1, sxy = (mesh.nx + 1) * (mesh.ny + 1);
    std::vector<std::array<double, 576>> ke(box.k1 - box.k0);
    for (size_t k = box.k0; k < box.k1; ++k) {
      const Material& mat = mesh.levelMaterial(k);
      ke[k - box.k0] =
          boxElementStiffness(mesh.hx, mesh.hy, mesh.z[k + 1] - mesh.z[k], mat.lambda(), mat.shearModulus());
    }
    auto faceClass = [](size_t i, size_t lo, size_t hi) {
      return i == lo ? kLowFace : (i == hi ? kHighFace : kInside);
    };
    for (size_t k = box.k0; k <= box.k1; ++k) {
      const std::array<double, 576>* above = k > box.k0 ? &ke[k - 1 - box.k0] : nullptr;
      const std::array<double, 576>* below = k < box.k1 ? &ke[k - box.k0] : nullptr;
      const uint32_t first_table = static_cast<uint32_t>(tables->max_offsets.size());
      Pattern inside = Pattern::Full;
      for (int yc = 0; yc < 3; ++yc) {
        for (int xc = 0; xc < 3; ++xc) {
          std::array<double, kTableSize> t = nodeStencil(above, below, xc, yc);
          if (xc == kInside && yc == kInside && above && below) inside = insidePattern(t);
          addTable(*tables, t, sx, sxy);
        }
      }
      auto table = [&](int yc, int xc) { return first_table + static_cast<uint32_t>(3 * yc + xc); };
      const bool z_inside = above && below;
      for (size_t j = box.j0; j <= box.j1; ++j) {
        const int yc = faceClass(j, box.j0, box.j1);
        const size_t row = mesh.node(0, j, k);
        if (box.i1 > box.i0 + 1) {
          const Pattern p = z_inside && yc == kInside ? inside : Pattern::Full;
          addLine({row + box.i0 + 1, box.i1 - box.i0 - 1, 1, table(yc, kInside), p});
        }
        if (yc != kInside) {  // the box's edges along z: single nodes
          addLine({row + box.i0, 1, 1, table(yc, kLowFace), Pattern::Full});
          addLine({row + box.i1, 1, 1, table(yc, kHighFace), Pattern::Full});
        }
      }
      if (box.j1 > box.j0 + 1) {  // the x faces, along y
        const size_t start = mesh.node(0, box.j0 + 1, k);
        addLine(
            {start + box.i0, box.j1 - box.j0 - 1, static_cast<ptrdiff_t>(sx), table(kInside, kLowFace), Pattern::Full});
        addLine({start + box.i1, box.j1 - box.j0 - 1, static_cast<ptrdiff_t>(sx), table(kInside, kHighFace),
                 Pattern::Full});
      }
    }
  }

  /// A part of `whole`: some of its lines (each node's force is computed by exactly one line, so the parts
  /// together give the whole kernel's result bit for bit); the tables are shared.
  StencilKernel(const StencilKernel& whole, const std::vector<Line>& lines)
      : mesh_(whole.mesh_), threads_(whole.threads_), run_(whole.run_), tables_(whole.tables_) {
    for (const Line& line : lines) addLine(line);
  }

  void apply(const Real* const in[3], Real* const out[3]) const override {
    if (lines_.empty()) return;
    const Tables<Real> tab{tables_->coef.data(), tables_->offsets.data(), tables_->max_offsets.data()};
    const size_t node_count = mesh_.nodeCount();
    const Line* lines = lines_.data();
    const size_t n_lines = lines_.size();
    const double* cost = cost_prefix_.data();
    const RunLines<Real> run = run_;
#pragma omp parallel num_threads(threads_) if (threads_ > 1 && nodes_ >= kMinParallelNodes)
    {
      // Contiguous runs of lines of equal estimated cost (the partition does not change any result).
      const double t = omp_get_thread_num(), nt = omp_get_num_threads(), total = cost[n_lines];
      const size_t q0 = static_cast<size_t>(std::lower_bound(cost, cost + n_lines, total * t / nt) - cost);
      const size_t q1 = static_cast<size_t>(std::lower_bound(cost, cost + n_lines, total * (t + 1) / nt) - cost);
      run(lines + q0, q1 - q0, tab, in, out, node_count);
    }
  }

  double multiplyAddsPerApply() const override { return multiply_adds_; }
  KernelKind kind() const override { return KernelKind::Stencil; }

  const std::vector<Line>& lines() const { return lines_; }
  /// Estimated cost of lines [0, q) (the thread partition's measure).
  double costBefore(size_t q) const { return cost_prefix_.empty() ? 0.0 : cost_prefix_[q]; }

 private:
  static void addTable(StencilTables<Real>& tables, const std::array<double, kTableSize>& t, size_t sx, size_t sxy) {
    ptrdiff_t max_off = 0;
    for (int o = 0; o < kOffsets; ++o) {
      bool zero = true;
      for (int q = 0; q < 9; ++q) zero = zero && t[o * 9 + q] == 0.0;
      // A neighbour outside the box has a zero block: read the node itself instead (never outside the box).
      const ptrdiff_t off =
          zero ? 0 : offsetDi(o) + offsetDj(o) * static_cast<ptrdiff_t>(sx) + offsetDk(o) * static_cast<ptrdiff_t>(sxy);
      tables.offsets.push_back(off);
      max_off = std::max(max_off, off);
    }
    tables.max_offsets.push_back(max_off);
    for (double c : t) tables.coef.push_back(static_cast<Real>(c));
  }

  void addLine(const Line& line) {
    if (line.count == 0) return;
    lines_.push_back(line);
    nodes_ += line.count;
    const double fma = static_cast<double>(line.count) * patternSize(line.pattern);
    multiply_adds_ += fma;
    // Gathers cost about twice a contiguous load: weight the x-face lines for the thread partition.
    if (cost_prefix_.empty()) cost_prefix_.push_back(0.0);
    cost_prefix_.push_back(cost_prefix_.back() + fma * (line.stride == 1 ? 1.0 : 2.0));
  }

  const StructuredMesh& mesh_;
  int threads_;
  RunLines<Real> run_;
  std::shared_ptr<const StencilTables<Real>> tables_;
  std::vector<Line> lines_;          // plane by plane, rows in order
  std::vector<double> cost_prefix_;  // cumulative estimated cost of the lines (size lines + 1)
  size_t nodes_ = 0;                 // nodes the lines compute (each once)
  double multiply_adds_ = 0.0;
};

}  // namespace

std::vector<std::string> stencilInstructionSets() {
  __builtin_cpu_init();
  std::vector<std::string> sets;
  if (__builtin_cpu_supports("avx512f")) sets.push_back("avx512f");
  if (__builtin_cpu_supports("avx2") && __builtin_cpu_supports("fma")) sets.push_back("avx2+fma");
  sets.push_back("sse2");
  return sets;
}

template <class Real>
std::unique_ptr<StiffnessKernel<Real>> makeStencilKernel(const StructuredMesh& mesh, const ElementBox& box, int threads,
                                                         const std::string& instruction_set) {
  return std::make_unique<StencilKernel<Real>>(mesh, box, threads, instruction_set);
}

template <class Real>
SplitKernel<Real> makeSplitStencilKernel(const StructuredMesh& mesh, const ElementBox& box, int threads, bool low_face,
                                         bool high_face, size_t pieces, const std::string& instruction_set) {
  const StencilKernel<Real> whole(mesh, box, threads, instruction_set);
  // A line lies on an x face as a whole (the faces' lines along y and the single nodes of the edges) or not at
  // all (the lines along x stop one node short of the faces).
  const size_t sx = mesh.nx + 1;
  std::vector<Line> faces, rest;
  std::vector<double> rest_cost{0.0};
  for (size_t q = 0; q < whole.lines().size(); ++q) {
    const Line& line = whole.lines()[q];
    const size_t i = line.first % sx;
    if ((low_face && i == 0) || (high_face && i == mesh.nx)) {
      faces.push_back(line);
    } else {
      rest.push_back(line);
      rest_cost.push_back(rest_cost.back() + whole.costBefore(q + 1) - whole.costBefore(q));
    }
  }
  SplitKernel<Real> split;
  if (!faces.empty()) split.faces.push_back(std::make_unique<StencilKernel<Real>>(whole, faces));
  // The rest in runs of lines of equal estimated cost.
  const size_t n = std::max<size_t>(1, std::min(pieces, rest.size()));
  size_t q0 = 0;
  for (size_t p = 0; p < n; ++p) {
    const double target = rest_cost.back() * static_cast<double>(p + 1) / static_cast<double>(n);
    size_t q1 =
        p + 1 == n
            ? rest.size()
            : static_cast<size_t>(std::lower_bound(rest_cost.begin(), rest_cost.end(), target) - rest_cost.begin());
    q1 = std::clamp(q1, q0, rest.size());
    if (q1 > q0) {
      split.rest.push_back(std::make_unique<StencilKernel<Real>>(
          whole,
          std::vector<Line>(rest.begin() + static_cast<ptrdiff_t>(q0), rest.begin() + static_cast<ptrdiff_t>(q1))));
    }
    q0 = q1;
  }
  return split;
}

template SplitKernel<float> makeSplitStencilKernel<float>(const StructuredMesh&, const ElementBox&, int, bool, bool,
                                                          size_t, const std::string&);
template SplitKernel<double> makeSplitStencilKernel<double>(const StructuredMesh&, const ElementBox&, int, bool, bool,
                                                            size_t, const std::string&);

template std::unique_ptr<StiffnessKernel<float>> makeStencilKernel<float>(const StructuredMesh&, const ElementBox&, int,
                                                                          const std::string&);
template std::unique_ptr<StiffnessKernel<double>> makeStencilKernel<double>(const StructuredMesh&, const ElementBox&,
                                                                            int, const std::string&);

}  // namespace railvib::soil
