// CheapSIMPLE(C): the Schur-complement block preconditioner of seed 000 for
//     [ A   B1^T ] [x1]   [b1]
//     [ B2  C    ] [x2] = [b2],
// with Â = diag(A) (SIMPLE) or the absolute row sums of A (SIMPLEC). One sweep, from the current
// iterate x:
//   1. r = b - K x
//   2. displacement prediction          A dx1~ = r1                  (inner AMG / relaxation)
//   3. approximate Schur complement     S dx2~ = r2 - B2 dx1~,  S = C - B2 Â^-1 B1^T  (ILU(0))
//   4. update                           dx2 = w dx2~,  dx1 = dx1~ - (1/w) Â^-1 B1^T dx2
//   5. x <- x + dx
// "CheapSIMPLE(AMG)" puts the multigrid inside the block method: the contact constraints are seen
// on the finest level only (the seeds' contrast to saddle-point AMG).
#pragma once

#include "block_system.h"

#include <Teuchos_ParameterList.hpp>
#include <Xpetra_Operator.hpp>

#include <memory>

namespace MueLu
{
  template <class SC, class LO, class GO, class NO>
  class Hierarchy;
}

namespace multigrid
{
  class CheapSimpleOperator : public Xpetra::Operator<SC, LO, GO, NO>
  {
  public:
    /// `parameters`: sweeps, damping, simplec, sublists "primal solver" and "schur solver"
    /// (MueLu parameter lists).
    CheapSimpleOperator(const BlockSystem& system, const Teuchos::ParameterList& parameters);

    RCP<const ::multigrid::Map> getDomainMap() const override { return system_.full_map(); }
    RCP<const ::multigrid::Map> getRangeMap() const override { return system_.full_map(); }
    void                        apply(const ::multigrid::MultiVector& X, ::multigrid::MultiVector& Y,
                                      Teuchos::ETransp mode = Teuchos::NO_TRANS, SC alpha = 1.0, SC beta = 0.0) const override;
    void                        residual(const ::multigrid::MultiVector& X, const ::multigrid::MultiVector& B,
                                         ::multigrid::MultiVector& R) const override;

    /// Levels of the inner primal AMG (fine first) and of the Schur solver, for the report.
    std::vector<std::pair<long long, long long>> primal_levels() const;
    long long                                    schur_nonzeros() const;

  private:
    const BlockSystem&                    system_;
    int                                   sweeps_  = 1;
    double                                damping_ = 1.0;
    RCP<Matrix>                           A_, B1t_, B2_, S_;
    RCP<::multigrid::MultiVector>         inv_diag_; ///< 1 / Â on the primal map
    RCP<MueLu::Hierarchy<SC, LO, GO, NO>> primal_, schur_;
  };
} // namespace multigrid
