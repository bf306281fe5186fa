// railvib/soil: the element-by-element stiffness kernel (KernelKind::Element) and the kernel factory.
//
// Per element a 24 x 24 product (576 multiply-adds) of its level's matrix with
// the 24 nodal values, vectorised over the elements of a row (x), then a
// scatter of the 24 outputs to the 8 corners. OpenMP over depth slabs of
// levels, in two phases (all levels of each slab but its last, a barrier, then
// the last ones) so that no two threads write the same node plane at once;
// the order of the float sums depends only on the thread count.
#include <omp.h>

#include <algorithm>
#include <stdexcept>

#include "railvib/common/force_inline.hpp"
#include "railvib/soil/kernel.hpp"

namespace railvib::soil {

namespace {

constexpr size_t kElementChunk = 64;

// One element level k, element rows j in [j_begin, j_end), elements i in [i_begin, i_end):
// f -= K_e w, vectorised over the elements of a row. The element outputs go to a small
// buffer, then are added to the nodes corner by corner (no write conflict inside a loop).
template <class Real>
RAILVIB_FORCE_INLINE void levelKernelBody(const Real* __restrict ke, const Real* const* w, Real* const* f,
                                          size_t i_begin, size_t i_end, size_t sx, size_t sxy, size_t k, size_t j_begin,
                                          size_t j_end) {
  alignas(64) Real out[24][kElementChunk];
  size_t off[8];
  for (size_t c = 0; c < 8; ++c) off[c] = (c & 1) + ((c >> 1) & 1) * sx + ((c >> 2) & 1) * sxy;
  for (size_t j = j_begin; j < j_end; ++j) {
    const size_t base = j * sx + k * sxy;
    for (size_t i0 = i_begin; i0 < i_end; i0 += kElementChunk) {
      const size_t len = std::min(kElementChunk, i_end - i0);
      const Real* src[24];
      for (size_t q = 0; q < 24; ++q) src[q] = w[q % 3] + base + off[q / 3] + i0;
#pragma omp simd
      for (size_t ii = 0; ii < len; ++ii) {
        Real in[24];
#pragma GCC unroll 24
        for (size_t q = 0; q < 24; ++q) in[q] = src[q][ii];
#pragma GCC unroll 24
        for (size_t r = 0; r < 24; ++r) {
          Real s = 0;
#pragma GCC unroll 24
          for (size_t q = 0; q < 24; ++q) s += ke[r * 24 + q] * in[q];
          out[r][ii] = s;
        }
      }
      for (size_t r = 0; r < 24; ++r) {
        Real* __restrict dst = f[r % 3] + base + off[r / 3] + i0;
        const Real* __restrict o = out[r];
#pragma omp simd
        for (size_t ii = 0; ii < len; ++ii) dst[ii] -= o[ii];
      }
    }
  }
}

__attribute__((target_clones("avx512f", "avx2", "default"))) void levelKernel(const float* ke, const float* const* w,
                                                                              float* const* f, size_t ib, size_t ie,
                                                                              size_t sx, size_t sxy, size_t k,
                                                                              size_t jb, size_t je) {
  levelKernelBody<float>(ke, w, f, ib, ie, sx, sxy, k, jb, je);
}

__attribute__((target_clones("avx512f", "avx2", "default"))) void levelKernel(const double* ke, const double* const* w,
                                                                              double* const* f, size_t ib, size_t ie,
                                                                              size_t sx, size_t sxy, size_t k,
                                                                              size_t jb, size_t je) {
  levelKernelBody<double>(ke, w, f, ib, ie, sx, sxy, k, jb, je);
}

template <class Real>
class ElementKernel final : public StiffnessKernel<Real> {
 public:
  ElementKernel(const StructuredMesh& mesh, const ElementBox& box, int threads)
      : mesh_(mesh), box_(box), threads_(std::max(1, threads)) {
    ke_.resize(mesh.nz * 576);
    for (size_t k = 0; k < mesh.nz; ++k) {
      const Material& mat = mesh.levelMaterial(k);
      const auto kd =
          boxElementStiffness(mesh.hx, mesh.hy, mesh.z[k + 1] - mesh.z[k], mat.lambda(), mat.shearModulus());
      for (size_t q = 0; q < 576; ++q) ke_[k * 576 + q] = static_cast<Real>(kd[q]);
    }
  }
  ElementKernel(const StructuredMesh& mesh, const ElementBox& box, int threads,
                const std::vector<double>& level_matrices)
      : mesh_(mesh), box_(box), threads_(std::max(1, threads)) {
    if (level_matrices.size() != mesh.nz * 576) {
      throw std::invalid_argument("element kernel: " + std::to_string(level_matrices.size()) + " matrix entries for " +
                                  std::to_string(mesh.nz) + " levels of 576");
    }
    ke_.assign(level_matrices.begin(), level_matrices.end());
  }

  void apply(const Real* const in[3], Real* const out[3]) const override {
    if (box_.empty()) return;
    const size_t sx = mesh_.nx + 1, sxy = (mesh_.nx + 1) * (mesh_.ny + 1);
    const size_t levels = box_.k1 - box_.k0;
    const int t_eff =
        static_cast<int>(std::max<size_t>(1, std::min<size_t>(static_cast<size_t>(threads_), levels / 2)));
    const ElementBox b = box_;
#pragma omp parallel num_threads(t_eff) if (t_eff > 1 && b.count() >= kMinParallelElements)
    {
      const size_t t = static_cast<size_t>(omp_get_thread_num());
      const size_t nt = static_cast<size_t>(omp_get_num_threads());
      const size_t k0 = b.k0 + levels * t / nt, k1 = b.k0 + levels * (t + 1) / nt;
      for (size_t k = k0; k + 1 < k1; ++k) levelKernel(&ke_[k * 576], in, out, b.i0, b.i1, sx, sxy, k, b.j0, b.j1);
#pragma omp barrier
      if (k1 > k0) levelKernel(&ke_[(k1 - 1) * 576], in, out, b.i0, b.i1, sx, sxy, k1 - 1, b.j0, b.j1);
    }
  }

  double multiplyAddsPerApply() const override { return 576.0 * static_cast<double>(box_.count()); }
  KernelKind kind() const override { return KernelKind::Element; }

 private:
  const StructuredMesh& mesh_;
  ElementBox box_;
  int threads_;
  std::vector<Real> ke_;  // nz * 576, row-major per level
};

}  // namespace

std::string kernelName(KernelKind kind) {
  switch (kind) {
    case KernelKind::Element:
      return "element";
    case KernelKind::Stencil:
      return "stencil";
  }
  return "?";
}

KernelKind kernelFromName(const std::string& name) {
  if (name == "element") return KernelKind::Element;
  if (name == "stencil") return KernelKind::Stencil;
  throw std::invalid_argument("unknown soil kernel '" + name + "' (element | stencil)");
}

template <class Real>
std::unique_ptr<StiffnessKernel<Real>> makeStiffnessKernel(KernelKind kind, const StructuredMesh& mesh,
                                                           const ElementBox& box, int threads) {
  switch (kind) {
    case KernelKind::Element:
      return std::make_unique<ElementKernel<Real>>(mesh, box, threads);
    case KernelKind::Stencil:
      return makeStencilKernel<Real>(mesh, box, threads);
  }
  throw std::invalid_argument("soil kernel '" + kernelName(kind) + "' is not available");
}

template <class Real>
std::unique_ptr<StiffnessKernel<Real>> makeElementKernel(const StructuredMesh& mesh, const ElementBox& box, int threads,
                                                         const std::vector<double>& level_matrices) {
  return std::make_unique<ElementKernel<Real>>(mesh, box, threads, level_matrices);
}
template std::unique_ptr<StiffnessKernel<float>> makeElementKernel<float>(const StructuredMesh&, const ElementBox&, int,
                                                                          const std::vector<double>&);
template std::unique_ptr<StiffnessKernel<double>> makeElementKernel<double>(const StructuredMesh&, const ElementBox&,
                                                                            int, const std::vector<double>&);

template <class Real>
SplitKernel<Real> makeSplitStiffnessKernel(KernelKind kind, const StructuredMesh& mesh, const ElementBox& box,
                                           int threads, bool low_face, bool high_face, size_t pieces) {
  if (kind == KernelKind::Stencil) return makeSplitStencilKernel<Real>(mesh, box, threads, low_face, high_face, pieces);
  // Element by element: the element columns next to a face (their forces complete the face's nodes), then the
  // interior in pieces along y (each keeps the rows along x whole).
  SplitKernel<Real> split;
  ElementBox interior = box;
  if (low_face) {
    const ElementBox edge = box.intersect({0, 1, 0, mesh.ny, 0, mesh.nz});
    if (!edge.empty()) split.faces.push_back(makeStiffnessKernel<Real>(kind, mesh, edge, threads));
    interior.i0 = std::max<size_t>(interior.i0, 1);
  }
  if (high_face) {
    const ElementBox edge = box.intersect({mesh.nx - 1, mesh.nx, 0, mesh.ny, 0, mesh.nz});
    if (!edge.empty()) split.faces.push_back(makeStiffnessKernel<Real>(kind, mesh, edge, threads));
    interior.i1 = std::min(interior.i1, mesh.nx - 1);
  }
  if (interior.empty()) return split;
  const size_t ny = interior.j1 - interior.j0, n = std::max<size_t>(1, std::min(pieces, ny));
  for (size_t q = 0; q < n; ++q) {
    ElementBox piece = interior;
    piece.j0 = interior.j0 + ny * q / n;
    piece.j1 = interior.j0 + ny * (q + 1) / n;
    if (!piece.empty()) split.rest.push_back(makeStiffnessKernel<Real>(kind, mesh, piece, threads));
  }
  return split;
}

template SplitKernel<float> makeSplitStiffnessKernel<float>(KernelKind, const StructuredMesh&, const ElementBox&, int,
                                                            bool, bool, size_t);
template SplitKernel<double> makeSplitStiffnessKernel<double>(KernelKind, const StructuredMesh&, const ElementBox&, int,
                                                              bool, bool, size_t);

template std::unique_ptr<StiffnessKernel<float>> makeStiffnessKernel<float>(KernelKind, const StructuredMesh&,
                                                                            const ElementBox&, int);
template std::unique_ptr<StiffnessKernel<double>> makeStiffnessKernel<double>(KernelKind, const StructuredMesh&,
                                                                              const ElementBox&, int);

}  // namespace railvib::soil
