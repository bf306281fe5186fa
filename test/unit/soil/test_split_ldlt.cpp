// The implicit inclusions' factor (src/soil/split_ldlt.hpp): its two-thread substitutions solve the
// system as a plain sparse LDL^T does, with the same arithmetic on one thread and on two.
#include <gtest/gtest.h>

#include <Eigen/SparseCholesky>
#include <cstring>
#include <random>
#include <stdexcept>
#include <vector>

#include "../../../src/soil/split_ldlt.hpp"

using railvib::soil::SplitLdlt;

namespace {

// M/dt + dt/4 K of a plate: a 5-point Laplacian with 2 unknowns per node, coupled, on nx x ny nodes.
Eigen::SparseMatrix<double> plate(int nx, int ny) {
  std::vector<Eigen::Triplet<double>> t;
  auto id = [&](int i, int j, int c) { return 2 * (i + nx * j) + c; };
  for (int j = 0; j < ny; ++j) {
    for (int i = 0; i < nx; ++i) {
      for (int c = 0; c < 2; ++c) {
        t.emplace_back(id(i, j, c), id(i, j, c), 4.5 + 0.3 * c);
        t.emplace_back(id(i, j, c), id(i, j, 1 - c), 0.4);
        if (i + 1 < nx)
          t.emplace_back(id(i, j, c), id(i + 1, j, c), -1.0), t.emplace_back(id(i + 1, j, c), id(i, j, c), -1.0);
        if (j + 1 < ny)
          t.emplace_back(id(i, j, c), id(i, j + 1, c), -1.0), t.emplace_back(id(i, j + 1, c), id(i, j, c), -1.0);
      }
    }
  }
  Eigen::SparseMatrix<double> a(2 * nx * ny, 2 * nx * ny);
  a.setFromTriplets(t.begin(), t.end());
  return a;
}

std::vector<int> columnSeparator(int nx, int ny, int i_separator) {
  std::vector<int> part(2 * static_cast<size_t>(nx * ny));
  for (int j = 0; j < ny; ++j)
    for (int i = 0; i < nx; ++i)
      for (int c = 0; c < 2; ++c) part[2 * (i + nx * j) + c] = i < i_separator ? 0 : i > i_separator ? 1 : 2;
  return part;
}

}  // namespace

TEST(SplitLdlt, SolvesAsAPlainLdltOnOneThreadAndTwo) {
  const int nx = 41, ny = 23;
  const Eigen::SparseMatrix<double> a = plate(nx, ny);
  SplitLdlt split;
  ASSERT_TRUE(split.factor(a, columnSeparator(nx, ny, 20)));
  EXPECT_EQ(split.partSize(0), 2 * 20 * ny);
  EXPECT_EQ(split.partSize(1), 2 * 20 * ny);
  EXPECT_EQ(split.partSize(2), 2 * ny);
  Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>> plain(a);
  std::mt19937 rng(7);
  std::normal_distribution<double> g;
  Eigen::VectorXd b(a.rows());
  for (long q = 0; q < b.size(); ++q) b[q] = g(rng);
  const Eigen::VectorXd reference = plain.solve(b);
  Eigen::VectorXd one = b, two = b;
  split.solveInPlace(one, 1);
  split.solveInPlace(two, 2);
  EXPECT_LT((one - reference).norm(), 1e-13 * reference.norm());
  EXPECT_LT((a * one - b).norm(), 1e-13 * b.norm());
  EXPECT_EQ(std::memcmp(one.data(), two.data(), sizeof(double) * static_cast<size_t>(one.size())), 0);
  // An empty separator (two separate plates) and a part left empty are both valid splits.
  ASSERT_TRUE(split.factor(a, columnSeparator(nx, ny, nx + 5)));
  Eigen::VectorXd all_in_one = b;
  split.solveInPlace(all_in_one, 2);
  EXPECT_LT((all_in_one - reference).norm(), 1e-13 * reference.norm());
}

TEST(SplitLdlt, RefusesCoupledPartsAndAnIndefiniteMatrix) {
  const int nx = 8, ny = 5;
  SplitLdlt split;
  std::vector<int> coupled(2 * nx * ny, 0);
  coupled[2 * 3 + 0] = 1;  // a node of part 1 among part 0's neighbours
  EXPECT_THROW(split.factor(plate(nx, ny), coupled), std::invalid_argument);
  Eigen::SparseMatrix<double> indefinite = plate(nx, ny);
  indefinite.coeffRef(5, 5) = -10.0;
  EXPECT_FALSE(split.factor(indefinite, columnSeparator(nx, ny, 4)));
}
