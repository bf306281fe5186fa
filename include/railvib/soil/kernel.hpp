// railvib/soil: stiffness kernels, the one hot loop of the explicit solver.
//
// A kernel adds f -= K_box w, the internal force of the elements of one
// ElementBox of a StructuredMesh acting on a nodal field w (structure of
// arrays, one array per component), to the nodes of those elements. The
// element stiffness depends only on the element level k (box elements,
// uniform in x and y), so a kernel keeps one 24 x 24 matrix per level.
// Kernels own their threading and must be deterministic for a given thread
// count. Boundaries and attached structures never change a kernel: elements
// outside the box (e.g. a PML layer) are integrated by their unit
// (solver_unit.hpp).
#pragma once

#include <cstddef>
#include <memory>
#include <string>
#include <vector>

#include "railvib/soil/mesh.hpp"

namespace railvib::soil {

/// Below this many elements per step the work (< ~0.5 ms) does not pay for the OpenMP fork/join and
/// barriers: kernels and boundary units run such a box serially.
inline constexpr size_t kMinParallelElements = 20000;

enum class KernelKind {
  /// Element by element: per element a 24 x 24 product, then a scatter to its 8 nodes.
  Element,
  /// Node by node: the assembled operator as a 27-point stencil of 3 x 3 blocks per node plane.
  Stencil,
};

std::string kernelName(KernelKind kind);
/// "element" | "stencil"; throws std::invalid_argument otherwise.
KernelKind kernelFromName(const std::string& name);

template <class Real>
class StiffnessKernel {
 public:
  virtual ~StiffnessKernel() = default;
  /// f -= K_box w. in/out: 3 component arrays of StructuredMesh::nodeCount() values.
  virtual void apply(const Real* const in[3], Real* const out[3]) const = 0;
  /// Multiply-adds per application (for the throughput figures).
  virtual double multiplyAddsPerApply() const = 0;
  virtual KernelKind kind() const = 0;
};

/// The kernel of `kind` for the elements of `box` of `mesh` (which must outlive it), with
/// at most `threads` OpenMP threads.
template <class Real>
std::unique_ptr<StiffnessKernel<Real>> makeStiffnessKernel(KernelKind kind, const StructuredMesh& mesh,
                                                           const ElementBox& box, int threads);

/// The KernelKind::Element kernel of `box` with a 24 x 24 matrix of its own per element level k
/// (level_matrices[k * 576 + q], row-major, nz levels) instead of the mesh's level materials': e.g. the
/// stiffness a material inclusion adds to the elements it holds (soil/inclusion_unit.hpp).
template <class Real>
std::unique_ptr<StiffnessKernel<Real>> makeElementKernel(const StructuredMesh& mesh, const ElementBox& box, int threads,
                                                         const std::vector<double>& level_matrices);

/// A kernel in parts, for a slab spread over ranks (solver.cpp): `faces` completes the forces on the nodes of the
/// mesh's node planes i = 0 (low_face) and i = nx (high_face), which are sent to the neighbours; `rest` is the
/// remaining work in pieces, applied while the messages travel. Applying faces, then every piece of rest, gives
/// apply() of the whole box: bit for bit with the stencil (each node's force is one line's), to round-off with
/// the element kernel (edge columns and interior pieces are element boxes; their sums at the cuts change order).
template <class Real>
struct SplitKernel {
  std::vector<std::unique_ptr<StiffnessKernel<Real>>> faces;
  std::vector<std::unique_ptr<StiffnessKernel<Real>>> rest;
  double multiplyAddsPerApply() const {
    double m = 0.0;
    for (const auto& k : faces) m += k->multiplyAddsPerApply();
    for (const auto& k : rest) m += k->multiplyAddsPerApply();
    return m;
  }
};
template <class Real>
SplitKernel<Real> makeSplitStiffnessKernel(KernelKind kind, const StructuredMesh& mesh, const ElementBox& box,
                                           int threads, bool low_face, bool high_face, size_t pieces);

/// The KernelKind::Stencil kernel (kernel_stencil.cpp); makeStiffnessKernel dispatches to it with the widest
/// instruction set of the CPU. `instruction_set` (one of stencilInstructionSets()) forces another (tests).
template <class Real>
std::unique_ptr<StiffnessKernel<Real>> makeStencilKernel(const StructuredMesh& mesh, const ElementBox& box, int threads,
                                                         const std::string& instruction_set = "");
/// makeSplitStiffnessKernel for the stencil: one table set shared by the parts, the lines dealt out.
template <class Real>
SplitKernel<Real> makeSplitStencilKernel(const StructuredMesh& mesh, const ElementBox& box, int threads, bool low_face,
                                         bool high_face, size_t pieces, const std::string& instruction_set = "");
/// The stencil kernel's code paths this CPU can run, widest first: "avx512f", "avx2+fma", "sse2".
std::vector<std::string> stencilInstructionSets();

}  // namespace railvib::soil
