// The project's SuperLU adaptor (Debian's Amesos2 is built without SuperLU; see PLATFORM.md).
//
// SuperLUDirect gathers a distributed Xpetra matrix onto rank 0, factorizes it there with SuperLU's
// expert driver dgssvx, and solves by gathering the right-hand side and scattering the solution
// back. Before the factorization the matrix is permuted and scaled by MC64 (large entries onto
// the diagonal, |diagonal| = 1: saddle-point systems with zero diagonal blocks and rows of very
// different scale) and ordered by METIS nested dissection; dgssvx equilibrates and, by default,
// refines the solution iteratively (details in superlu_direct.cc). This is the right tool for
// coarse levels and for reference solutions on the sizes this project runs; SuperLU_DIST would be
// the next step for direct solves too large for one rank's memory.
//
// Diagnostics: with SUPERLU_DUMP_SINGULAR=FILE in the environment, a matrix found singular is
// written to FILE (Matrix Market) before the error is raised.
//
// It serves three roles: the `direct(superlu)` preset (DirectSolverOperator), the coarse-level
// solver of MueLu hierarchies ("SuperLUDirectSolver" in preset XML), and reference solutions in tests.
#pragma once

#include "types.h"

#include <Xpetra_Import.hpp>
#include <Xpetra_Matrix.hpp>
#include <Xpetra_Operator.hpp>

#include <memory>

namespace multigrid
{
  struct SuperLUOptions
  {
    /// Rows without a nonzero value get a one on the diagonal first (coarse levels: DOFs the
    /// prolongator does not reach).
    bool unit_diagonal_on_empty_rows = false;
    /// dgssvx's iterative refinement on every solve (one residual and usually one more solve):
    /// for whole-system solves and references; coarse levels of a preconditioner do without.
    bool iterative_refinement = true;
  };

  class SuperLUDirect
  {
  public:
    /// Factorizes A (square, fill-complete). Throws InputError if A is structurally or
    /// numerically singular.
    explicit SuperLUDirect(const RCP<const Matrix>& A, const SuperLUOptions& options = SuperLUOptions());
    ~SuperLUDirect();
    SuperLUDirect(const SuperLUDirect&)            = delete;
    SuperLUDirect& operator=(const SuperLUDirect&) = delete;

    /// X = A^-1 B (X and B distributed like A's range/domain maps).
    void solve(const ::multigrid::MultiVector& B, ::multigrid::MultiVector& X) const;

    /// Nonzeros of L + U (on rank 0, broadcast): a measure of the direct solver's memory.
    long long factor_nonzeros() const { return factor_nnz_; }

  private:
    struct Factors;
    RCP<const ::multigrid::Map> distributed_map_;
    RCP<const ::multigrid::Map> root_map_;
    /// distributed -> rank 0, built once: solves run on every coarse-level visit of every cycle.
    RCP<const Xpetra::Import<LO, GO, NO>> gather_;
    std::unique_ptr<Factors>              factors_; ///< only on rank 0
    long long                             factor_nnz_ = 0;
  };

  /// direct(superlu) as an Xpetra operator: apply(B) = A^-1 B. Used as a "preconditioner" in the
  /// same Krylov driver, which then converges in one iteration and reports the true residual.
  class DirectSolverOperator : public Xpetra::Operator<SC, LO, GO, NO>
  {
  public:
    explicit DirectSolverOperator(const RCP<const Matrix>& A);
    RCP<const ::multigrid::Map> getDomainMap() const override { return A_->getDomainMap(); }
    RCP<const ::multigrid::Map> getRangeMap() const override { return A_->getRangeMap(); }
    void                        apply(const ::multigrid::MultiVector& X, ::multigrid::MultiVector& Y,
                                      Teuchos::ETransp mode = Teuchos::NO_TRANS, SC alpha = 1.0, SC beta = 0.0) const override;
    void                        residual(const ::multigrid::MultiVector& X, const ::multigrid::MultiVector& B,
                                         ::multigrid::MultiVector& R) const override;
    const SuperLUDirect&        solver() const { return *solver_; }

  private:
    RCP<const Matrix>              A_;
    std::unique_ptr<SuperLUDirect> solver_;
  };
} // namespace multigrid
