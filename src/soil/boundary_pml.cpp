// railvib/soil: perfectly matched layer (BoundaryMethod::Pml), convolutional and multi-axial.
//
// Complex coordinate stretching (Chew & Weedon 1994; elastodynamics: Collino &
// Tsogka 2001): in the layer every derivative d/dx_l becomes (1 / s_l) d/dx_l,
//   s_l(omega) = kappa_l + d_l / (alpha + i omega)
// (complex frequency shifted, Kuzuoglu & Mittra 1996). The elastodynamic
// equations rho dv_i/dt = sum_j (1 / s_j) d sigma_ij / dx_j and
// sigma = C : sym(G~), G~_kl = (1 / s_l) d w_k / dx_l, are discretised with the
// solver's trilinear box elements and lumped mass:
// - the stretched gradient: the difference of w along each mesh edge of
//   direction l (w = u + beta vf, the field the stiffness acts on, so the
//   Rayleigh damping stays the same operator) is filtered by 1 / s_l with d_l
//   taken at the edge midpoint, then interpolated to the 2x2x2 Gauss points as
//   the element gradient is (for a trilinear field d w / dx_l at a Gauss point
//   is the bilinear interpolation of the four l-edge differences of the element);
//   filtering before differentiating would be wrong where d varies: d(w / s)/dx
//   is not (1 / s) dw/dx;
// - the stress at the Gauss points gives the split nodal forces
//   f^(j)_ai = -int dN_a/dx_j sigma_ij (sum over j = the element force -K w);
// - the momentum side: the lumped form of (1 / s_j) d sigma_ij / dx_j at node a
//   is (1 / s_j(x_a)) f^(j)_ai, the filter applied to the split nodal forces
//   with d_j at the node; their sum enters the solver's ordinary nodal update.
// The filter y~ = y / s is the recursive convolution of Komatitsch & Martin
// (2007), after Roden & Gedney (2000):
//   y~_n = y_n / kappa + psi_n,  psi_n = b psi_{n-1} + a y_n,
//   b = exp(-(d / kappa + alpha) dt),  a = d (b - 1) / (kappa (d + kappa alpha)).
// With d = 0 and kappa = 1 it is the identity (a = 0): the layer elements then
// give exactly -K w, the interface nodes (d = 0) the plain sum. Memory: 3
// components per edge direction per node (edges) and 3 x 3 per node (split
// forces); the layer's nodes need no update of their own, so constraints
// (symmetry planes) and the outer dashpots act through the nodal update.
// Each box of the layer is swept plane by plane so that the edge gradients and
// split forces of a plane are used while in cache.
// Multi-axial PML (Meza-Fajardo & Papageorgiou 2008): the directions parallel
// to a face get p times its damping. docs/soil.md, "Perfectly matched layer".
#include <omp.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>
#include <vector>

#include "railvib/common/force_inline.hpp"
#include "railvib/soil/boundary.hpp"
#include "railvib/soil/kernel.hpp"

namespace railvib::soil {

namespace {

constexpr size_t kPmlChunk = 32;

// Where the layer is on a mesh: element counts per face, the interior the kernel keeps, and the
// layer as disjoint element boxes (bottom slab, then the x strips, then the y strips between them).
struct PmlLayout {
  size_t x_lo = 0, x_hi = 0, y_lo = 0, y_hi = 0, z_hi = 0;
  ElementBox interior;
  std::vector<ElementBox> boxes;
  double length_x_m = 0.0, length_y_m = 0.0, length_z_m = 0.0;  // layer thickness per direction (as meshed)

  // Relative depth s / L in [0, 1] into the layer of a coordinate along each direction (0 outside).
  double sx(const StructuredMesh& m, double x) const {
    const double a = m.x(x_lo), b = m.x(m.nx - x_hi);
    if (x_lo > 0 && x < a) return std::min(1.0, (a - x) / (a - m.x0));
    if (x_hi > 0 && x > b) return std::min(1.0, (x - b) / (m.xMax() - b));
    return 0.0;
  }
  double sy(const StructuredMesh& m, double y) const {
    const double a = m.y(y_lo), b = m.y(m.ny - y_hi);
    if (y_lo > 0 && y < a) return std::min(1.0, (a - y) / (a - m.y0));
    if (y_hi > 0 && y > b) return std::min(1.0, (y - b) / (m.yMax() - b));
    return 0.0;
  }
  double sz(const StructuredMesh& m, double z) const {
    const double a = m.z[m.nz - z_hi];
    if (z_hi > 0 && z > a) return std::min(1.0, (z - a) / (m.depth() - a));
    return 0.0;
  }
};

PmlLayout pmlLayout(const StructuredMesh& m, const AbsorbingFaces& f, const PmlSpec& spec) {
  PmlLayout p;
  const double L = spec.thickness_m;
  // A whole number of elements, at most L thick (receivers and loads are refused within L).
  auto count = [&](double h, const char* face) {
    const size_t n = static_cast<size_t>(std::floor(L / h + 1e-9));
    if (n == 0) {
      throw std::invalid_argument("soil PML: thickness " + std::to_string(L) + " m is less than one element (" +
                                  std::to_string(h) + " m) at " + face);
    }
    return n;
  };
  if (f.x_min) p.x_lo = count(m.hx, "x_min");
  if (f.x_max) p.x_hi = count(m.hx, "x_max");
  if (f.y_min) p.y_lo = count(m.hy, "y_min");
  if (f.y_max) p.y_hi = count(m.hy, "y_max");
  if (f.bottom && spec.bottom) {
    size_t k = m.nz;
    while (k > 0 && m.depth() - m.z[k - 1] <= L * (1.0 + 1e-9)) --k;
    p.z_hi = m.nz - k;
    if (p.z_hi == 0) {
      throw std::invalid_argument("soil PML: thickness " + std::to_string(L) +
                                  " m is less than the deepest element level");
    }
  }
  if (p.x_lo + p.x_hi >= m.nx || p.y_lo + p.y_hi >= m.ny || p.z_hi >= m.nz) {
    throw std::invalid_argument("soil PML: the layer (" + std::to_string(L) + " m) fills the soil box");
  }
  p.length_x_m = static_cast<double>(std::max(p.x_lo, p.x_hi)) * m.hx;
  p.length_y_m = static_cast<double>(std::max(p.y_lo, p.y_hi)) * m.hy;
  p.length_z_m = m.depth() - m.z[m.nz - p.z_hi];
  const size_t kb = m.nz - p.z_hi;  // first level of the bottom slab
  p.interior = {p.x_lo, m.nx - p.x_hi, p.y_lo, m.ny - p.y_hi, 0, kb};
  auto add = [&](ElementBox b) {
    if (!b.empty()) p.boxes.push_back(b);
  };
  add({0, m.nx, 0, m.ny, kb, m.nz});
  add({0, p.x_lo, 0, m.ny, 0, kb});
  add({m.nx - p.x_hi, m.nx, 0, m.ny, 0, kb});
  add({p.x_lo, m.nx - p.x_hi, 0, p.y_lo, 0, kb});
  add({p.x_lo, m.nx - p.x_hi, m.ny - p.y_hi, m.ny, 0, kb});
  return p;
}

// Damping profile of the layer and the recursive-convolution coefficients of 1 / s.
struct PmlProfile {
  PmlSpec spec;
  double d0[3] = {0.0, 0.0, 0.0};  // 1/s, per direction

  PmlProfile(const PmlSpec& s, const PmlLayout& lay, double vp_max) : spec(s) {
    // Collino & Tsogka (2001): R = exp(-2 / c int_0^L d ds) at normal incidence for d = d0 (s / L)^n.
    const double lnr = std::log(spec.reflection_coefficient);
    const double lengths[3] = {lay.length_x_m, lay.length_y_m, lay.length_z_m};
    for (int l = 0; l < 3; ++l) {
      d0[l] = lengths[l] > 0.0 ? -(spec.exponent + 1.0) * vp_max * lnr / (2.0 * lengths[l]) : 0.0;
    }
  }
  double main(int l, double s) const { return s > 0.0 ? d0[l] * std::pow(s, spec.exponent) : 0.0; }

  struct Coefficients {
    double a = 0.0, b = 0.0, c = 1.0;  // y~ = c y + psi, psi <- b psi + a y
    bool identity() const { return a == 0.0 && c == 1.0; }
  };
  // Direction l at a point with relative depths s[3] into the layer of each direction.
  Coefficients at(int l, const double s[3], double dt) const {
    double d = main(l, s[l]);
    for (int m = 0; m < 3; ++m) {
      if (m != l) d += spec.perpendicular_ratio * main(m, s[m]);
    }
    const double kappa = 1.0 + (spec.max_kappa - 1.0) * (s[l] > 0.0 ? std::pow(s[l], spec.exponent) : 0.0);
    const double alpha = spec.alpha_1_s;
    Coefficients c;
    c.c = 1.0 / kappa;
    if (d > 0.0) {
      c.b = std::exp(-(d / kappa + alpha) * dt);
      c.a = d * (c.b - 1.0) / (kappa * (d + kappa * alpha));
    }
    return c;
  }
};

// One box of layer elements with its own edge and node memory. Nodes shared with another box or with
// the interior get each box's filtered forces: the filter is linear and has the same coefficients there.
// The box is swept plane by plane along `sweep` (k or j, the longer); i is the vectorised axis.
template <class Real>
struct PmlBox {
  ElementBox e;
  size_t ni = 0, nj = 0, nk = 0;
  size_t sx = 0, sxy = 0, nodes = 0;
  bool along_k = true;          // sweep axis k (else j); the other one is the row axis
  size_t planes = 0, rows = 0;  // element planes along the sweep axis, element rows in a plane
  // Edge of direction l starting at a local node: memory psi per component and filter coefficients.
  std::vector<Real> psi[3][3];
  std::vector<Real> edge_a[3], edge_b[3], edge_c[3];
  // Node: memory phi of the split force f^(j), per component i and direction j, and its coefficients.
  std::vector<Real> phi[3][3];
  std::vector<Real> node_a[3], node_b[3], node_c[3];
  // Whether any edge / node of the box has a filter other than the identity, per direction.
  bool edge_active[3] = {false, false, false}, node_active[3] = {false, false, false};
  // Per element level: lambda, mu, and the Gauss weight over h_j (W / h_j) per direction.
  std::vector<Real> lam, mu, wx, wy, wz, inv_hz;
  size_t local(size_t i, size_t j, size_t k) const { return i + sx * (j + (nj + 1) * k); }
  // Local (j, k) of node row r of node plane q.
  size_t rowJ(size_t q, size_t r) const { return along_k ? r : q; }
  size_t rowK(size_t q, size_t r) const { return along_k ? q : r; }
};

// A node plane's temporaries: the stretched edge gradients (direction l, component c) and the split
// forces (component i, direction j), (ni + 1) values per node row.
template <class Real>
struct PlaneSlot {
  std::vector<Real> grad[9], split[9];
  void reserve(size_t n) {
    for (auto& g : grad) g.assign(n, Real(0));
    for (auto& s : split) s.assign(n, Real(0));
  }
};

// Pass B of one element row: gradients at the 2x2x2 Gauss points from the stretched edge differences,
// stress, and the split forces added to the nodes. src[(l * 3 + c) * 4 + p]: the four edges of direction
// l (slot p = u + 2 v over the two other directions in order), component c; near/far[(j * 3 + i) * 4 + p]:
// the nodes at the near / far end along j of slot p, split force f^(j) component i. Vectorised over the row.
template <class Real>
RAILVIB_FORCE_INLINE void rowForcesBody(const Real* const* src, Real* const* near, Real* const* far, size_t ni,
                                        Real lam, Real mu, Real wx, Real wy, Real wz) {
  // Bilinear weights of the two nodes along a direction at its two Gauss points -/+ 1/sqrt(3).
  const Real gp = Real(0.5 + 0.5 / std::sqrt(3.0)), gm = Real(0.5 - 0.5 / std::sqrt(3.0));
  const Real wgt[2][2] = {{gp, gm}, {gm, gp}};  // wgt[node][gauss point]
  const Real wj[3] = {wx, wy, wz};
  alignas(64) Real out[36][kPmlChunk];
  for (size_t i0 = 0; i0 < ni; i0 += kPmlChunk) {
    const size_t len = std::min(kPmlChunk, ni - i0);
#pragma omp simd
    for (size_t ii = 0; ii < len; ++ii) {
      // G[l][c][q1][q2]: d w_c / dx_l stretched, at the Gauss points of the two other directions (in order).
      Real G[3][3][2][2];
#pragma GCC unroll 9
      for (size_t lc = 0; lc < 9; ++lc) {
        const Real e00 = src[lc * 4][i0 + ii], e10 = src[lc * 4 + 1][i0 + ii];
        const Real e01 = src[lc * 4 + 2][i0 + ii], e11 = src[lc * 4 + 3][i0 + ii];
#pragma GCC unroll 2
        for (size_t q1 = 0; q1 < 2; ++q1) {
          const Real t0 = wgt[0][q1] * e00 + wgt[1][q1] * e10;
          const Real t1 = wgt[0][q1] * e01 + wgt[1][q1] * e11;
#pragma GCC unroll 2
          for (size_t q2 = 0; q2 < 2; ++q2) G[lc / 3][lc % 3][q1][q2] = wgt[0][q2] * t0 + wgt[1][q2] * t1;
        }
      }
      // S[j][i][q1][q2]: sigma_ij summed over the two Gauss points along j.
      Real S[3][3][2][2] = {};
#pragma GCC unroll 2
      for (size_t qx = 0; qx < 2; ++qx) {
#pragma GCC unroll 2
        for (size_t qy = 0; qy < 2; ++qy) {
#pragma GCC unroll 2
          for (size_t qz = 0; qz < 2; ++qz) {
            const Real gxx = G[0][0][qy][qz], gyx = G[0][1][qy][qz], gzx = G[0][2][qy][qz];  // d/dx of w_x, w_y, w_z
            const Real gxy = G[1][0][qx][qz], gyy = G[1][1][qx][qz], gzy = G[1][2][qx][qz];
            const Real gxz = G[2][0][qx][qy], gyz = G[2][1][qx][qy], gzz = G[2][2][qx][qy];
            const Real lt = lam * (gxx + gyy + gzz);
            const Real sxx = lt + Real(2) * mu * gxx, syy = lt + Real(2) * mu * gyy, szz = lt + Real(2) * mu * gzz;
            const Real sxy = mu * (gxy + gyx), sxz = mu * (gxz + gzx), syz = mu * (gyz + gzy);
            S[0][0][qy][qz] += sxx;
            S[0][1][qy][qz] += sxy;
            S[0][2][qy][qz] += sxz;
            S[1][0][qx][qz] += sxy;
            S[1][1][qx][qz] += syy;
            S[1][2][qx][qz] += syz;
            S[2][0][qx][qy] += sxz;
            S[2][1][qx][qy] += syz;
            S[2][2][qx][qy] += szz;
          }
        }
      }
      // Transposed interpolation: F[j][i][n1][n2] = (W / h_j) sum_q wgt[n1][q1] wgt[n2][q2] S[j][i][q1][q2];
      // the node at the near end along j gets +F, the far one -F (dN/dx_j = -+1/h_j times the weights).
#pragma GCC unroll 9
      for (size_t ji = 0; ji < 9; ++ji) {
        const size_t j = ji / 3, i = ji % 3;
#pragma GCC unroll 2
        for (size_t n1 = 0; n1 < 2; ++n1) {
          const Real t0 = wgt[n1][0] * S[j][i][0][0] + wgt[n1][1] * S[j][i][1][0];
          const Real t1 = wgt[n1][0] * S[j][i][0][1] + wgt[n1][1] * S[j][i][1][1];
#pragma GCC unroll 2
          for (size_t n2 = 0; n2 < 2; ++n2) out[ji * 4 + n1 + 2 * n2][ii] = wj[j] * (wgt[n2][0] * t0 + wgt[n2][1] * t1);
        }
      }
    }
    for (size_t r = 0; r < 36; ++r) {
      const Real* __restrict o = out[r];
      Real* __restrict dn = near[r] + i0;
#pragma omp simd
      for (size_t ii = 0; ii < len; ++ii) dn[ii] += o[ii];
      Real* __restrict df = far[r] + i0;
#pragma omp simd
      for (size_t ii = 0; ii < len; ++ii) df[ii] -= o[ii];
    }
  }
}

__attribute__((target_clones("avx512f", "avx2", "default"))) void rowForces(const float* const* src, float* const* near,
                                                                            float* const* far, size_t ni, float lam,
                                                                            float mu, float wx, float wy, float wz) {
  rowForcesBody<float>(src, near, far, ni, lam, mu, wx, wy, wz);
}

__attribute__((target_clones("avx512f", "avx2", "default"))) void rowForces(const double* const* src,
                                                                            double* const* near, double* const* far,
                                                                            size_t ni, double lam, double mu, double wx,
                                                                            double wy, double wz) {
  rowForcesBody<double>(src, near, far, ni, lam, mu, wx, wy, wz);
}

// Pass A of one node row: the differences of w along the edges that start at the row's nodes (x: n - 1 of
// them, y and z: n, when the box has them), filtered by 1 / s_l (memory psi) into grad. The pointers are
// per direction l (coefficients, inverse length) and per l * 3 + c (w at the far end, memory, output); w0
// holds w at the row's nodes. Inactive directions skip the filter (identity everywhere in the box).
template <class Real>
struct RowGradientArgs {
  const Real* w0[3];
  const Real* w1[9];
  const Real *ea[3], *eb[3], *ec[3];
  Real* psi[9];
  Real* grad[9];
  Real inv_h[3];
  bool has[3], active[3];
  size_t n;
};

template <class Real, bool Stretch>
RAILVIB_FORCE_INLINE void rowGradientsBody(const RowGradientArgs<Real>& a) {
  for (int l = 0; l < 3; ++l) {
    if (!a.has[l]) continue;
    const size_t n = l == 0 ? a.n - 1 : a.n;
    const Real ih = a.inv_h[l];
    if (!a.active[l]) {
      for (int c = 0; c < 3; ++c) {
        const Real* __restrict w0 = a.w0[c];
        const Real* __restrict w1 = a.w1[l * 3 + c];
        Real* __restrict g = a.grad[l * 3 + c];
#pragma omp simd
        for (size_t i = 0; i < n; ++i) g[i] = (w1[i] - w0[i]) * ih;
      }
      continue;
    }
    const Real* __restrict ea = a.ea[l];
    const Real* __restrict eb = a.eb[l];
    const Real* __restrict ec = a.ec[l];
    const Real* __restrict w0x = a.w0[0];
    const Real* __restrict w0y = a.w0[1];
    const Real* __restrict w0z = a.w0[2];
    const Real* __restrict w1x = a.w1[l * 3];
    const Real* __restrict w1y = a.w1[l * 3 + 1];
    const Real* __restrict w1z = a.w1[l * 3 + 2];
    Real* __restrict px = a.psi[l * 3];
    Real* __restrict py = a.psi[l * 3 + 1];
    Real* __restrict pz = a.psi[l * 3 + 2];
    Real* __restrict gx = a.grad[l * 3];
    Real* __restrict gy = a.grad[l * 3 + 1];
    Real* __restrict gz = a.grad[l * 3 + 2];
#pragma omp simd
    for (size_t i = 0; i < n; ++i) {
      const Real cb = eb[i], ca = ea[i], cc = Stretch ? ec[i] : Real(1);
      const Real yx = (w1x[i] - w0x[i]) * ih, yy = (w1y[i] - w0y[i]) * ih, yz = (w1z[i] - w0z[i]) * ih;
      const Real qx = cb * px[i] + ca * yx, qy = cb * py[i] + ca * yy, qz = cb * pz[i] + ca * yz;
      px[i] = qx;
      py[i] = qy;
      pz[i] = qz;
      gx[i] = cc * yx + qx;
      gy[i] = cc * yy + qy;
      gz[i] = cc * yz + qz;
    }
  }
}

// Stretch: kappa != 1 somewhere (else the 1 / kappa factors are not loaded).
__attribute__((target_clones("avx512f", "avx2", "default"))) void rowGradients(const RowGradientArgs<float>& a,
                                                                               bool stretch) {
  stretch ? rowGradientsBody<float, true>(a) : rowGradientsBody<float, false>(a);
}
__attribute__((target_clones("avx512f", "avx2", "default"))) void rowGradients(const RowGradientArgs<double>& a,
                                                                               bool stretch) {
  stretch ? rowGradientsBody<double, true>(a) : rowGradientsBody<double, false>(a);
}

// Pass C of one node row: the split forces f^(j) (component i, direction j: index i * 3 + j) filtered by
// 1 / s_j at the node (memory phi) and summed into the solver's forces f; the split forces cleared.
template <class Real>
struct RowNodalArgs {
  Real* f[3];
  Real* split[9];
  Real* phi[9];
  const Real *na[3], *nb[3], *nc[3];
  bool active[3];
  size_t n;
};

template <class Real, bool Stretch>
RAILVIB_FORCE_INLINE void rowNodalBody(const RowNodalArgs<Real>& a) {
  for (int j = 0; j < 3; ++j) {
    if (!a.active[j]) {
      for (int i = 0; i < 3; ++i) {
        Real* __restrict fi = a.f[i];
        Real* __restrict sp = a.split[i * 3 + j];
#pragma omp simd
        for (size_t s = 0; s < a.n; ++s) {
          fi[s] += sp[s];
          sp[s] = Real(0);
        }
      }
      continue;
    }
    const Real* __restrict na = a.na[j];
    const Real* __restrict nb = a.nb[j];
    const Real* __restrict nc = a.nc[j];
    Real* __restrict fx = a.f[0];
    Real* __restrict fy = a.f[1];
    Real* __restrict fz = a.f[2];
    Real* __restrict sx = a.split[j];
    Real* __restrict sy = a.split[3 + j];
    Real* __restrict sz = a.split[6 + j];
    Real* __restrict hx = a.phi[j];
    Real* __restrict hy = a.phi[3 + j];
    Real* __restrict hz = a.phi[6 + j];
#pragma omp simd
    for (size_t s = 0; s < a.n; ++s) {
      const Real cb = nb[s], ca = na[s], cc = Stretch ? nc[s] : Real(1);
      const Real yx = sx[s], yy = sy[s], yz = sz[s];
      const Real qx = cb * hx[s] + ca * yx, qy = cb * hy[s] + ca * yy, qz = cb * hz[s] + ca * yz;
      hx[s] = qx;
      hy[s] = qy;
      hz[s] = qz;
      fx[s] += cc * yx + qx;
      fy[s] += cc * yy + qy;
      fz[s] += cc * yz + qz;
      sx[s] = Real(0);
      sy[s] = Real(0);
      sz[s] = Real(0);
    }
  }
}

__attribute__((target_clones("avx512f", "avx2", "default"))) void rowNodal(const RowNodalArgs<float>& a, bool stretch) {
  stretch ? rowNodalBody<float, true>(a) : rowNodalBody<float, false>(a);
}
__attribute__((target_clones("avx512f", "avx2", "default"))) void rowNodal(const RowNodalArgs<double>& a,
                                                                           bool stretch) {
  stretch ? rowNodalBody<double, true>(a) : rowNodalBody<double, false>(a);
}

template <class Real>
class PmlUnit final : public SolverUnit<Real> {
 public:
  PmlUnit(const StructuredMesh& m, const PmlLayout& layout, const PmlProfile& profile)
      : mesh_(m), layout_(layout), profile_(profile) {
    for (const ElementBox& e : layout_.boxes) {
      PmlBox<Real> b;
      b.e = e;
      b.ni = e.i1 - e.i0;
      b.nj = e.j1 - e.j0;
      b.nk = e.k1 - e.k0;
      b.sx = b.ni + 1;
      b.sxy = (b.ni + 1) * (b.nj + 1);
      b.nodes = b.sxy * (b.nk + 1);
      b.along_k = b.nk >= b.nj;
      b.planes = b.along_k ? b.nk : b.nj;
      b.rows = b.along_k ? b.nj : b.nk;
      for (int l = 0; l < 3; ++l) {
        for (int c = 0; c < 3; ++c) {
          b.psi[l][c].assign(b.nodes, Real(0));
          b.phi[l][c].assign(b.nodes, Real(0));
        }
        b.edge_a[l].assign(b.nodes, Real(0));
        b.edge_b[l].assign(b.nodes, Real(0));
        b.edge_c[l].assign(b.nodes, Real(1));
        b.node_a[l].assign(b.nodes, Real(0));
        b.node_b[l].assign(b.nodes, Real(0));
        b.node_c[l].assign(b.nodes, Real(1));
      }
      for (size_t k = e.k0; k < e.k1; ++k) {
        const Material& mat = m.levelMaterial(k);
        const double hz = m.z[k + 1] - m.z[k];
        const double w = m.hx * m.hy * hz / 8.0;  // Gauss weight (2x2x2, weights 1) times the Jacobian
        b.lam.push_back(static_cast<Real>(mat.lambda()));
        b.mu.push_back(static_cast<Real>(mat.shearModulus()));
        b.wx.push_back(static_cast<Real>(w / m.hx));
        b.wy.push_back(static_cast<Real>(w / m.hy));
        b.wz.push_back(static_cast<Real>(w / hz));
        b.inv_hz.push_back(static_cast<Real>(1.0 / hz));
      }
      elements_ += e.count();
      plane_nodes_ = std::max(plane_nodes_, (b.ni + 1) * (b.rows + 1));
      boxes_.push_back(std::move(b));
    }
  }

  void addForces(StepContext<Real>& ctx) override {
    if (static_cast<double>(ctx.dt) != dt_s_) setCoefficients(static_cast<double>(ctx.dt));
    const int threads = elements_ >= kMinParallelElements ? std::max(1, ctx.threads) : 1;
    if (static_cast<int>(slots_.size()) != 4 * threads) {
      slots_.assign(4 * static_cast<size_t>(threads), PlaneSlot<Real>{});
      for (auto& s : slots_) s.reserve(plane_nodes_);
    }
#pragma omp parallel num_threads(threads) if (threads > 1)
    {
      for (PmlBox<Real>& b : boxes_) sweep(b, ctx.fields);
    }
  }

 private:
  // The slab of element planes [p0, p1) of thread t of a team of `slabs` on a box.
  static void slab(const PmlBox<Real>& b, size_t t, size_t slabs, size_t& p0, size_t& p1) {
    p0 = b.planes * t / slabs;
    p1 = b.planes * (t + 1) / slabs;
  }

  // Where node plane q of a box lives during the sweep: the first plane of every slab but the first is
  // shared with the slab before (slot 2 t + 1 of... see slotOf), the others alternate between the two
  // ring slots of their slab's thread.
  PlaneSlot<Real>& slotOf(const PmlBox<Real>& b, size_t slabs, size_t q) {
    for (size_t t = slabs; t-- > 0;) {
      size_t p0, p1;
      slab(b, t, slabs, p0, p1);
      if (q == p0 && t > 0) return slots_[4 * t + 2];
      if (q >= p0) return slots_[4 * t + (q % 2)];
    }
    return slots_[q % 2];
  }

  // Pass A on node plane q: the differences of w along every edge that starts there, filtered by 1 / s_l
  // (memory psi), into the plane's grad slot.
  void planeGradients(PmlBox<Real>& b, const NodalFields<Real>& f, PlaneSlot<Real>& slot, size_t q) {
    const StructuredMesh& m = mesh_;
    const size_t gstep[3] = {1, m.nx + 1, (m.nx + 1) * (m.ny + 1)};
    RowGradientArgs<Real> a;
    a.n = b.ni + 1;
    a.inv_h[0] = static_cast<Real>(1.0 / m.hx);
    a.inv_h[1] = static_cast<Real>(1.0 / m.hy);
    for (int l = 0; l < 3; ++l) a.active[l] = b.edge_active[l];
    for (size_t r = 0; r <= b.rows; ++r) {
      const size_t j = b.rowJ(q, r), k = b.rowK(q, r);
      const size_t gbase = m.node(b.e.i0, b.e.j0 + j, b.e.k0 + k);
      const size_t lbase = b.local(0, j, k);
      const size_t sbase = (b.ni + 1) * r;
      a.inv_h[2] = k < b.nk ? b.inv_hz[k] : Real(0);
      // No edge of the box leaves its last node plane in y or z.
      a.has[0] = true;
      a.has[1] = j < b.nj;
      a.has[2] = k < b.nk;
      for (int l = 0; l < 3; ++l) {
        a.ea[l] = b.edge_a[l].data() + lbase;
        a.eb[l] = b.edge_b[l].data() + lbase;
        a.ec[l] = b.edge_c[l].data() + lbase;
        for (int c = 0; c < 3; ++c) {
          a.w0[c] = f.w[c] + gbase;
          a.w1[l * 3 + c] = f.w[c] + gbase + gstep[l];
          a.psi[l * 3 + c] = b.psi[l][c].data() + lbase;
          a.grad[l * 3 + c] = slot.grad[l * 3 + c].data() + sbase;
        }
      }
      rowGradients(a, stretch_);
    }
  }

  // Pass B on element plane p: every row of elements, gradients from the slots of node planes p, p + 1,
  // split forces into their split slots.
  void planeElements(PmlBox<Real>& b, PlaneSlot<Real>& lo, PlaneSlot<Real>& hi, size_t p) {
    PlaneSlot<Real>* pl[2] = {&lo, &hi};
    const size_t w = b.ni + 1;
    const Real* src[36];
    Real *near[36], *far[36];
    for (size_t r = 0; r < b.rows; ++r) {
      const size_t k = b.rowK(p, r);
      // Node at offsets (a, bb, e) along (x, y, z) of the element: (plane slot, row) for the sweep.
      auto plane = [&](size_t bb, size_t e) { return b.along_k ? e : bb; };
      auto row = [&](size_t bb, size_t e) { return (r + (b.along_k ? bb : e)) * w; };
      for (size_t s = 0; s < 4; ++s) {
        const size_t u = s & 1, v = s >> 1;
        for (size_t c = 0; c < 3; ++c) {
          // x-edges at (0, u, v), y-edges at (u, 0, v), z-edges at (u, v, 0).
          src[(0 * 3 + c) * 4 + s] = pl[plane(u, v)]->grad[0 * 3 + c].data() + row(u, v);
          src[(1 * 3 + c) * 4 + s] = pl[plane(0, v)]->grad[1 * 3 + c].data() + row(0, v) + u;
          src[(2 * 3 + c) * 4 + s] = pl[plane(v, 0)]->grad[2 * 3 + c].data() + row(v, 0) + u;
        }
        // For direction j, the node at the near end of slot s and the one a step further along j.
        for (size_t i = 0; i < 3; ++i) {
          const size_t qx = (0 * 3 + i) * 4 + s, qy = (1 * 3 + i) * 4 + s, qz = (2 * 3 + i) * 4 + s;
          near[qx] = pl[plane(u, v)]->split[i * 3 + 0].data() + row(u, v);
          far[qx] = near[qx] + 1;
          near[qy] = pl[plane(0, v)]->split[i * 3 + 1].data() + row(0, v) + u;
          far[qy] = pl[plane(1, v)]->split[i * 3 + 1].data() + row(1, v) + u;
          near[qz] = pl[plane(v, 0)]->split[i * 3 + 2].data() + row(v, 0) + u;
          far[qz] = pl[plane(v, 1)]->split[i * 3 + 2].data() + row(v, 1) + u;
        }
      }
      rowForces(src, near, far, b.ni, b.lam[k], b.mu[k], b.wx[k], b.wy[k], b.wz[k]);
    }
  }

  // Pass C on node plane q: the split forces filtered by 1 / s_j at the node (memory phi), summed into the
  // solver's forces; the slot's split forces cleared for its next plane.
  void planeForces(PmlBox<Real>& b, NodalFields<Real>& f, PlaneSlot<Real>& slot, size_t q) {
    const StructuredMesh& m = mesh_;
    RowNodalArgs<Real> a;
    a.n = b.ni + 1;
    for (int j = 0; j < 3; ++j) a.active[j] = b.node_active[j];
    for (size_t r = 0; r <= b.rows; ++r) {
      const size_t j = b.rowJ(q, r), k = b.rowK(q, r);
      const size_t gbase = m.node(b.e.i0, b.e.j0 + j, b.e.k0 + k);
      const size_t lbase = b.local(0, j, k);
      const size_t sbase = a.n * r;
      for (int i = 0; i < 3; ++i) {
        a.f[i] = f.f[i] + gbase;
        a.na[i] = b.node_a[i].data() + lbase;
        a.nb[i] = b.node_b[i].data() + lbase;
        a.nc[i] = b.node_c[i].data() + lbase;
        for (int jd = 0; jd < 3; ++jd) {
          a.split[i * 3 + jd] = slot.split[i * 3 + jd].data() + sbase;
          a.phi[i * 3 + jd] = b.phi[i][jd].data() + lbase;
        }
      }
      rowNodal(a, stretch_);
    }
  }

  // One box, inside the parallel region: each thread sweeps its slab of element planes (static split,
  // at least 2 planes each), computing the gradients of a node plane just before the elements need them
  // and filtering a node plane's forces as soon as both element planes around it are done, so that the
  // temporaries stay in cache. A slab's last element plane waits for a barrier (its upper node plane is
  // the next slab's first, whose gradients that slab computes and whose forces it starts), then the slab
  // finishes its last two node planes. The order of every sum depends only on the thread count.
  void sweep(PmlBox<Real>& b, NodalFields<Real>& f) {
    const size_t team = static_cast<size_t>(omp_get_num_threads());
    const size_t slabs = std::max<size_t>(1, std::min(team, b.planes / 2));
    const size_t t = static_cast<size_t>(omp_get_thread_num());
    size_t p0 = 0, p1 = 0;
    if (t < slabs) slab(b, t, slabs, p0, p1);
    const bool last = t + 1 == slabs;
    if (t < slabs) {
      planeGradients(b, f, slotOf(b, slabs, p0), p0);
      for (size_t p = p0; p + 1 < p1; ++p) {
        planeGradients(b, f, slotOf(b, slabs, p + 1), p + 1);
        planeElements(b, slotOf(b, slabs, p), slotOf(b, slabs, p + 1), p);
        if (p > p0 || t == 0) planeForces(b, f, slotOf(b, slabs, p), p);
      }
      if (last) planeGradients(b, f, slotOf(b, slabs, p1), p1);
    }
#pragma omp barrier
    if (t < slabs) {
      planeElements(b, slotOf(b, slabs, p1 - 1), slotOf(b, slabs, p1), p1 - 1);
      if (p1 - 1 > p0 || t == 0) planeForces(b, f, slotOf(b, slabs, p1 - 1), p1 - 1);
      planeForces(b, f, slotOf(b, slabs, p1), p1);
    }
#pragma omp barrier
  }

  // The recursive-convolution coefficients for the step dt: edges at their midpoints, nodes at the nodes.
  void setCoefficients(double dt) {
    const StructuredMesh& m = mesh_;
    stretch_ = false;
    for (PmlBox<Real>& b : boxes_) {
      for (int l = 0; l < 3; ++l) b.edge_active[l] = b.node_active[l] = false;
      for (size_t k = 0; k <= b.nk; ++k) {
        for (size_t j = 0; j <= b.nj; ++j) {
          for (size_t i = 0; i <= b.ni; ++i) {
            const size_t gi = b.e.i0 + i, gj = b.e.j0 + j, gk = b.e.k0 + k;
            const double node_s[3] = {layout_.sx(m, m.x(gi)), layout_.sy(m, m.y(gj)), layout_.sz(m, m.z[gk])};
            const size_t n = b.local(i, j, k);
            for (int l = 0; l < 3; ++l) {
              const PmlProfile::Coefficients cn = profile_.at(l, node_s, dt);
              b.node_a[l][n] = static_cast<Real>(cn.a);
              b.node_b[l][n] = static_cast<Real>(cn.b);
              b.node_c[l][n] = static_cast<Real>(cn.c);
              b.node_active[l] = b.node_active[l] || !cn.identity();
              stretch_ = stretch_ || cn.c != 1.0;
              // The edge of direction l from this node, if the box has it: d at its midpoint.
              const bool exists = (l == 0 && i < b.ni) || (l == 1 && j < b.nj) || (l == 2 && k < b.nk);
              if (!exists) continue;
              double edge_s[3] = {node_s[0], node_s[1], node_s[2]};
              if (l == 0) edge_s[0] = layout_.sx(m, m.x(gi) + 0.5 * m.hx);
              if (l == 1) edge_s[1] = layout_.sy(m, m.y(gj) + 0.5 * m.hy);
              if (l == 2) edge_s[2] = layout_.sz(m, 0.5 * (m.z[gk] + m.z[gk + 1]));
              const PmlProfile::Coefficients ce = profile_.at(l, edge_s, dt);
              b.edge_a[l][n] = static_cast<Real>(ce.a);
              b.edge_b[l][n] = static_cast<Real>(ce.b);
              b.edge_c[l][n] = static_cast<Real>(ce.c);
              b.edge_active[l] = b.edge_active[l] || !ce.identity();
              stretch_ = stretch_ || ce.c != 1.0;
            }
          }
        }
      }
    }
    dt_s_ = dt;
  }

  const StructuredMesh& mesh_;
  PmlLayout layout_;
  PmlProfile profile_;
  std::vector<PmlBox<Real>> boxes_;
  std::vector<PlaneSlot<Real>> slots_;  // per thread: 2 ring slots, the shared first plane of its slab, spare
  size_t elements_ = 0, plane_nodes_ = 0;
  bool stretch_ = false;  // kappa != 1 somewhere
  double dt_s_ = -1.0;
};

double largestVp(const StructuredMesh& m) {
  double c = 0.0;
  for (size_t k = 0; k < m.nz; ++k) c = std::max(c, m.levelMaterial(k).vp());
  return c;
}

class Pml final : public SoilBoundary {
 public:
  explicit Pml(const PmlSpec& spec) : spec_(spec) {}

  BoundaryMethod method() const override { return BoundaryMethod::Pml; }
  double zoneThicknessM() const override { return spec_.thickness_m; }
  bool zoneAlongBottom() const override { return spec_.bottom; }
  bool zoneTakesLoads() const override { return false; }

  ElementBox kernelElements(const BoundaryContext& ctx) const override {
    return pmlLayout(*ctx.mesh, ctx.faces, spec_).interior;
  }

  // Dashpots at the outer faces of the layer (if wanted) and on absorbing faces the layer does not cover.
  void addNodalDamping(const BoundaryContext& ctx, std::vector<double> c[3]) const override {
    AbsorbingFaces f = ctx.faces;
    if (!spec_.outer_dashpots) {
      f.x_min = f.x_max = f.y_min = f.y_max = false;
      f.bottom = f.bottom && !spec_.bottom;
    }
    addLysmerDashpots(*ctx.mesh, f, c);
  }

  std::unique_ptr<SolverUnit<float>> makeUnitFloat(const BoundaryContext& ctx) const override {
    return make<float>(ctx);
  }
  std::unique_ptr<SolverUnit<double>> makeUnitDouble(const BoundaryContext& ctx) const override {
    return make<double>(ctx);
  }

  nlohmann::json summary() const override {
    return {{"method", "pml"},
            {"thickness_m", spec_.thickness_m},
            {"reflection_coefficient", spec_.reflection_coefficient},
            {"exponent", spec_.exponent},
            {"max_kappa", spec_.max_kappa},
            {"alpha_1_s", spec_.alpha_1_s},
            {"perpendicular_ratio", spec_.perpendicular_ratio},
            {"bottom", spec_.bottom},
            {"outer_dashpots", spec_.outer_dashpots}};
  }

 private:
  template <class Real>
  std::unique_ptr<SolverUnit<Real>> make(const BoundaryContext& ctx) const {
    const PmlLayout layout = pmlLayout(*ctx.mesh, ctx.faces, spec_);
    if (layout.boxes.empty()) return nullptr;
    return std::make_unique<PmlUnit<Real>>(*ctx.mesh, layout, PmlProfile(spec_, layout, largestVp(*ctx.mesh)));
  }
  PmlSpec spec_;
};

}  // namespace

std::unique_ptr<SoilBoundary> makePml(const PmlSpec& spec) { return std::make_unique<Pml>(spec); }

}  // namespace railvib::soil
