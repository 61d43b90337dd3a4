// Sparse approximate inverses (multigrid/inverse_approximation.h) on distributed model matrices:
// exactness where the pattern allows it, ||A Â - I||_F decreasing as the pattern grows, the
// nonsymmetric case, and the SPAI smoother reducing the error of a model problem.
#include "inverse_approximation.h"

#include <TpetraExt_MatrixMatrix.hpp>
#include <Tpetra_Core.hpp>
#include <Tpetra_CrsMatrix.hpp>
#include <Tpetra_RowMatrixTransposer.hpp>
#include <Tpetra_MultiVector.hpp>
#include <gtest/gtest.h>

#include "test_helpers.h"

#include <cmath>

using namespace multigrid;

namespace
{
  /// 5-point stencil on an n x n grid, -Laplace + c * (first-order upwind convection in x),
  /// distributed by rows; c = 0 gives the symmetric Poisson matrix.
  Teuchos::RCP<TpetraMatrix> grid_matrix(int n, double convection)
  {
    auto map = Teuchos::rcp(new Tpetra::Map<LO, GO, NO>(static_cast<GO>(n) * n, 0, test_helpers::comm()));
    auto A   = Teuchos::rcp(new TpetraMatrix(map, 5));
    for (LO l = 0; l < static_cast<LO>(map->getNodeNumElements()); ++l)
      {
        const GO        row = map->getGlobalElement(l);
        const GO        i = row % n, j = row / n;
        std::vector<GO> cols{row};
        std::vector<SC> vals{4.0 + convection};
        auto            add = [&](GO c, double v) {
          cols.push_back(c);
          vals.push_back(v);
        };
        if (i > 0)
          add(row - 1, -1.0 - convection);
        if (i < n - 1)
          add(row + 1, -1.0);
        if (j > 0)
          add(row - n, -1.0);
        if (j < n - 1)
          add(row + n, -1.0);
        A->insertGlobalValues(row, Teuchos::ArrayView<const GO>(cols), Teuchos::ArrayView<const SC>(vals));
      }
    A->fillComplete();
    return A;
  }

  Teuchos::RCP<TpetraMatrix> diagonal_matrix(int n)
  {
    auto map = Teuchos::rcp(new Tpetra::Map<LO, GO, NO>(n, 0, test_helpers::comm()));
    auto A   = Teuchos::rcp(new TpetraMatrix(map, 1));
    for (LO l = 0; l < static_cast<LO>(map->getNodeNumElements()); ++l)
      {
        const GO row = map->getGlobalElement(l);
        A->insertGlobalValues(row, Teuchos::tuple<GO>(row), Teuchos::tuple<SC>(1.0 + row % 7));
      }
    A->fillComplete();
    return A;
  }

  InverseApproximationOptions options(const std::string& type, int power = 1, double drop = 0.0)
  {
    InverseApproximationOptions o;
    o.type           = type;
    o.pattern_power  = power;
    o.drop_tolerance = drop;
    return o;
  }
} // namespace

TEST(InverseApproximation, ExactForDiagonalMatrices)
{
  const auto A = diagonal_matrix(40);
  for (const std::string type : {"diagonal", "lumping", "spai"})
    EXPECT_LT(inverse_residual_norm(*A, *approximate_inverse(*A, options(type))), 1e-13) << type;
}

TEST(InverseApproximation, LargerPatternsApproximateBetter)
{
  for (const double convection : {0.0, 2.0}) // Poisson, and a nonsymmetric upwind operator
    {
      const auto   A        = grid_matrix(16, convection);
      const double diagonal = inverse_residual_norm(*A, *approximate_inverse(*A, options("diagonal")));
      const double lumped   = inverse_residual_norm(*A, *approximate_inverse(*A, options("lumping")));
      const auto   spai1    = approximate_inverse(*A, options("spai", 1));
      const double pattern1 = inverse_residual_norm(*A, *spai1);
      const double dropped  = inverse_residual_norm(*A, *approximate_inverse(*A, options("spai", 2, 0.08)));
      const double pattern2 = inverse_residual_norm(*A, *approximate_inverse(*A, options("spai", 2)));
      const double pattern3 = inverse_residual_norm(*A, *approximate_inverse(*A, options("spai", 3)));
      // The diagonal pattern is contained in the others, so its minimizer is no better (and
      // diag(A)^-1 is not even the minimizer over the diagonal).
      EXPECT_LT(pattern1, diagonal) << "convection " << convection;
      EXPECT_LT(pattern2, pattern1) << "convection " << convection;
      EXPECT_LT(pattern3, pattern2) << "convection " << convection;
      // drop 0.08 keeps the diagonal neighbours of A^2 (|2| / 20) and drops the distance-2 ones
      // (|1| / 20): a pattern strictly between those of A and A^2
      EXPECT_LT(pattern2, dropped) << "convection " << convection;
      EXPECT_LT(dropped, pattern1) << "convection " << convection;
      EXPECT_GT(lumped, 0.0);
      // The pattern of A: as many entries as A.
      EXPECT_EQ(spai1->getGlobalNumEntries(), A->getGlobalNumEntries());
      if (test_helpers::comm()->getRank() == 0)
        std::cout << "convection " << convection << ": ||A Ainv - I||_F diagonal " << diagonal << ", lumping "
                  << lumped << ", spai(A) " << pattern1 << ", spai(A^2, drop 0.08) " << dropped << ", spai(A^2) "
                  << pattern2 << ", spai(A^3) " << pattern3 << "\n";
    }
}

TEST(InverseApproximation, SpaiIsTheLeastSquaresMinimizer)
{
  // Optimality of min ||A M - I||_F over the pattern of M: the gradient A^T (A M - I) vanishes at
  // every pattern position (checks the row/column bookkeeping of the transposed algorithm).
  for (const double convection : {0.0, 2.0})
    for (const int power : {1, 2})
      {
        const auto   A = grid_matrix(12, convection);
        const auto   M = approximate_inverse(*A, options("spai", power));
        TpetraMatrix AM(A->getRowMap(), 0), AtAM(A->getRowMap(), 0);
        Tpetra::MatrixMatrix::Multiply(*A, false, *M, false, AM);
        Tpetra::MatrixMatrix::Multiply(*A, true, AM, false, AtAM);
        const auto At = Tpetra::RowMatrixTransposer<SC, LO, GO, NO>(A).createTranspose();
        auto       entry = [](const TpetraMatrix& B, GO row, GO col) {
          typename TpetraMatrix::nonconst_global_inds_host_view_type cols("c", B.getNodeMaxNumRowEntries());
          typename TpetraMatrix::nonconst_values_host_view_type      vals("v", B.getNodeMaxNumRowEntries());
          size_t                                                     n = 0;
          B.getGlobalRowCopy(row, cols, vals, n);
          for (size_t k = 0; k < n; ++k)
            if (cols(k) == col)
              return vals(k);
          return 0.0;
        };
        double largest = 0;
        for (LO i = 0; i < static_cast<LO>(M->getNodeNumRows()); ++i)
          {
            const GO row = M->getRowMap()->getGlobalElement(i);
            typename TpetraMatrix::local_inds_host_view_type inds;
            typename TpetraMatrix::values_host_view_type     vals;
            M->getLocalRowView(i, inds, vals);
            for (size_t k = 0; k < inds.extent(0); ++k)
              {
                const GO col = M->getColMap()->getGlobalElement(inds(k));
                largest      = std::max(largest, std::abs(entry(AtAM, row, col) - entry(*At, row, col)));
              }
          }
        EXPECT_LT(largest, 1e-12) << "convection " << convection << ", pattern power " << power;
      }
}

TEST(InverseApproximation, SpaiSmootherReducesTheError)
{
  // A x = 0 from a random start: x is the error. The SPAI smoother (no damping) removes its
  // oscillatory part quickly and never increases the A-norm here.
  const auto A    = grid_matrix(24, 0.0);
  const auto Ainv = approximate_inverse(*A, options("spai", 1));
  TpetraMultiVector b(A->getRowMap(), 1), x(A->getRowMap(), 1), Ax(A->getRowMap(), 1);
  x.randomize();
  auto a_norm = [&]() {
    A->apply(x, Ax);
    Teuchos::Array<double> dot(1);
    x.dot(Ax, dot);
    return std::sqrt(dot[0]);
  };
  const double e0       = a_norm();
  double       previous = e0;
  for (int sweep = 0; sweep < 5; ++sweep)
    {
      spai_smooth(*A, *Ainv, b, x, 1);
      const double e = a_norm();
      EXPECT_LT(e, previous) << "sweep " << sweep;
      previous = e;
    }
  EXPECT_LT(previous, 0.5 * e0);
}

TEST(InverseApproximation, RejectsBadOptions)
{
  const auto A = grid_matrix(4, 0.0);
  EXPECT_THROW(approximate_inverse(*A, options("magic")), InputError);
  EXPECT_THROW(approximate_inverse(*A, options("spai", 5)), InputError);
  EXPECT_THROW(approximate_inverse(*A, options("spai", 1, -0.1)), InputError);
}
