// railvib/soil: sparse LDL^T with two-thread substitutions (split_ldlt.hpp).
#include "split_ldlt.hpp"

#include <cholmod.h>

#include <Eigen/SparseCholesky>
#include <algorithm>
#include <stdexcept>

namespace railvib::soil {

namespace {

// Fill-reducing order of the unknowns `members` within `a` (their sub-matrix), appended to `order`:
// CHOLMOD's analysis, the best of AMD and METIS's nested dissection by the factor's fill (Chen, Davis,
// Hager & Rajamanickam, ACM TOMS 35, 2008).
void appendOrdering(const Eigen::SparseMatrix<double>& a, const std::vector<int>& members, std::vector<int>& order) {
  if (members.empty()) return;
  const size_t m = members.size();
  std::vector<int> local(static_cast<size_t>(a.rows()), -1);
  for (size_t q = 0; q < m; ++q) local[static_cast<size_t>(members[q])] = static_cast<int>(q);
  // The lower triangle's pattern, by columns.
  std::vector<std::vector<int>> rows(m);
  for (size_t q = 0; q < m; ++q) {
    for (Eigen::SparseMatrix<double>::InnerIterator it(a, members[q]); it; ++it) {
      const int r = local[static_cast<size_t>(it.row())];
      if (r >= static_cast<int>(q)) rows[q].push_back(r);
    }
    std::sort(rows[q].begin(), rows[q].end());
  }
  size_t nnz = 0;
  for (const auto& r : rows) nnz += r.size();
  cholmod_common cc;
  cholmod_start(&cc);
  cholmod_sparse* pattern = cholmod_allocate_sparse(m, m, nnz, 1, 1, -1, CHOLMOD_PATTERN, &cc);
  if (!pattern) {
    cholmod_finish(&cc);
    throw std::runtime_error("split LDL^T: CHOLMOD could not allocate the pattern");
  }
  int* cp = static_cast<int*>(pattern->p);
  int* ri = static_cast<int*>(pattern->i);
  cp[0] = 0;
  for (size_t q = 0; q < m; ++q) {
    std::copy(rows[q].begin(), rows[q].end(), ri + cp[q]);
    cp[q + 1] = cp[q] + static_cast<int>(rows[q].size());
  }
  cholmod_factor* symbolic = cholmod_analyze(pattern, &cc);
  if (!symbolic) {
    cholmod_free_sparse(&pattern, &cc);
    cholmod_finish(&cc);
    throw std::runtime_error("split LDL^T: CHOLMOD's analysis failed");
  }
  const int* perm = static_cast<const int*>(symbolic->Perm);  // position -> old index
  for (size_t q = 0; q < m; ++q) order.push_back(members[static_cast<size_t>(perm[q])]);
  cholmod_free_factor(&symbolic, &cc);
  cholmod_free_sparse(&pattern, &cc);
  cholmod_finish(&cc);
}

}  // namespace

bool SplitLdlt::factor(const Eigen::SparseMatrix<double>& a, const std::vector<int>& part) {
  n_ = a.rows();
  if (a.cols() != n_ || static_cast<long>(part.size()) != n_) {
    throw std::invalid_argument("split LDL^T: matrix and partition sizes differ");
  }
  std::vector<int> members[3];
  for (long i = 0; i < n_; ++i) {
    const int p = part[static_cast<size_t>(i)];
    if (p < 0 || p > 2) throw std::invalid_argument("split LDL^T: a part must be 0, 1 or 2");
    members[p].push_back(static_cast<int>(i));
  }
  for (long c = 0; c < n_; ++c) {
    for (Eigen::SparseMatrix<double>::InnerIterator it(a, c); it; ++it) {
      const int pr = part[static_cast<size_t>(it.row())], pc = part[static_cast<size_t>(c)];
      if (pr + pc == 1) throw std::invalid_argument("split LDL^T: the two parts are coupled (not a separator)");
    }
  }
  n0_ = static_cast<long>(members[0].size());
  n1_ = static_cast<long>(members[1].size());
  order_.clear();
  for (const auto& m : members) appendOrdering(a, m, order_);
  std::vector<int> position(static_cast<size_t>(n_));
  for (long q = 0; q < n_; ++q) position[static_cast<size_t>(order_[static_cast<size_t>(q)])] = static_cast<int>(q);

  // Lower triangle of P A P^T, factorised in that order: the parts' fill stays within the part and the
  // separator's rows.
  // (Memory: the triplets go before the factorisation, and L is read in place, not copied, into
  // arrays sized once; together they had doubled the Haren soil run's peak.)
  Eigen::SparseMatrix<double> permuted(n_, n_);
  {
    std::vector<Eigen::Triplet<double>> t;
    t.reserve(static_cast<size_t>(a.nonZeros()));
    for (long c = 0; c < n_; ++c) {
      for (Eigen::SparseMatrix<double>::InnerIterator it(a, c); it; ++it) {
        const int r = position[static_cast<size_t>(it.row())], pc = position[static_cast<size_t>(c)];
        if (r >= pc) t.emplace_back(r, pc, it.value());
      }
    }
    permuted.setFromTriplets(t.begin(), t.end());
  }
  Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>, Eigen::Lower, Eigen::NaturalOrdering<int>> ldlt;
  ldlt.compute(permuted);
  permuted.resize(0, 0);
  permuted.data().squeeze();
  if (ldlt.info() != Eigen::Success) return false;
  const Eigen::VectorXd d = ldlt.vectorD();
  if (!(d.size() == n_ && d.minCoeff() > 0.0)) return false;
  const Eigen::SparseMatrix<double>& l = ldlt.matrixL().nestedExpression();
  col_ptr_.assign(static_cast<size_t>(n_) + 1, 0);
  row_.clear();
  value_.clear();
  row_.reserve(static_cast<size_t>(l.nonZeros()));
  value_.reserve(static_cast<size_t>(l.nonZeros()));
  for (long j = 0; j < n_; ++j) {
    for (Eigen::SparseMatrix<double>::InnerIterator it(l, j); it; ++it) {
      if (it.row() <= j) continue;  // the unit diagonal
      row_.push_back(static_cast<int>(it.row()));
      value_.push_back(it.value());
    }
    col_ptr_[static_cast<size_t>(j) + 1] = static_cast<long>(row_.size());
  }
  inv_d_.resize(static_cast<size_t>(n_));
  for (long j = 0; j < n_; ++j) inv_d_[static_cast<size_t>(j)] = 1.0 / d[j];
  work_.assign(static_cast<size_t>(n_), 0.0);
  update0_.assign(static_cast<size_t>(n_ - n0_ - n1_), 0.0);
  update1_.assign(update0_.size(), 0.0);
  return true;
}

// L y = b over the columns [begin, end): rows inside the range in place, the separator's rows into
// `separator_update` (indexed from n0 + n1).
void SplitLdlt::forwardPart(double* y, long begin, long end, double* separator_update) const {
  const long s0 = n0_ + n1_;
  for (long j = begin; j < end; ++j) {
    const double yj = y[j];
    if (yj == 0.0) continue;
    for (long p = col_ptr_[static_cast<size_t>(j)]; p < col_ptr_[static_cast<size_t>(j) + 1]; ++p) {
      const long i = row_[static_cast<size_t>(p)];
      if (i < end) {
        y[i] -= value_[static_cast<size_t>(p)] * yj;
      } else {
        separator_update[i - s0] -= value_[static_cast<size_t>(p)] * yj;
      }
    }
  }
  for (long j = begin; j < end; ++j) y[j] *= inv_d_[static_cast<size_t>(j)];
}

// L^T x = y over the columns [begin, end), descending; every row read is final (inside the range,
// above it, or the separator's).
void SplitLdlt::backwardPart(double* y, long begin, long end) const {
  const int* row = row_.data();
  const double* value = value_.data();
  for (long j = end - 1; j >= begin; --j) {
    // Four partial sums: the gathers overlap instead of waiting on one chain of additions.
    double s0 = 0.0, s1 = 0.0, s2 = 0.0, s3 = 0.0;
    long p = col_ptr_[static_cast<size_t>(j)];
    const long last = col_ptr_[static_cast<size_t>(j) + 1];
    for (; p + 4 <= last; p += 4) {
      s0 += value[p] * y[row[p]];
      s1 += value[p + 1] * y[row[p + 1]];
      s2 += value[p + 2] * y[row[p + 2]];
      s3 += value[p + 3] * y[row[p + 3]];
    }
    for (; p < last; ++p) s0 += value[p] * y[row[p]];
    y[j] -= (s0 + s1) + (s2 + s3);
  }
}

void SplitLdlt::solveInPlace(Eigen::VectorXd& x, int threads) const {
  if (x.size() != n_) throw std::invalid_argument("split LDL^T: right-hand side of the wrong size");
  double* y = work_.data();
  for (long q = 0; q < n_; ++q) y[q] = x[order_[static_cast<size_t>(q)]];
  std::fill(update0_.begin(), update0_.end(), 0.0);
  std::fill(update1_.begin(), update1_.end(), 0.0);
  const long s0 = n0_ + n1_;
#pragma omp parallel sections num_threads(2) if (threads >= 2)
  {
#pragma omp section
    forwardPart(y, 0, n0_, update0_.data());
#pragma omp section
    forwardPart(y, n0_, s0, update1_.data());
  }
  for (long i = s0; i < n_; ++i) y[i] += update0_[static_cast<size_t>(i - s0)] + update1_[static_cast<size_t>(i - s0)];
  double* none = nullptr;
  forwardPart(y, s0, n_, none);
  backwardPart(y, s0, n_);
#pragma omp parallel sections num_threads(2) if (threads >= 2)
  {
#pragma omp section
    backwardPart(y, 0, n0_);
#pragma omp section
    backwardPart(y, n0_, s0);
  }
  for (long q = 0; q < n_; ++q) x[order_[static_cast<size_t>(q)]] = y[q];
}

}  // namespace railvib::soil
