#include "railvib/track/dynamic_stiffness_lu.hpp"

#include <Eigen/UmfPackSupport>
#include <stdexcept>
#include <string>

namespace railvib::track {

struct DynamicStiffnessLu::Impl {
  // Eigen's wrapper keeps a reference to the factorised matrix and hands it to every UMFPACK solve
  // (which reads it for iterative refinement): the matrix is held here, not left to the caller's
  // temporary.
  Matrix matrix;
  Eigen::UmfPackLU<Matrix> lu;
  Eigen::Index rows = -1;
  Eigen::Index nonzeros = -1;
  bool factorised = false;
};

DynamicStiffnessLu::DynamicStiffnessLu() : impl_(std::make_unique<Impl>()) {
  // No iterative refinement: a dynamic stiffness away from its singular frequencies is well conditioned,
  // and the direct solve agrees with a dense LU to round-off (test
  // TrackReceptance.DynamicStiffnessLuSolvesADampedChain).
  impl_->lu.umfpackControl()(UMFPACK_IRSTEP) = 0;
}
DynamicStiffnessLu::~DynamicStiffnessLu() = default;

void DynamicStiffnessLu::factorize(const Matrix& d, const char* what) {
  if (d.rows() != d.cols() || d.rows() == 0) {
    throw std::runtime_error(std::string(what) + ": the dynamic stiffness is not a square, non-empty matrix");
  }
  impl_->factorised = false;
  if (impl_->rows >= 0 && (d.rows() != impl_->rows || d.nonZeros() != impl_->nonzeros)) {
    throw std::runtime_error(std::string(what) + ": the dynamic stiffness changed its sparsity pattern");
  }
  impl_->matrix = d;
  impl_->matrix.makeCompressed();
  if (impl_->rows < 0) {
    impl_->lu.analyzePattern(impl_->matrix);
    impl_->rows = d.rows();
    impl_->nonzeros = d.nonZeros();
  }
  if (impl_->lu.info() == Eigen::Success) impl_->lu.factorize(impl_->matrix);
  if (impl_->lu.info() != Eigen::Success) {
    throw std::runtime_error(std::string(what) +
                             ": factorisation failed (UMFPACK: a singular dynamic stiffness, or out of memory)");
  }
  impl_->factorised = true;
}

Eigen::VectorXcd DynamicStiffnessLu::solve(const Eigen::VectorXcd& b) const {
  if (!impl_->factorised || b.size() != impl_->rows)
    throw std::logic_error("DynamicStiffnessLu: no factorisation, or a right-hand side of another size");
  return impl_->lu.solve(b);
}

Eigen::MatrixXcd DynamicStiffnessLu::solve(const Eigen::MatrixXcd& b) const {
  if (!impl_->factorised || b.rows() != impl_->rows)
    throw std::logic_error("DynamicStiffnessLu: no factorisation, or a right-hand side of another size");
  return impl_->lu.solve(b);
}

}  // namespace railvib::track
