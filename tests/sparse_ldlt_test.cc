// SparseLdlt (sparse_ldlt.h) on Schur patterns of chains, trees and loops, against Eigen's dense LDL^T:
//   - the solution of S x = b, for random symmetric positive definite S with the pattern, to 1e-12 relative, and of
//     four right-hand sides at once the same as of each alone, to the bit;
//   - the pivots D equal those of the dense factorization of P S P^T (the same matrix, the same order);
//   - a chain's factor has no fill (one entry of L per row), a closed loop some;
//   - a zero pivot is refused, and so is a non-finite entry anywhere (it reaches a pivot: SchurSolver relies on
//     that), and the next factorization is unaffected;
//   - the same for joints' blocks of 1 to 7 rows (supernodes, cut where wider than six columns);
//   - a binary tree of 5000 rows, whose breadth-first order from the root would fill L almost densely, is analysed
//     in its minimum-degree order with little fill;
//   - a hub's rows (a star) form one dense block, factored in pieces with the same result, and kAuto factors such a
//     block densely (schur_solver.h);
//   - S stored in its factorization's order (SchurSolver::StoreInFactorOrder) is the same matrix: assembled,
//   multiplied,
//     ordered and factored, it gives every number of the first storage to the bit.
#include "tether/dynamics/solvers/sparse_ldlt.h"

#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>
#include <random>
#include <utility>
#include <vector>

#include "tether/dynamics/solvers/schur_solver.h"

namespace tether {
namespace {

constexpr double kAgreement = 1e-12;

// A pattern of rows between the given body pairs (kWorld allowed), rows_each rows each (a joint's).
SchurPattern PatternOf(const std::vector<std::pair<int, int>>& links, int bodies, int rows_each = 1) {
  std::vector<RowInfo> infos;
  for (const auto& [a, b] : links) {
    for (int r = 0; r < rows_each; ++r) infos.push_back({static_cast<int>(infos.size()), a, b});
  }
  return SchurPattern(infos, bodies);
}

std::vector<std::pair<int, int>> Chain(int n) {
  std::vector<std::pair<int, int>> links;
  for (int k = 0; k < n; ++k) links.push_back({k - 1, k});  // body -1 is the world
  return links;
}

// A binary tree of particles hanging from the world: body k hangs from body (k - 1) / 2.
std::vector<std::pair<int, int>> Tree(int n) {
  std::vector<std::pair<int, int>> links{{kWorld, 0}};
  for (int k = 1; k < n; ++k) links.push_back({(k - 1) / 2, k});
  return links;
}

// A ring of n bodies with spokes to a hub (body n): loops everywhere.
std::vector<std::pair<int, int>> Wheel(int n) {
  std::vector<std::pair<int, int>> links;
  for (int k = 0; k < n; ++k) {
    links.push_back({k, (k + 1) % n});
    links.push_back({k, n});
  }
  links.push_back({kWorld, n});
  return links;
}

// n bodies each held to a hub (body n) by one row: every pair of rows shares the hub.
std::vector<std::pair<int, int>> Star(int n) {
  std::vector<std::pair<int, int>> links;
  for (int k = 0; k < n; ++k) links.push_back({n, k});
  return links;
}

// Random values with the pattern, diagonally dominant (so positive definite).
std::vector<double> RandomValues(const SchurPattern& pattern, unsigned seed) {
  std::mt19937 random(seed);
  std::uniform_real_distribution<double> unit(-1.0, 1.0);
  std::vector<double> values(pattern.nonzeros());
  std::vector<double> dominance(pattern.size(), 1.0);
  for (int k = 0; k < pattern.nonzeros(); ++k) {
    const int i = pattern.row_index()[k], j = pattern.column_index()[k];
    if (i == j) continue;
    values[k] = unit(random);
    dominance[i] += std::abs(values[k]);
    dominance[j] += std::abs(values[k]);
  }
  for (int i = 0; i < pattern.size(); ++i) values[pattern.diagonal()[i]] = dominance[i];
  return values;
}

Eigen::MatrixXd Dense(const SchurPattern& pattern, const std::vector<double>& values) {
  Eigen::MatrixXd s = Eigen::MatrixXd::Zero(pattern.size(), pattern.size());
  for (int k = 0; k < pattern.nonzeros(); ++k) {
    s(pattern.row_index()[k], pattern.column_index()[k]) = values[k];
    s(pattern.column_index()[k], pattern.row_index()[k]) = values[k];
  }
  return s;
}

void ExpectAgreesWithDense(const SchurPattern& pattern, unsigned seed) {
  const std::vector<double> values = RandomValues(pattern, seed);
  const Eigen::MatrixXd s = Dense(pattern, values);
  SparseLdlt ldlt(pattern);
  ASSERT_TRUE(ldlt.Factor(values));

  const Eigen::VectorXd b = Eigen::VectorXd::LinSpaced(pattern.size(), -1.0, 2.0);
  Eigen::VectorXd x = b;
  ldlt.SolveInPlace(&x);
  const Eigen::VectorXd expected = s.ldlt().solve(b);
  EXPECT_LE((x - expected).cwiseAbs().maxCoeff(), kAgreement * expected.cwiseAbs().maxCoeff());
  // four right-hand sides side by side (a Jet's derivative parts) give the four single solves to the bit
  Eigen::Matrix<double, Eigen::Dynamic, 4, Eigen::RowMajor> columns(pattern.size(), 4);
  for (int c = 0; c < 4; ++c) columns.col(c) = b.array().sin() * (c + 1.0) - c;
  Eigen::Matrix<double, Eigen::Dynamic, 4, Eigen::RowMajor> each = columns;
  ldlt.SolveInPlace(&columns);
  for (int c = 0; c < 4; ++c) {
    Eigen::VectorXd column = each.col(c);
    ldlt.SolveInPlace(&column);
    EXPECT_TRUE((columns.col(c).array() == column.array()).all()) << "column " << c;
  }

  // P S P^T in the factorization's order, factored densely without pivoting (Cholesky: D = diag(L)^2)
  const int n = pattern.size();
  Eigen::MatrixXd permuted(n, n);
  for (int a = 0; a < n; ++a) {
    for (int c = 0; c < n; ++c) permuted(a, c) = s(ldlt.order()[a], ldlt.order()[c]);
  }
  const Eigen::VectorXd pivots = permuted.llt().matrixLLT().diagonal().cwiseAbs2();
  for (int k = 0; k < n; ++k) EXPECT_NEAR(ldlt.pivots()[k], pivots[k], kAgreement * pivots[k]) << "pivot " << k;
}

TEST(SparseLdlt, SolvesChainsTreesAndLoopsAsTheDenseFactorizationDoes) {
  ExpectAgreesWithDense(PatternOf(Chain(50), 50), 1);
  ExpectAgreesWithDense(PatternOf(Tree(63), 63), 2);
  ExpectAgreesWithDense(PatternOf(Wheel(20), 21), 3);
  ExpectAgreesWithDense(PatternOf({{kWorld, 0}}, 1), 4);
}

// Joints of 1 to 7 rows: each joint's rows are a dense block, factored as supernodes of up to six columns (a
// chain's last two joints make one of ten, cut in two; a 7-row joint's block is cut too).
TEST(SparseLdlt, SolvesJointsRowBlocksAsTheDenseFactorizationDoes) {
  for (int rows_each = 1; rows_each <= 7; ++rows_each) {
    SCOPED_TRACE(rows_each);
    ExpectAgreesWithDense(PatternOf(Chain(10), 10, rows_each), 10 + rows_each);
    ExpectAgreesWithDense(PatternOf(Tree(14), 14, rows_each), 20 + rows_each);
    ExpectAgreesWithDense(PatternOf(Wheel(6), 7, rows_each), 30 + rows_each);
  }
}

TEST(SparseLdlt, AChainFactorsWithoutFillAndALoopWithSome) {
  const SparseLdlt chain(PatternOf(Chain(100), 100));
  EXPECT_EQ(chain.nonzeros(), 99);  // S and L are both tridiagonal
  const SchurPattern wheel = PatternOf(Wheel(20), 21);
  const int below_diagonal = wheel.nonzeros() - wheel.size();
  EXPECT_GT(SparseLdlt(wheel).nonzeros(), below_diagonal);
}

TEST(SparseLdlt, RefusesZeroAndNonFinitePivotsAndRecovers) {
  const SchurPattern pattern = PatternOf(Tree(15), 15);
  SparseLdlt ldlt(pattern);
  EXPECT_FALSE(ldlt.Factor(std::vector<double>(pattern.nonzeros(), 0.0)));
  std::vector<double> broken = RandomValues(pattern, 5);
  broken[pattern.diagonal()[ldlt.order()[pattern.size() - 1]]] = std::nan("");  // the last pivot
  EXPECT_FALSE(ldlt.Factor(broken));
  const std::vector<double> values = RandomValues(pattern, 6);
  ASSERT_TRUE(ldlt.Factor(values));
  const Eigen::VectorXd ones = Eigen::VectorXd::Ones(pattern.size());
  Eigen::VectorXd x = ones;
  ldlt.SolveInPlace(&x);
  EXPECT_LE((Dense(pattern, values) * x - ones).cwiseAbs().maxCoeff(), kAgreement);
}

TEST(SparseLdlt, RefusesANonFiniteEntryBelowTheDiagonal) {
  const double infinity = std::numeric_limits<double>::infinity();
  for (const SchurPattern& pattern : {PatternOf(Wheel(10), 11), PatternOf(Tree(6), 6, 5)}) {
    SparseLdlt ldlt(pattern);
    for (double bad : {std::nan(""), infinity, -infinity}) {
      for (int k = 0; k < pattern.nonzeros(); ++k) {
        if (pattern.row_index()[k] == pattern.column_index()[k]) continue;
        std::vector<double> values = RandomValues(pattern, 7);
        values[k] = bad;
        EXPECT_FALSE(ldlt.Factor(values)) << "entry " << k << " = " << bad;
      }
    }
  }
}

TEST(SparseLdlt, ABigBinaryTreeKeepsAnOrderWithLittleFill) {
  const SchurPattern pattern = PatternOf(Tree(5000), 5000);
  SparseLdlt ldlt(pattern);
  // little fill (29% over S's 7498 entries below the diagonal; the breadth-first order would have millions)
  EXPECT_LT(ldlt.nonzeros(), 1.5 * (pattern.nonzeros() - pattern.size()));
  const std::vector<double> values = RandomValues(pattern, 8);
  ASSERT_TRUE(ldlt.Factor(values));
  const Eigen::VectorXd ones = Eigen::VectorXd::Ones(pattern.size());
  Eigen::VectorXd x = ones;
  ldlt.SolveInPlace(&x);
  Eigen::VectorXd product;  // S x, from its lower triangle (a dense S would take 200 MB)
  MultiplySymmetric(pattern, values, x, &product);
  EXPECT_LE((product - ones).cwiseAbs().maxCoeff(), kAgreement);
}

TEST(SparseLdlt, AHubsDenseBlockIsFactoredInPiecesOfItsColumns) {
  const SchurPattern pattern = PatternOf(Star(400), 401);
  const SparseLdlt ldlt(pattern);
  EXPECT_EQ(ldlt.nonzeros(), 400 * 399 / 2);  // dense below the diagonal: one supernode of 400 columns
  EXPECT_EQ(ldlt.updates(), std::int64_t{400} * 401 * 399 / 6);
  ExpectAgreesWithDense(pattern, 9);
  // 700 rows: the entries its pieces update would be a list of 9.4 million, past sparse_ldlt.cc's bound, so the
  // factorization finds them as it goes, with the same result
  ExpectAgreesWithDense(PatternOf(Star(700), 701), 10);
}

TEST(SparseLdlt, AutoFactorsAHubsDenseBlockDenselyAndAChainSparsely) {
  EXPECT_EQ(SchurSolver(PatternOf(Star(kDenseBlockRows), kDenseBlockRows + 1), KktSolver::kAuto).kind(),
            KktSolver::kDense);
  EXPECT_EQ(SchurSolver(PatternOf(Star(kDenseBlockRows - 1), kDenseBlockRows), KktSolver::kAuto).kind(),
            KktSolver::kSparse);  // small blocks stay on the path tuned for them
  EXPECT_EQ(SchurSolver(PatternOf(Chain(5000), 5000), KktSolver::kAuto).kind(), KktSolver::kSparse);
  EXPECT_EQ(SchurSolver(PatternOf(Star(300), 301), KktSolver::kSparse).kind(), KktSolver::kSparse);  // as asked
}

// 3D bodies in a chain, each held to the previous one by a joint of five rows with random Jacobian blocks: the
// assembly's dense per-body products (schur_system.h).
struct RigidChain {
  explicit RigidChain(int bodies) {
    std::mt19937 random(11);
    std::uniform_real_distribution<double> unit(-1.0, 1.0);
    for (int k = 0; k < bodies; ++k) {
      layout.push_back({BodyKind::kRigid3d, 6 * k});
      const Eigen::Matrix3d a = Eigen::Matrix3d::NullaryExpr([&] { return unit(random); });
      inverse_rotational.push_back(a * a.transpose() + Eigen::Matrix3d::Identity());
      for (int r = 0; r < 5; ++r) infos.push_back({static_cast<int>(infos.size()), k - 1, k});
    }
    inverse_diagonal = Eigen::VectorXd::NullaryExpr(6 * bodies, [&] { return 1.5 + unit(random); });
    rows.resize(infos.size());
    for (size_t i = 0; i < infos.size(); ++i) {
      for (BodyVector<double>* block : {&rows[i].a, &rows[i].b}) {
        block->translation = Eigen::Vector3d::NullaryExpr([&] { return unit(random); });
        block->rotation = Eigen::Vector3d::NullaryExpr([&] { return unit(random); });
      }
    }
  }
  std::vector<double> Assemble(const SchurPattern& pattern) const {
    std::vector<double> scratch, values(pattern.nonzeros());
    AssembleSchur(layout, pattern, rows, inverse_diagonal, inverse_rotational, &scratch, &values);
    return values;
  }
  std::vector<BodyLayout> layout;
  std::vector<RowInfo> infos;
  std::vector<ConstraintRow<double>> rows;
  Eigen::VectorXd inverse_diagonal;
  std::vector<Eigen::Matrix3d> inverse_rotational;
};

void ExpectFactorOrderChangesNothing(const SchurPattern& pattern, const std::vector<double>& values) {
  SCOPED_TRACE(pattern.size());
  SparseLdlt first(pattern);
  SchurPattern stored = pattern;
  SparseLdlt ldlt(stored);
  const std::vector<int> position = ldlt.FactorOrder();
  stored.StoreValuesAt(position);
  ldlt.StoreValuesAt(position);
  std::vector<double> moved(values.size());
  for (size_t v = 0; v < values.size(); ++v) moved[position[v]] = values[v];
  EXPECT_EQ(Dense(stored, moved), Dense(pattern, values));
  for (int i = 0; i < pattern.size(); ++i) EXPECT_EQ(moved[stored.diagonal()[i]], values[pattern.diagonal()[i]]);

  const Eigen::VectorXd b = Eigen::VectorXd::LinSpaced(pattern.size(), -1.0, 2.0);
  Eigen::VectorXd product, moved_product;
  MultiplySymmetric(pattern, values, b, &product);
  MultiplySymmetric(stored, moved, b, &moved_product);
  EXPECT_EQ(moved_product, product);

  ASSERT_TRUE(first.Factor(values));
  ASSERT_TRUE(ldlt.Factor(moved));
  EXPECT_EQ(ldlt.pivots(), first.pivots());
  Eigen::VectorXd x = b, moved_x = b;
  first.SolveInPlace(&x);
  ldlt.SolveInPlace(&moved_x);
  EXPECT_EQ(moved_x, x);
  // the stored pattern analysed afresh orders its rows as the first did (the order does not read the storage),
  // and so does one stored in a random order
  SparseLdlt fresh(stored);
  EXPECT_EQ(fresh.order(), first.order());
  ASSERT_TRUE(fresh.Factor(moved));
  EXPECT_EQ(fresh.pivots(), first.pivots());
  std::vector<int> shuffle(values.size());
  std::iota(shuffle.begin(), shuffle.end(), 0);
  std::shuffle(shuffle.begin(), shuffle.end(), std::mt19937(13));
  SchurPattern shuffled = pattern;
  shuffled.StoreValuesAt(shuffle);
  EXPECT_EQ(SparseLdlt(shuffled).order(), first.order());
}

TEST(SparseLdlt, SStoredInItsFactorOrderIsTheSameMatrix) {
  for (const SchurPattern& pattern : {PatternOf(Chain(50), 50), PatternOf(Tree(63), 63, 3), PatternOf(Wheel(20), 21),
                                      PatternOf(Star(30), 31), PatternOf(Chain(10), 10, 5)}) {
    ExpectFactorOrderChangesNothing(pattern, RandomValues(pattern, 12));
  }
  // the dense products of 3D bodies write to the moved entries
  const RigidChain chain(10);
  const SchurPattern pattern(chain.infos, chain.layout);
  SchurPattern stored = pattern;
  SchurSolver solver(stored, KktSolver::kSparse);
  const std::vector<int> position = SparseLdlt(pattern).FactorOrder();
  solver.StoreInFactorOrder(&stored);
  const std::vector<double> values = chain.Assemble(pattern), moved = chain.Assemble(stored);
  for (size_t v = 0; v < values.size(); ++v) EXPECT_EQ(moved[position[v]], values[v]) << "value " << v;
  ExpectFactorOrderChangesNothing(pattern, values);
}

}  // namespace
}  // namespace tether
