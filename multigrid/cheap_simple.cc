#include "cheap_simple.h"

#include "hierarchy_utils.h"

#include <MueLu_Hierarchy.hpp>

#include <Xpetra_BlockedCrsMatrix.hpp>
#include <Xpetra_MapExtractor.hpp>
#include <Xpetra_MatrixFactory.hpp>
#include <Xpetra_MatrixMatrix.hpp>
#include <Xpetra_MultiVectorFactory.hpp>
#include <Xpetra_VectorFactory.hpp>

#include <cmath>

namespace multigrid
{
  CheapSimpleOperator::CheapSimpleOperator(const BlockSystem& system, const Teuchos::ParameterList& p)
      : system_(system)
  {
    if (system.n_blocks() != 2)
      throw InputError("CheapSIMPLE needs a 2 x 2 block system, got " + std::to_string(system.n_blocks()) +
                       " blocks");
    sweeps_            = p.get<int>("sweeps");
    damping_           = p.get<double>("damping");
    const bool simplec = p.get<bool>("simplec");
    if (sweeps_ < 1 || !(damping_ > 0.0))
      throw InputError("CheapSIMPLE: sweeps must be >= 1 and damping > 0 (got " + std::to_string(sweeps_) +
                       ", " + std::to_string(damping_) + ")");

    const auto blocked = system.blocked_matrix();
    A_                 = blocked->getMatrix(0, 0);
    B1t_               = blocked->getMatrix(0, 1);
    B2_                = blocked->getMatrix(1, 0);
    RCP<Matrix> C      = blocked->getMatrix(1, 1);

    // Â^-1: inverse diagonal (SIMPLE) or inverse absolute row sums (SIMPLEC) of A.
    auto inv = Xpetra::VectorFactory<SC, LO, GO, NO>::Build(A_->getRowMap(), true);
    {
      auto data = inv->getDataNonConst(0);
      for (std::size_t i = 0; i < A_->getNodeNumRows(); ++i)
        {
          Teuchos::ArrayView<const LO> cols;
          Teuchos::ArrayView<const SC> vals;
          A_->getLocalRowView(i, cols, vals);
          const GO row = A_->getRowMap()->getGlobalElement(i);
          double   d   = 0.0;
          for (LO k = 0; k < cols.size(); ++k)
            {
              if (simplec)
                d += std::abs(vals[k]);
              else if (A_->getColMap()->getGlobalElement(cols[k]) == row)
                d = vals[k];
            }
          data[i] = (d != 0.0) ? 1.0 / d : 1.0;
        }
    }
    inv_diag_ = inv;

    // S = C - B2 Â^-1 B1^T, formed explicitly (sparse: Â is diagonal).
    auto        out  = Teuchos::fancyOStream(Teuchos::rcpFromRef(std::cerr));
    RCP<Matrix> DB1t = Xpetra::MatrixFactory<SC, LO, GO, NO>::BuildCopy(B1t_);
    DB1t->leftScale(*inv);
    RCP<Matrix> product = Xpetra::MatrixMatrix<SC, LO, GO, NO>::Multiply(*B2_, false, *DB1t, false, *out);
    RCP<Matrix> S;
    Xpetra::MatrixMatrix<SC, LO, GO, NO>::TwoMatrixAdd(*C, false, 1.0, *product, false, -1.0, S, *out);
    S->fillComplete(C->getDomainMap(), C->getRangeMap());
    S_ = S;

    const auto& primal = system.block(0);
    primal_ = build_single_field_hierarchy(A_, primal.dofs_per_node, system.nullspace_or_translations(0),
                                           p.sublist("primal solver"));
    schur_  = build_single_field_hierarchy(S_, 1, Teuchos::null, p.sublist("schur solver"));
  }

  void CheapSimpleOperator::apply(const ::multigrid::MultiVector& X, ::multigrid::MultiVector& Y,
                                  Teuchos::ETransp mode, SC alpha, SC beta) const
  {
    if (mode != Teuchos::NO_TRANS)
      throw std::logic_error("CheapSimpleOperator: transposed apply is not supported");
    using MVF        = Xpetra::MultiVectorFactory<SC, LO, GO, NO>;
    const auto& ext  = *system_.map_extractor();
    const auto  full = system_.full_map();
    const auto  n    = X.getNumVectors();
    auto        x    = MVF::Build(full, n, true);
    auto        r    = MVF::Build(full, n);
    auto        dx1  = MVF::Build(A_->getRangeMap(), n);
    auto        dx2  = MVF::Build(S_->getRangeMap(), n);
    auto        tmp1 = MVF::Build(A_->getRangeMap(), n);
    auto        rhs2 = MVF::Build(S_->getRangeMap(), n);

    for (int sweep = 0; sweep < sweeps_; ++sweep)
      {
        // 1. residual of the current iterate (x = 0 on the first sweep)
        if (sweep == 0)
          r->update(1.0, X, 0.0);
        else
          {
            system_.merged_matrix()->apply(*x, *r);
            r->update(1.0, X, -1.0);
          }
        auto r1 = ext.ExtractVector(r, 0);
        auto r2 = ext.ExtractVector(r, 1);
        // 2. displacement prediction with the inner solver
        dx1->putScalar(0.0);
        primal_->Iterate(*r1, *dx1, 1, true);
        // 3. approximate Schur complement equation
        B2_->apply(*dx1, *rhs2);
        rhs2->update(1.0, *r2, -1.0);
        dx2->putScalar(0.0);
        schur_->Iterate(*rhs2, *dx2, 1, true);
        // 4. damped multiplier update and its consequence for the displacements
        dx2->scale(damping_);
        B1t_->apply(*dx2, *tmp1);
        dx1->elementWiseMultiply(-1.0 / damping_, *inv_diag_->getVector(0), *tmp1, 1.0);
        // 5. increment
        auto xx1 = ext.ExtractVector(x, 0);
        auto xx2 = ext.ExtractVector(x, 1);
        xx1->update(1.0, *dx1, 1.0);
        xx2->update(1.0, *dx2, 1.0);
        ext.InsertVector(xx1, 0, x);
        ext.InsertVector(xx2, 1, x);
      }
    Y.update(alpha, *x, beta);
  }

  void CheapSimpleOperator::residual(const ::multigrid::MultiVector& X, const ::multigrid::MultiVector& B,
                                     ::multigrid::MultiVector& R) const
  {
    system_.merged_matrix()->apply(X, R);
    R.update(1.0, B, -1.0);
  }

  std::vector<std::pair<long long, long long>> CheapSimpleOperator::primal_levels() const
  {
    return level_sizes(*primal_);
  }

  long long CheapSimpleOperator::schur_nonzeros() const
  {
    return S_->getGlobalNumEntries();
  }
} // namespace multigrid
