// railvib/track: LU factorisation of a track's complex dynamic stiffness
// D(w) = K - w^2 M + i w C, for frequency sweeps (receptance, transmissibility,
// wheel impedance): the sparsity pattern is analysed once, each frequency is
// factorised and solved.
//
// The factorisation is UMFPACK's (T. A. Davis, "Algorithm 832: UMFPACK V4.3,
// an unsymmetric-pattern multifrontal method", ACM TOMS 30(2), 2004), through
// Eigen's wrapper, kept behind this one class: a precompiled library call
// instead of a templated solver instantiated in every file that sweeps.
#pragma once

#include <Eigen/Core>
#include <Eigen/SparseCore>
#include <complex>
#include <memory>

namespace railvib::track {

class DynamicStiffnessLu {
 public:
  using Matrix = Eigen::SparseMatrix<std::complex<double>>;

  DynamicStiffnessLu();
  ~DynamicStiffnessLu();
  DynamicStiffnessLu(const DynamicStiffnessLu&) = delete;
  DynamicStiffnessLu& operator=(const DynamicStiffnessLu&) = delete;

  /// Factorises d (square; a copy is kept, compressed, for the solves). The first call analyses the
  /// pattern, which later calls must share (same nonzero structure; checked by size and nonzero count).
  /// Throws std::runtime_error naming `what` if d is singular or not square, or the pattern changed.
  void factorize(const Matrix& d, const char* what);

  /// x = D^{-1} b for the last factorised D (one column or several).
  Eigen::VectorXcd solve(const Eigen::VectorXcd& b) const;
  Eigen::MatrixXcd solve(const Eigen::MatrixXcd& b) const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace railvib::track
