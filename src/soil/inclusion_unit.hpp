// railvib/soil (internal): the material inclusions of a mesh (MeshSpec::inclusions) as a solver unit.
//
// The stiffness kernel integrates every element with its level's material and knows nothing of
// inclusions. This unit adds, over each inclusion's elements, the difference its own material makes:
//   f -= (K_incl - K_level) w                    (w = u + beta vf, the field the kernel acts on)
//   f -= (beta_i / beta - 1) K_incl (w - u)      (only when the inclusion has a Rayleigh beta_i of its
//                                                 own: K_incl (u + beta_i vf) in all)
// with the element kernel (kernel.hpp, makeElementKernel) over the inclusion's element box and the
// difference matrices per level. A void is K_incl = 0: the kernel's forces of its elements are taken
// back, its faces are free surfaces, and its inner nodes have no mass (the solver holds them still).
// The lumped mass and the stable step follow the element materials in Solver itself.
#pragma once

#include <cmath>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

#include "railvib/soil/kernel.hpp"
#include "railvib/soil/mesh.hpp"
#include "railvib/soil/solver_unit.hpp"

namespace railvib::soil {

template <class Real>
class InclusionUnit final : public SolverUnit<Real> {
 public:
  /// `soil_beta_s`: the soil's Rayleigh coefficient (the damping filter's); an inclusion's own one
  /// needs it to be > 0 (vf is read back as (w - u) / beta).
  InclusionUnit(const StructuredMesh& mesh, double soil_beta_s, int threads) {
    for (const MeshInclusion& inc : mesh.inclusions) {
      Part part;
      part.box = inc.elements;
      std::vector<double> difference(mesh.nz * 576, 0.0), own(mesh.nz * 576, 0.0);
      for (size_t k = inc.elements.k0; k < inc.elements.k1; ++k) {
        const double hz = mesh.z[k + 1] - mesh.z[k];
        const Material& host = mesh.levelMaterial(k);
        const auto kh = boxElementStiffness(mesh.hx, mesh.hy, hz, host.lambda(), host.shearModulus());
        std::array<double, 576> ki{};
        if (!inc.is_void)
          ki = boxElementStiffness(mesh.hx, mesh.hy, hz, inc.material.lambda(), inc.material.shearModulus());
        for (size_t q = 0; q < 576; ++q) {
          difference[k * 576 + q] = ki[q] - kh[q];
          own[k * 576 + q] = ki[q];
        }
      }
      part.difference = makeElementKernel<Real>(mesh, inc.elements, threads, difference);
      // An implicit inclusion's damping is in its own solve (implicit_unit.hpp): the soil's is taken off it here.
      const double explicit_beta_s = inc.implicit ? 0.0 : inc.rayleigh_beta_s;
      const bool own_damping = !inc.is_void && explicit_beta_s >= 0.0 && explicit_beta_s != soil_beta_s;
      if (own_damping) {
        if (!(soil_beta_s > 0.0)) {
          throw std::invalid_argument("soil inclusion '" + inc.name +
                                      "': a Rayleigh coefficient of its own needs the soil's damping filter "
                                      "(soil.rayleigh_beta_s > 0)");
        }
        part.own_damping = makeElementKernel<Real>(mesh, inc.elements, threads, own);
        part.damping_factor = static_cast<Real>(explicit_beta_s / soil_beta_s - 1.0);
        if (scratch_[0].empty()) {
          for (auto& s : scratch_) s.assign(mesh.nodeCount(), Real(0));
        }
      }
      parts_.push_back(std::move(part));
    }
  }

  /// f -= (K_incl - K_level) in over every inclusion: what the inclusions change in the internal force.
  void addStiffness(const Real* const in[3], Real* const out[3]) const {
    for (const Part& p : parts_) p.difference->apply(in, out);
  }

  void addForces(StepContext<Real>& ctx) override {
    const Real* w[3] = {ctx.fields.w[0], ctx.fields.w[1], ctx.fields.w[2]};
    addStiffness(w, ctx.fields.f);
    for (const Part& p : parts_) {
      if (!p.own_damping) continue;
      // (beta_i / beta - 1) beta vf on the inclusion's nodes; the kernel reads no other node.
      const StructuredMesh& m = *ctx.mesh;
      Real* r[3] = {scratch_[0].data(), scratch_[1].data(), scratch_[2].data()};
      for (size_t k = p.box.k0; k <= p.box.k1; ++k) {
        for (size_t j = p.box.j0; j <= p.box.j1; ++j) {
          for (size_t i = p.box.i0; i <= p.box.i1; ++i) {
            const size_t nd = m.node(i, j, k);
            for (int d = 0; d < 3; ++d) r[d][nd] = p.damping_factor * (ctx.fields.w[d][nd] - ctx.fields.u[d][nd]);
          }
        }
      }
      const Real* in[3] = {r[0], r[1], r[2]};
      p.own_damping->apply(in, ctx.fields.f);
    }
  }

 private:
  struct Part {
    ElementBox box;
    std::unique_ptr<StiffnessKernel<Real>> difference;
    std::unique_ptr<StiffnessKernel<Real>> own_damping;
    Real damping_factor = 0;
  };
  std::vector<Part> parts_;
  std::vector<Real> scratch_[3];
};

}  // namespace railvib::soil
