// The explicit Schur complement and the sum of two matrices (multigrid/schur_complement.h) on
// distributed model matrices whose column maps differ: the operators agree with the sum and the
// product chain applied vector by vector, and every row holds exactly the union of the two
// patterns, sorted and merged.
#include "schur_complement.h"

#include <MueLu_Utilities.hpp>
#include <Tpetra_CrsMatrix.hpp>
#include <Xpetra_MultiVectorFactory.hpp>
#include <gtest/gtest.h>

#include "test_helpers.h"

#include <functional>
#include <set>

using namespace multigrid;

namespace
{
  using TpetraCrs = Tpetra::CrsMatrix<SC, LO, GO, NO>;
  using TpetraMap = Tpetra::Map<LO, GO, NO>;

  /// An n-row matrix distributed by rows whose row `row` has entries at row + offset (for the
  /// offsets that stay inside [0, domain size)), value f(row, column). Wide offsets reach rows of
  /// other ranks, so two such matrices have different column maps.
  RCP<Matrix> banded(const Teuchos::RCP<const TpetraMap>& rows, const Teuchos::RCP<const TpetraMap>& domain,
                     const std::vector<GO>& offsets, const std::function<double(GO, GO)>& f)
  {
    auto A = Teuchos::rcp(new TpetraCrs(rows, offsets.size()));
    for (LO l = 0; l < static_cast<LO>(rows->getNodeNumElements()); ++l)
      {
        const GO        row = rows->getGlobalElement(l);
        std::vector<GO> cols;
        std::vector<SC> vals;
        for (const GO o : offsets)
          if (row + o >= 0 && row + o < static_cast<GO>(domain->getGlobalNumElements()))
            {
              cols.push_back(row + o);
              vals.push_back(f(row, row + o));
            }
        A->insertGlobalValues(row, Teuchos::ArrayView<const GO>(cols), Teuchos::ArrayView<const SC>(vals));
      }
    A->fillComplete(domain, rows);
    return MueLu::TpetraCrs_To_XpetraMatrix(A);
  }

  Teuchos::RCP<const TpetraMap> map_of(GO n)
  {
    return Teuchos::rcp(new TpetraMap(n, 0, test_helpers::comm()));
  }

  RCP<MultiVector> random_vector(const RCP<const Map>& map)
  {
    auto x = Xpetra::MultiVectorFactory<SC, LO, GO, NO>::Build(map, 1);
    x->randomize();
    return x;
  }

  /// Largest |y - z| against the largest |y|.
  double relative_difference(const MultiVector& y, const MultiVector& z)
  {
    auto d = Xpetra::MultiVectorFactory<SC, LO, GO, NO>::Build(y.getMap(), 1);
    d->update(1.0, y, -1.0, z, 0.0);
    Teuchos::Array<double> dn(1), yn(1);
    d->normInf(dn);
    y.normInf(yn);
    return dn[0] / yn[0];
  }

  double value(GO i, GO j)
  {
    return 1.0 + 0.01 * static_cast<double>((3 * i + 7 * j) % 11);
  }
} // namespace

TEST(SchurComplement, SumIsTheUnionOfThePatterns)
{
  const GO    n    = 40;
  const auto  rows = map_of(n);
  RCP<Matrix> C    = banded(rows, rows, {-1, 0, 1}, value);
  RCP<Matrix> P    = banded(rows, rows, {-17, 0, 2, 13}, [](GO i, GO j) { return -value(j, i); });
  RCP<Matrix> S    = add_matrices(*C, -0.5, *P);

  ASSERT_TRUE(S->isFillComplete());
  EXPECT_TRUE(S->getDomainMap()->isSameAs(*C->getDomainMap()));
  EXPECT_TRUE(S->getRangeMap()->isSameAs(*C->getRangeMap()));
  // S x = C x - 0.5 P x.
  const auto x = random_vector(C->getDomainMap());
  auto       y = Xpetra::MultiVectorFactory<SC, LO, GO, NO>::Build(C->getRangeMap(), 1);
  auto       z = Xpetra::MultiVectorFactory<SC, LO, GO, NO>::Build(C->getRangeMap(), 1);
  S->apply(*x, *y);
  C->apply(*x, *z);
  P->apply(*x, *z, Teuchos::NO_TRANS, -0.5, 1.0);
  EXPECT_LT(relative_difference(*y, *z), 1e-14);

  // Row by row: the union of the two patterns, each column once, in ascending local ids.
  for (LO l = 0; l < static_cast<LO>(rows->getNodeNumElements()); ++l)
    {
      const GO     row = rows->getGlobalElement(l);
      std::set<GO> expected;
      for (const GO o : {-1, 0, 1, -17, 2, 13})
        if (row + o >= 0 && row + o < n)
          expected.insert(row + o);
      Teuchos::ArrayView<const LO> columns;
      Teuchos::ArrayView<const SC> values;
      S->getLocalRowView(l, columns, values);
      std::set<GO> found;
      for (LO k = 0; k < columns.size(); ++k)
        {
          found.insert(S->getColMap()->getGlobalElement(columns[k]));
          if (k > 0)
            {
              EXPECT_LT(columns[k - 1], columns[k]) << "row " << row;
            }
        }
      EXPECT_EQ(found, expected) << "row " << row;
      EXPECT_EQ(static_cast<std::size_t>(columns.size()), expected.size()) << "row " << row;
    }
}

TEST(SchurComplement, ExplicitSchurComplementAppliesAsTheProductChain)
{
  // A 2 x 2 block structure of sizes 30 (first block) and 24 (second): B2 (24 x 30), Â (30 x 30,
  // nonsymmetric), B1t (30 x 24), C (24 x 24).
  const auto  first = map_of(30), second = map_of(24);
  RCP<Matrix> B2 = banded(second, first, {-3, 0, 4, 6}, value);
  RCP<Matrix> Ainv =
      banded(first, first, {-2, 0, 1, 9}, [](GO i, GO j) { return 0.1 * value(i, j) + (i == j); });
  RCP<Matrix>  B1t   = banded(first, second, {-5, -1, 0, 2}, value);
  RCP<Matrix>  C     = banded(second, second, {-1, 0, 1}, value);
  const double scale = 1.0 / 0.8;

  const auto x = random_vector(C->getDomainMap());
  // z = C x - scale B2 (Â (B1t x)).
  auto t1 = Xpetra::MultiVectorFactory<SC, LO, GO, NO>::Build(B1t->getRangeMap(), 1);
  auto t2 = Xpetra::MultiVectorFactory<SC, LO, GO, NO>::Build(Ainv->getRangeMap(), 1);
  auto z  = Xpetra::MultiVectorFactory<SC, LO, GO, NO>::Build(C->getRangeMap(), 1);
  B1t->apply(*x, *t1);
  Ainv->apply(*t1, *t2);
  C->apply(*x, *z);
  B2->apply(*t2, *z, Teuchos::NO_TRANS, -scale, 1.0);

  for (const bool with_C : {true, false})
    {
      RCP<Matrix> S = explicit_schur_complement(with_C ? C : Teuchos::null, *B2, *Ainv, *B1t, scale);
      auto        y = Xpetra::MultiVectorFactory<SC, LO, GO, NO>::Build(C->getRangeMap(), 1);
      S->apply(*x, *y);
      if (!with_C)
        C->apply(*x, *y, Teuchos::NO_TRANS, 1.0, 1.0); // S without C, plus C x
      EXPECT_LT(relative_difference(*y, *z), 1e-13) << (with_C ? "with C" : "without C");
    }
}
