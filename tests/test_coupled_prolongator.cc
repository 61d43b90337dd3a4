// The prolongator smoothed across the blocks (multigrid/coupled_prolongator.h) on a 1D Laplacian
// cut into blocks, where the answer is known: one Jacobi step of the whole operator on the
// block-diagonal tentative prolongator is the single-field SA prolongator of the uncut problem,
// P = Pt - omega D^-1 A Pt with one omega for every block, and the coupling entries at the cuts
// are exactly what a block-diagonal P would lack. Also the blocked transpose and the Galerkin
// product of a 3 x 3 blocked operator (three products in one block, which MueLu 13.2's
// BlockedRAPFactory cannot add up), on 1 and 2 ranks.
#include "coupled_prolongator.h"

#include <MueLu_Utilities.hpp>
#include <Teuchos_CommHelpers.hpp>
#include <Tpetra_CrsMatrix.hpp>
#include <Xpetra_BlockedCrsMatrix.hpp>
#include <Xpetra_MapExtractorFactory.hpp>
#include <Xpetra_MapUtils.hpp>
#include <Xpetra_MultiVectorFactory.hpp>
#include <gtest/gtest.h>

#include "test_helpers.h"

#include <cmath>

using namespace multigrid;

namespace
{
  using TpetraCrs = Tpetra::CrsMatrix<SC, LO, GO, NO>;
  using TpetraMap = Tpetra::Map<LO, GO, NO>;
  using MVF       = Xpetra::MultiVectorFactory<SC, LO, GO, NO>;

  /// A 1D Laplacian (2 on the diagonal, -1 beside it) of `sizes` summed DOFs, cut into blocks of
  /// `sizes` consecutive DOFs (global ids in order, Xpetra numbering), and its tentative
  /// prolongator: aggregates of two neighbouring DOFs of one block, value 1/sqrt(2) (the
  /// normalized constant); coarse ids in block order as well.
  struct CutLaplacian
  {
    RCP<BlockedCrsMatrix> A, Pt;
    GO                    n = 0;
  };

  Teuchos::RCP<const TpetraMap> range(GO size, GO first)
  {
    return Teuchos::rcp(new TpetraMap(size, first, test_helpers::comm()));
  }

  RCP<const MapExtractor> extractor(const std::vector<Teuchos::RCP<const TpetraMap>>& maps)
  {
    std::vector<RCP<const Map>> xmaps;
    for (const auto& m : maps)
      xmaps.push_back(Xpetra::toXpetra(m));
    return Xpetra::MapExtractorFactory<SC, LO, GO, NO>::Build(
        Xpetra::MapUtils<LO, GO, NO>::concatenateMaps(xmaps), xmaps);
  }

  /// Rows of `rows` with entries f(row, column) != 0 in the columns of `columns`.
  RCP<Matrix> block(const Teuchos::RCP<const TpetraMap>& rows, const Teuchos::RCP<const TpetraMap>& columns,
                    const std::function<double(GO, GO)>& f)
  {
    auto M = Teuchos::rcp(new TpetraCrs(rows, 3));
    for (LO l = 0; l < static_cast<LO>(rows->getNodeNumElements()); ++l)
      {
        const GO        row = rows->getGlobalElement(l);
        std::vector<GO> cols;
        std::vector<SC> vals;
        for (GO c = columns->getMinAllGlobalIndex(); c <= columns->getMaxAllGlobalIndex(); ++c)
          if (const double v = f(row, c); v != 0.0)
            {
              cols.push_back(c);
              vals.push_back(v);
            }
        if (!cols.empty())
          M->insertGlobalValues(row, Teuchos::ArrayView<const GO>(cols), Teuchos::ArrayView<const SC>(vals));
      }
    M->fillComplete(columns, rows);
    return MueLu::TpetraCrs_To_XpetraMatrix(M);
  }

  CutLaplacian cut_laplacian(const std::vector<GO>& sizes)
  {
    std::vector<Teuchos::RCP<const TpetraMap>> fine, coarse;
    GO                                         first = 0, first_coarse = 0;
    for (const GO s : sizes)
      {
        fine.push_back(range(s, first));
        coarse.push_back(range(s / 2, first_coarse));
        first += s;
        first_coarse += s / 2;
      }
    CutLaplacian c;
    c.n                  = first;
    auto fine_rows       = extractor(fine);
    auto coarse_ids      = extractor(coarse);
    c.A                  = Teuchos::rcp(new BlockedCrsMatrix(fine_rows, fine_rows, 3));
    c.Pt                 = Teuchos::rcp(new BlockedCrsMatrix(fine_rows, coarse_ids, 1));
    const auto laplacian = [](GO i, GO j) { return i == j ? 2.0 : (std::abs(i - j) == 1 ? -1.0 : 0.0); };
    for (std::size_t i = 0; i < sizes.size(); ++i)
      {
        for (std::size_t j = 0; j < sizes.size(); ++j)
          if (std::abs(static_cast<long>(i) - static_cast<long>(j)) <= 1)
            c.A->setMatrix(i, j, block(fine[i], fine[j], laplacian));
        const GO f0 = fine[i]->getMinAllGlobalIndex(), c0 = coarse[i]->getMinAllGlobalIndex();
        c.Pt->setMatrix(i, i, block(fine[i], coarse[i], [&](GO row, GO col) {
                          return (row - f0) / 2 == col - c0 ? 1.0 / std::sqrt(2.0) : 0.0;
                        }));
      }
    c.A->fillComplete();
    c.Pt->fillComplete();
    return c;
  }

  RCP<MultiVector> apply(const Matrix& M, const MultiVector& x)
  {
    auto y = MVF::Build(M.getRangeMap(), 1);
    M.apply(x, *y);
    return y;
  }

  double dot(const MultiVector& a, const MultiVector& b)
  {
    Teuchos::Array<double> d(1);
    a.dot(b, d);
    return d[0];
  }

  double norm(const MultiVector& a)
  {
    return std::sqrt(dot(a, a));
  }

  /// Entries of a block on all ranks (0 for none: BlockedCrsMatrix::fillComplete puts empty
  /// matrices where no block was set).
  long long entries(const RCP<Matrix>& M)
  {
    if (M.is_null())
      return 0;
    const long long local = M->getNodeNumEntries();
    long long       total = 0;
    Teuchos::reduceAll(*test_helpers::comm(), Teuchos::REDUCE_SUM, local, Teuchos::outArg(total));
    return total;
  }

  /// P x, Pt x and D^-1 A Pt x on the merged (uncut) operators, for a random coarse x.
  struct Applied
  {
    RCP<MultiVector> Px, Ptx, DAPtx;
  };

  Applied applied(const CutLaplacian& c, const BlockedCrsMatrix& P)
  {
    const auto Pm  = P.Merge();
    const auto Ptm = c.Pt->Merge();
    const auto Am  = c.A->Merge();
    auto       x   = MVF::Build(Pm->getDomainMap(), 1);
    x->randomize();
    Applied a;
    a.Px    = apply(*Pm, *x);
    a.Ptx   = apply(*Ptm, *x);
    a.DAPtx = apply(*Am, *a.Ptx);
    a.DAPtx->scale(0.5); // D = 2 I
    return a;
  }

  /// Ac is the Galerkin product of the merged operators (Ac x = R (A (P x)) for a random x),
  /// symmetric like A, and couples neighbouring blocks (and, with `far_blocks_empty`, no others).
  void expect_galerkin_product(const BlockedCrsMatrix& Ac, const CutLaplacian& c, const BlockedCrsMatrix& R,
                               const BlockedCrsMatrix& P, bool far_blocks_empty)
  {
    for (std::size_t i = 0; i < Ac.Rows(); ++i)
      for (std::size_t j = 0; j < Ac.Cols(); ++j)
        {
          const bool neighbours = std::abs(static_cast<long>(i) - static_cast<long>(j)) <= 1;
          if (neighbours || far_blocks_empty)
            {
              EXPECT_EQ(entries(Ac.getMatrix(i, j)) > 0, neighbours) << i << ", " << j;
            }
        }
    const auto Acm = Ac.Merge();
    const auto Pm  = P.Merge();
    auto       x   = MVF::Build(Pm->getDomainMap(), 1);
    auto       x2  = MVF::Build(Pm->getDomainMap(), 1);
    x->randomize();
    x2->randomize();
    const auto direct   = apply(*Acm, *x);
    const auto chained  = apply(*R.Merge(), *apply(*c.A->Merge(), *apply(*Pm, *x)));
    auto       residual = MVF::Build(direct->getMap(), 1);
    residual->update(1.0, *direct, -1.0, *chained, 0.0);
    EXPECT_LT(norm(*residual), 1e-12 * norm(*chained));
    EXPECT_NEAR(dot(*x2, *apply(*Acm, *x)), dot(*apply(*Acm, *x2), *x), 1e-12 * norm(*x) * norm(*x2) * 10);
  }
} // namespace

TEST(CoupledProlongator, IsTheUncutProblemsSmoothedAggregation)
{
  // Blocks of 6 and 10 DOFs: P x = Pt x - omega D^-1 A Pt x with one omega, including the rows
  // beside the cut, whose coupling entry -1 sits in the off-diagonal blocks of A.
  const auto       c = cut_laplacian({6, 10});
  CoupledSmoothing settings;
  const auto       P = coupled_smoothed_prolongator(*c.A, *c.Pt, settings);
  // the one coupling entry of A_01 / A_10 reaches the two coarse functions beside the cut
  EXPECT_EQ(entries(P->getMatrix(0, 1)), 1);
  EXPECT_EQ(entries(P->getMatrix(1, 0)), 1);
  const auto a    = applied(c, *P);
  auto       step = MVF::Build(a.Px->getMap(), 1);
  step->update(1.0, *a.Ptx, -1.0, *a.Px, 0.0); // omega D^-1 A Pt x
  const double omega = dot(*step, *a.DAPtx) / dot(*a.DAPtx, *a.DAPtx);
  step->update(-omega, *a.DAPtx, 1.0);
  EXPECT_LT(norm(*step), 1e-12 * norm(*a.Ptx));
  // omega = (4/3) / lambda with lambda from 10 power steps, at most lambda_max(D^-1 A) =
  // 1 - cos(pi n / (n + 1)) (D^-1 A = A / 2): the power method underestimates it, never over.
  const double lambda_max = 1.0 - std::cos(M_PI * c.n / (c.n + 1.0));
  EXPECT_GE(omega * lambda_max, 4.0 / 3.0 * (1 - 1e-10));
  EXPECT_LT(omega * lambda_max, 4.0 / 3.0 / 0.8);

  // Without the off-diagonal blocks (each block smoothed alone) the rows at the cut differ.
  auto rows           = c.A->getRangeMapExtractor();
  auto columns        = c.Pt->getDomainMapExtractor();
  auto block_diagonal = Teuchos::rcp(new BlockedCrsMatrix(rows, columns, 3));
  block_diagonal->setMatrix(0, 0, P->getMatrix(0, 0));
  block_diagonal->setMatrix(1, 1, P->getMatrix(1, 1));
  block_diagonal->fillComplete();
  const auto b = applied(c, *block_diagonal);
  step->update(1.0, *b.Ptx, -1.0, *b.Px, 0.0);
  step->update(-omega, *b.DAPtx, 1.0);
  EXPECT_GT(norm(*step), 1e-3 * norm(*b.Ptx));
}

TEST(CoupledProlongator, TentativeRowsStayTentativeAndOthersKeepTheirCoupling)
{
  const auto       c = cut_laplacian({8, 8});
  CoupledSmoothing settings;
  settings.tentative_rows = {1};
  const auto P            = coupled_smoothed_prolongator(*c.A, *c.Pt, settings);
  EXPECT_EQ(entries(P->getMatrix(1, 0)), 0);
  // block 1: P_11 = Pt_11 exactly
  const auto a = applied(c, *P);
  auto       d = MVF::Build(a.Px->getMap(), 1);
  d->update(1.0, *a.Px, -1.0, *a.Ptx, 0.0);
  const auto rows1 = c.A->getRangeMapExtractor()->getMap(1);
  for (LO l = 0; l < static_cast<LO>(d->getLocalLength()); ++l)
    if (rows1->isNodeGlobalElement(d->getMap()->getGlobalElement(l)))
      {
        EXPECT_EQ(d->getData(0)[l], 0.0);
      }
  // block 0 is smoothed with the rows' full coupling (P_01 present)
  EXPECT_EQ(entries(P->getMatrix(0, 1)), 1);

  settings.tentative_rows = {2};
  EXPECT_NE(test_helpers::error_of([&] {
              coupled_smoothed_prolongator(*c.A, *c.Pt, settings);
            }).find("tentative block 2 of a 2 x 2 operator"),
            std::string::npos);
}

TEST(CoupledProlongator, RefusesATentativeProlongatorWithOffDiagonalBlocks)
{
  const auto c = cut_laplacian({6, 6});
  const auto P = coupled_smoothed_prolongator(*c.A, *c.Pt, {});
  EXPECT_NE(test_helpers::error_of([&] {
              coupled_smoothed_prolongator(*c.A, *P, {});
            }).find("must be block-diagonal"),
            std::string::npos);
}

TEST(CoupledProlongator, TransposeAndGalerkinProductOfThreeBlocks)
{
  // Blocks 6 / 8 / 10: (A P)_1j = sum_l A_1l P_lj sums three products in the middle block row.
  const auto c  = cut_laplacian({6, 8, 10});
  const auto P  = coupled_smoothed_prolongator(*c.A, *c.Pt, {});
  const auto R  = blocked_transpose(*P);
  const auto Pm = P->Merge();
  const auto Rm = R->Merge();
  auto       x  = MVF::Build(Pm->getDomainMap(), 1);
  auto       y  = MVF::Build(Pm->getRangeMap(), 1);
  x->randomize();
  y->randomize();
  EXPECT_NEAR(dot(*y, *apply(*Pm, *x)), dot(*apply(*Rm, *y), *x), 1e-12 * norm(*x) * norm(*y) * 10);

  expect_galerkin_product(*blocked_galerkin_product(*R, *c.A, *P), c, *R, *P, false);
}

TEST(CoupledProlongator, GalerkinProductOfBlockDiagonalTransfersOfUnequalDensity)
{
  // Block-diagonal P whose blocks differ in density: the tentative one (one entry per row) on
  // block 0, smoothed ones on blocks 1 and 2 (the diagonal blocks of the coupled P, three entries
  // per row). Blocks (0, 1) and (1, 0) are then associated differently ((R_00 A_01) P_11 and
  // R_11 (A_10 P_00)); every block must still be the Galerkin product of the merged operators.
  const auto c       = cut_laplacian({6, 8, 10});
  const auto coupled = coupled_smoothed_prolongator(*c.A, *c.Pt, {});
  auto       rows    = c.Pt->getRangeMapExtractor();
  auto       columns = c.Pt->getDomainMapExtractor();
  auto       P       = Teuchos::rcp(new BlockedCrsMatrix(rows, columns, 3));
  P->setMatrix(0, 0, c.Pt->getMatrix(0, 0));
  P->setMatrix(1, 1, coupled->getMatrix(1, 1));
  P->setMatrix(2, 2, coupled->getMatrix(2, 2));
  P->fillComplete();
  ASSERT_LT(entries(P->getMatrix(0, 0)), entries(P->getMatrix(1, 1)));
  // block-diagonal transfers keep A's block pattern: (0, 2) and (2, 0) stay empty
  const auto R = blocked_transpose(*P);
  expect_galerkin_product(*blocked_galerkin_product(*R, *c.A, *P), c, *R, *P, true);
}
