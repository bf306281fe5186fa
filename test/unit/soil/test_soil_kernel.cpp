// The stiffness kernels (kernel.hpp) against a naive assembled product in double.
//
// Round-off bound. Each kernel output is f_n - sum_t c_t w_t, a sum of m
// products with coefficients c_t rounded once to the working precision (unit
// roundoff u: 2^-24 float, 2^-53 double) and w_t exact in it. Summed in any
// order (FMA or not), |computed - exact| <= (m + 2) u sum_t |c_t w_t| to first
// order: (m - 1) additions plus the final subtraction each err by at most u of
// a partial sum bounded by sum |c_t w_t| + |f_n|, and the coefficient rounding
// adds u |c_t w_t|. The stencil sums at most 81 terms per output (27 nodes x 3
// components) into 2 partial sums, the element kernel 8 element dot products
// of 24 terms: m = 81 and m = 8 x 24 = 192 (conservative: each element product
// is one chain, then the 8 are added). So per node
//   |f_kernel - f_exact| <= (m + 2) u (|K| |w| + |f_n|)_n,
// with |K| |w| the product of the absolute values, computed here in double.
// A wrong, missing or doubled coefficient moves f by O(|K| |w|), 1e4 x more
// than the float bound.
#include <gtest/gtest.h>
#include <omp.h>

#include <cmath>
#include <cstring>
#include <random>
#include <string>
#include <vector>

#include "railvib/soil/kernel.hpp"
#include "railvib/soil/mesh.hpp"

using namespace railvib::soil;

namespace {

// Graded, three materials (an interface inside the mesh, one at a level boundary,
// thin and thick levels), rows long enough for full vector blocks (x) and tails.
StructuredMesh gradedLayeredMesh(size_t nx, size_t ny) {
  const Material l1{61.0e6, 1876.0, 0.13}, l2{84.0e6, 1876.0, 0.13}, hs{465.0e6, 1992.0, 0.48};
  const std::vector<double> dz{0.2, 0.2, 0.25, 0.3, 0.3, 0.5, 0.7, 0.7};
  const std::vector<Material> mats{l1, l1, l1, l2, l2, hs, hs, hs};
  std::vector<double> z{0.0};
  for (double h : dz) z.push_back(z.back() + h);
  return buildUniformMesh(nx, ny, 0.29, 0.31, z, mats, -3.0, -2.0);
}

struct Fields {
  std::vector<double> w[3], f[3];
};

Fields randomFields(const StructuredMesh& m, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> dist(-1.0f, 1.0f);  // float values: exact in both precisions
  Fields fl;
  for (int c = 0; c < 3; ++c) {
    fl.w[c].resize(m.nodeCount());
    fl.f[c].resize(m.nodeCount());
    for (auto& x : fl.w[c]) x = dist(rng);
    for (auto& x : fl.f[c]) x = 1e6 * dist(rng);  // the kernel adds to what is there
  }
  return fl;
}

// f - K_box w (exact to double round-off) and |f| + |K_box| |w|, element by element.
void naiveReference(const StructuredMesh& m, const ElementBox& box, const Fields& in, std::vector<double> f[3],
                    std::vector<double> bound[3]) {
  for (int c = 0; c < 3; ++c) {
    f[c] = in.f[c];
    bound[c].resize(m.nodeCount());
    for (size_t q = 0; q < m.nodeCount(); ++q) bound[c][q] = std::abs(in.f[c][q]);
  }
  for (size_t k = box.k0; k < box.k1; ++k) {
    const Material& mat = m.levelMaterial(k);
    const auto ke = boxElementStiffness(m.hx, m.hy, m.z[k + 1] - m.z[k], mat.lambda(), mat.shearModulus());
    for (size_t j = box.j0; j < box.j1; ++j) {
      for (size_t i = box.i0; i < box.i1; ++i) {
        size_t node[8];
        for (size_t a = 0; a < 8; ++a) node[a] = m.node(i + (a & 1), j + ((a >> 1) & 1), k + ((a >> 2) & 1));
        for (size_t r = 0; r < 24; ++r) {
          for (size_t q = 0; q < 24; ++q) {
            const double t = ke[r * 24 + q] * in.w[q % 3][node[q / 3]];
            f[r % 3][node[r / 3]] -= t;
            bound[r % 3][node[r / 3]] += std::abs(t);
          }
        }
      }
    }
  }
}

// instruction_set: "" = the factory's choice, else a stencil code path (stencilInstructionSets()).
template <class Real>
void applyKernel(KernelKind kind, const StructuredMesh& m, const ElementBox& box, int threads, const Fields& in,
                 std::vector<Real> out[3], const std::string& instruction_set = "") {
  std::vector<Real> w[3];
  for (int c = 0; c < 3; ++c) {
    w[c].assign(in.w[c].begin(), in.w[c].end());
    out[c].assign(in.f[c].begin(), in.f[c].end());
  }
  const auto kernel = instruction_set.empty() ? makeStiffnessKernel<Real>(kind, m, box, threads)
                                              : makeStencilKernel<Real>(m, box, threads, instruction_set);
  ASSERT_EQ(kernel->kind(), kind);
  const Real* pin[3] = {w[0].data(), w[1].data(), w[2].data()};
  Real* pout[3] = {out[0].data(), out[1].data(), out[2].data()};
  kernel->apply(pin, pout);
}

bool inBoxNodes(const StructuredMesh& m, const ElementBox& b, size_t q) {
  const size_t i = q % (m.nx + 1), j = (q / (m.nx + 1)) % (m.ny + 1), k = q / ((m.nx + 1) * (m.ny + 1));
  return i >= b.i0 && i <= b.i1 && j >= b.j0 && j <= b.j1 && k >= b.k0 && k <= b.k1;
}

// Largest error / bound over the nodes (must be <= 1), and the largest error relative to max |K w|.
template <class Real>
void checkKernel(KernelKind kind, const StructuredMesh& m, const ElementBox& box, const char* what,
                 const std::string& instruction_set = "") {
  const Fields in = randomFields(m, 11);
  std::vector<double> ref[3], bound[3];
  naiveReference(m, box, in, ref, bound);
  std::vector<Real> out[3];
  applyKernel<Real>(kind, m, box, 1, in, out, instruction_set);
  const double u = std::ldexp(1.0, std::is_same<Real, float>::value ? -24 : -53);
  const double terms = kind == KernelKind::Stencil ? 81.0 : 192.0;
  double worst = 0.0, max_err = 0.0, max_kw = 0.0;
  size_t changed_outside = 0;
  for (int c = 0; c < 3; ++c) {
    for (size_t q = 0; q < m.nodeCount(); ++q) {
      const double err = std::abs(static_cast<double>(out[c][q]) - ref[c][q]);
      if (!inBoxNodes(m, box, q)) {
        // Outside the box's nodes nothing may change, not even by round-off.
        if (out[c][q] != static_cast<Real>(in.f[c][q])) ++changed_outside;
        continue;
      }
      worst = std::max(worst, err / ((terms + 2.0) * u * bound[c][q]));
      max_err = std::max(max_err, err);
      max_kw = std::max(max_kw, std::abs(ref[c][q] - in.f[c][q]));
    }
  }
  EXPECT_EQ(changed_outside, 0u) << what;
  EXPECT_LE(worst, 1.0) << what << ": error above the round-off bound";
  EXPECT_GT(max_kw, 0.0) << what;
  std::printf("%-8s %-8s %-6s %-34s error / bound %.3f, max error / max |K w| %.2e\n", kernelName(kind).c_str(),
              instruction_set.c_str(), std::is_same<Real, float>::value ? "float" : "double", what, worst,
              max_err / max_kw);
}

struct NamedBox {
  ElementBox box;
  const char* name;
};

// The whole mesh and boxes that cut it in x, y and depth, touch some mesh faces, or are one element thick.
std::vector<NamedBox> testBoxes(const StructuredMesh& m) {
  return {
      {ElementBox::all(m), "whole mesh"},
      {{3, m.nx - 4, 1, m.ny - 2, 1, m.nz - 2}, "inside, cuts x, y and depth"},
      {{0, m.nx - 7, 2, m.ny, 0, 5}, "x_min, y_max faces, cut at depth"},
      {{5, m.nx, 0, 3, 3, m.nz}, "x_max, y_min, bottom faces"},
      {{m.nx - 3, m.nx, m.ny - 2, m.ny, m.nz - 3, m.nz}, "last corner (array end)"},
      {{4, 5, 1, m.ny - 1, 2, 6}, "one element thick in x"},
      {{2, m.nx - 2, 3, 4, 0, m.nz}, "one element thick in y"},
      {{1, m.nx, 1, m.ny - 1, 4, 5}, "one element thick in depth"},
      {{7, 8, 2, 3, 5, 6}, "one element"},
  };
}

}  // namespace

// Every code path of the stencil kernel this CPU runs (AVX-512 blocks are 32 floats, AVX2 16, SSE2 8: rows
// of 74 inner nodes give full blocks and tails of every size class).
TEST(SoilKernel, StencilAndElementMatchTheAssembledProductOnBoxes) {
  const StructuredMesh m = gradedLayeredMesh(75, 7);
  for (const NamedBox& b : testBoxes(m)) {
    checkKernel<float>(KernelKind::Element, m, b.box, b.name);
    checkKernel<double>(KernelKind::Element, m, b.box, b.name);
    for (const std::string& isa : stencilInstructionSets()) {
      checkKernel<float>(KernelKind::Stencil, m, b.box, b.name, isa);
      checkKernel<double>(KernelKind::Stencil, m, b.box, b.name, isa);
    }
  }
}

// Short rows (shorter than one vector block) and a single row in y.
TEST(SoilKernel, StencilOnNarrowMeshes) {
  for (size_t nx : {1u, 2u, 5u, 17u, 40u}) {
    const StructuredMesh m = gradedLayeredMesh(nx, nx == 17 ? 1 : 3);
    for (const std::string& isa : stencilInstructionSets()) {
      checkKernel<float>(KernelKind::Stencil, m, ElementBox::all(m), "narrow mesh", isa);
      checkKernel<double>(KernelKind::Stencil, m, ElementBox::all(m), "narrow mesh", isa);
    }
  }
}

// The stencil against the element kernel directly: both within their bounds of the exact product, so within the
// sum of the two; double to ~1e-14 of max |K w|.
TEST(SoilKernel, StencilEqualsElementKernelToRoundOff) {
  const StructuredMesh m = gradedLayeredMesh(75, 7);
  for (const NamedBox& b : testBoxes(m)) {
    const Fields in = randomFields(m, 5);
    std::vector<double> e[3], s[3];
    applyKernel<double>(KernelKind::Element, m, b.box, 1, in, e);
    applyKernel<double>(KernelKind::Stencil, m, b.box, 1, in, s);
    double max_diff = 0.0, max_kw = 0.0;
    for (int c = 0; c < 3; ++c) {
      for (size_t q = 0; q < m.nodeCount(); ++q) {
        max_diff = std::max(max_diff, std::abs(e[c][q] - s[c][q]));
        max_kw = std::max(max_kw, std::abs(e[c][q] - in.f[c][q]));
      }
    }
    EXPECT_LE(max_diff, 1e-12 * max_kw) << b.name;
  }
}

// Every node is one sum in a fixed order, computed by one thread: 2 threads give the same bits as 1.
TEST(SoilKernel, StencilIsBitwiseIndependentOfTheThreadCount) {
  omp_set_dynamic(0);
  const StructuredMesh m = gradedLayeredMesh(75, 40);
  ASSERT_GE(m.nodeCount(), 20000u) << "mesh too small: the kernel would run serially";
  // Both boxes have >= 20000 nodes (the kernel's serial threshold).
  for (const ElementBox& box : {ElementBox::all(m), ElementBox{3, 72, 2, 38, 1, 8}}) {
    const Fields in = randomFields(m, 3);
    std::vector<float> one[3], two[3], again[3];
    applyKernel<float>(KernelKind::Stencil, m, box, 1, in, one);
    applyKernel<float>(KernelKind::Stencil, m, box, 2, in, two);
    applyKernel<float>(KernelKind::Stencil, m, box, 2, in, again);
    for (int c = 0; c < 3; ++c) {
      EXPECT_EQ(std::memcmp(one[c].data(), two[c].data(), one[c].size() * sizeof(float)), 0) << "1 vs 2 threads";
      EXPECT_EQ(std::memcmp(two[c].data(), again[c].data(), two[c].size() * sizeof(float)), 0) << "2 vs 2 threads";
    }
  }
}

TEST(SoilKernel, NamesAndCounts) {
  EXPECT_EQ(kernelFromName("stencil"), KernelKind::Stencil);
  EXPECT_EQ(kernelFromName("element"), KernelKind::Element);
  EXPECT_THROW(kernelFromName("fft"), std::invalid_argument);
  const StructuredMesh m = gradedLayeredMesh(75, 7);
  const ElementBox box = ElementBox::all(m);
  EXPECT_EQ(makeStiffnessKernel<float>(KernelKind::Element, m, box, 1)->multiplyAddsPerApply(), 576.0 * box.count());
  // Inside nodes 153 (177 on the interface planes), face nodes 243.
  const double stencil = makeStiffnessKernel<float>(KernelKind::Stencil, m, box, 1)->multiplyAddsPerApply();
  const double nodes = static_cast<double>(m.nodeCount());
  EXPECT_GT(stencil, 153.0 * nodes);
  EXPECT_LT(stencil, 243.0 * nodes);
}

// The kernel in parts (a slab on a rank with neighbours): the face part completes every force on the shared
// node planes by itself, and faces + rest together give the whole kernel: bit for bit with the stencil (each
// node's force is one line's sum), to the kernels' round-off with the element kernel (sums change order at
// the cuts). Every combination of neighbours and piece counts, on boxes that cut the mesh or touch its faces.
TEST(SoilKernel, SplitKernelPartsSumToTheWholeKernel) {
  const StructuredMesh m = gradedLayeredMesh(40, 9);
  const std::vector<ElementBox> boxes{ElementBox::all(m), {0, m.nx, 2, m.ny - 1, 0, m.nz - 2}};
  for (const ElementBox& box : boxes) {
    for (KernelKind kind : {KernelKind::Stencil, KernelKind::Element}) {
      for (int faces = 0; faces < 4; ++faces) {
        for (size_t pieces : {1u, 3u, 4u, 50u}) {
          const bool low = faces & 1, high = faces & 2;
          const Fields in = randomFields(m, 7);
          std::vector<float> whole[3], parts[3], face_only[3], w[3];
          applyKernel<float>(kind, m, box, 1, in, whole);
          for (int c = 0; c < 3; ++c) {
            w[c].assign(in.w[c].begin(), in.w[c].end());
            parts[c].assign(in.f[c].begin(), in.f[c].end());
          }
          const SplitKernel<float> split = makeSplitStiffnessKernel<float>(kind, m, box, 1, low, high, pieces);
          EXPECT_EQ(split.faces.empty(), !low && !high);
          EXPECT_LE(split.rest.size(), pieces);
          EXPECT_DOUBLE_EQ(split.multiplyAddsPerApply(),
                           kind == KernelKind::Stencil
                               ? makeStiffnessKernel<float>(kind, m, box, 1)->multiplyAddsPerApply()
                               : 576.0 * box.count());
          const float* pin[3] = {w[0].data(), w[1].data(), w[2].data()};
          float* pout[3] = {parts[0].data(), parts[1].data(), parts[2].data()};
          for (const auto& k : split.faces) k->apply(pin, pout);
          for (int c = 0; c < 3; ++c) face_only[c] = parts[c];
          for (const auto& k : split.rest) k->apply(pin, pout);
          // Both within (m + 2) u (|f| + |K| |w|) of the exact sum (top of the file): their difference within twice.
          std::vector<double> ref[3], bound[3];
          naiveReference(m, box, in, ref, bound);
          const double u = std::ldexp(1.0, -24), terms = kind == KernelKind::Stencil ? 81.0 : 192.0;
          double max_diff = 0.0, face_diff = 0.0, max_kw = 0.0;
          for (int c = 0; c < 3; ++c) {
            for (size_t q = 0; q < m.nodeCount(); ++q) {
              const double scale = 2.0 * (terms + 2.0) * u * bound[c][q];
              max_kw = std::max(max_kw, std::abs(ref[c][q] - in.f[c][q]));
              max_diff = std::max(max_diff, std::abs(double(parts[c][q]) - double(whole[c][q])) / scale);
              const size_t i = q % (m.nx + 1);
              if ((low && i == 0) || (high && i == m.nx))
                face_diff = std::max(face_diff, std::abs(double(face_only[c][q]) - double(whole[c][q])) / scale);
            }
          }
          ASSERT_GT(max_kw, 0.0);
          const std::string what =
              kernelName(kind) + " faces " + std::to_string(faces) + " pieces " + std::to_string(pieces);
          if (kind == KernelKind::Stencil) {
            EXPECT_EQ(max_diff, 0.0) << what;
            EXPECT_EQ(face_diff, 0.0) << what;
          } else {
            EXPECT_LE(max_diff, 1.0) << what;
            EXPECT_LE(face_diff, 1.0) << what;
          }
        }
      }
    }
  }
}
