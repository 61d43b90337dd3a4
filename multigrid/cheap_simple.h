// CheapSIMPLE(C): the Schur-complement block preconditioner (block method outside, multigrid
// inside) for
//     [ A   B1^T ] [x1]   [b1]
//     [ B2  C    ] [x2] = [b2],
// with an explicit cheap approximation Â ≈ A^-1. One sweep, from the current iterate x:
//   1. r = b - K x
//   2. prediction                       dx1~ = P(r1)          (inner AMG on A, or Â r1)
//   3. approximate Schur complement     S dx2~ = r2 - B2 dx1~,  S = C - B2 Â B1^T  (inner solver)
//   4. update                           dx2 = w dx2~,  dx1 = dx1~ - (1/w) Â_u B1^T dx2
//   5. x <- x + dx
// Â ("inverse approximation", in S): diag(A)^-1 (seed 000's CheapSIMPLE), the absolute-row-sum
// lumped inverse (CheapSIMPLEC), the signed row sum, or the sparse approximate inverse
// min ||A Â - I||_F over the pattern of A^k (seed 001's beam block,
// multigrid/inverse_approximation.h). Â_u ("update inverse approximation", in the final update)
// is Â unless chosen apart, e.g. SIMPLE's diag(A)^-1 with a lumped S. With the SPAI the predictor may be
// the SPAI smoother itself (dx1~ = Â r1, one sweep from zero) and S lives on the second block's
// DOFs (the solid of beam/solid): its inner AMG then gets that block's near-nullspace.
// With Â = A^-1, exact inner solves and w = 1, one sweep is the exact block LU solve.
// "CheapSIMPLE(AMG)" puts the multigrid inside the block method: the coupling is seen on the
// finest level only (the seeds' contrast to saddle-point AMG).
#pragma once

#include "block_system.h"
#include "inverse_approximation.h"

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
    /// `parameters`: sweeps, damping, "inverse approximation" (diagonal | row-sum |
    /// absolute-row-sum (lumping) | spai, with "spai: pattern power" and "spai: drop tolerance"),
    /// "update inverse approximation" (the same choices; default: "inverse approximation"),
    /// predictor (amg | approximate inverse),
    /// "schur nullspace" (none | block), sublists "primal solver" (predictor amg) and
    /// "schur solver" (MueLu parameter lists).
    /// With `keep_transfers`, the inner AMG hierarchies keep their transfers for refresh().
    CheapSimpleOperator(const BlockSystem& system, const Teuchos::ParameterList& parameters,
                        bool keep_transfers = false);

    /// The preconditioner of `system`'s matrix (the same block maps as the first one's): Â, the
    /// Schur complement and the final update's Â are formed anew, the inner AMG hierarchies set
    /// up again on their kept transfers (refresh_single_field_hierarchy). Only for an operator
    /// built with keep_transfers.
    void refresh(const BlockSystem& system);

    RCP<const ::multigrid::Map> getDomainMap() const override { return full_map_; }
    RCP<const ::multigrid::Map> getRangeMap() const override { return full_map_; }
    void                        apply(const ::multigrid::MultiVector& X, ::multigrid::MultiVector& Y,
                                      Teuchos::ETransp mode = Teuchos::NO_TRANS, SC alpha = 1.0, SC beta = 0.0) const override;
    void                        residual(const ::multigrid::MultiVector& X, const ::multigrid::MultiVector& B,
                                         ::multigrid::MultiVector& R) const override;

    /// The inner primal AMG (null with the approximate-inverse predictor).
    RCP<MueLu::Hierarchy<SC, LO, GO, NO>> primal_hierarchy() const { return primal_; }
    /// Levels of the inner primal AMG (fine first); empty with the approximate-inverse predictor.
    std::vector<std::pair<long long, long long>> primal_levels() const;
    /// Levels of the Schur-complement solver (fine first).
    std::vector<std::pair<long long, long long>> schur_levels() const;
    long long                                    schur_nonzeros() const;
    long long                                    inverse_approximation_nonzeros() const;

  private:
    /// The blocks of `system`, Â, Â_u and S = C - B2 Â B1^T (the first step of the set-up and of
    /// refresh()), and their adoption as this operator's.
    struct Blocks
    {
      RCP<const Matrix> merged;
      RCP<Matrix>       A, B1t, B2, S, A_inverse, update_inverse;
    };
    Blocks form_blocks(const BlockSystem& system) const;
    void   adopt(Blocks blocks);

    // The system's operator and block splitting by reference count (not the BlockSystem itself):
    // a Newton solver may keep this preconditioner after the system it was built from is gone.
    RCP<const Matrix>                     merged_;
    RCP<const MapExtractor>               extractor_;
    RCP<const ::multigrid::Map>           full_map_;
    int                                   sweeps_  = 1;
    double                                damping_ = 1.0;
    RCP<Matrix>                           A_, B1t_, B2_, S_;
    RCP<Matrix>                           A_inverse_;      ///< Â in S
    RCP<Matrix>                           update_inverse_; ///< Â_u in the final update
    RCP<MueLu::Hierarchy<SC, LO, GO, NO>> primal_;    ///< null with the approximate-inverse predictor
    RCP<MueLu::Hierarchy<SC, LO, GO, NO>> schur_;
    InverseApproximationOptions           inverse_options_, update_options_;
    Teuchos::ParameterList                primal_parameters_, schur_parameters_;
  };
} // namespace multigrid
