// railvib/soil (internal): a sparse LDL^T whose solves run on two threads.
//
// The implicit inclusions' solve (implicit_unit.hpp) is one forward and one backward substitution per
// soil step, while the solver's other thread would wait. Ordered by one level of nested dissection
// (George 1973) -- two parts that share no matrix entry, then their separator -- the factor of each
// part only reaches its own rows and the separator's, so the two parts substitute concurrently: forward,
// each part's columns with their updates of the separator's rows kept apart and added in a fixed order,
// then the separator's columns; backward, the separator first, then the parts. Within each part and
// the separator the fill-reducing order is CHOLMOD's (AMD or METIS, whichever fills less). The
// arithmetic does not depend on the thread count.
#pragma once

#include <Eigen/Sparse>
#include <vector>

namespace railvib::soil {

class SplitLdlt {
 public:
  /// `a`: symmetric positive definite (both triangles or the lower one stored); `part[i]` 0 or 1 for the
  /// two parts, 2 for the separator: no entry of `a` may couple part 0 to part 1. Returns false when the
  /// factorisation fails or the matrix is not positive definite.
  bool factor(const Eigen::SparseMatrix<double>& a, const std::vector<int>& part);
  /// x <- A^{-1} x, on two threads when `threads` >= 2 (the same arithmetic either way).
  void solveInPlace(Eigen::VectorXd& x, int threads) const;

  long factorNonZeros() const { return static_cast<long>(row_.size()); }
  /// Unknowns in part 0, part 1 and the separator.
  long partSize(int p) const { return p == 0 ? n0_ : p == 1 ? n1_ : n_ - n0_ - n1_; }

 private:
  void forwardPart(double* y, long begin, long end, double* separator_update) const;
  void backwardPart(double* y, long begin, long end) const;

  long n_ = 0, n0_ = 0, n1_ = 0;
  std::vector<int> order_;  // position -> unknown
  // Strictly lower part of the unit L by columns (CSC) and D.
  std::vector<long> col_ptr_;
  std::vector<int> row_;
  std::vector<double> value_, inv_d_;
  mutable std::vector<double> work_, update0_, update1_;
};

}  // namespace railvib::soil
