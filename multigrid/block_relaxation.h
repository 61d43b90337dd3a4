// Block relaxation outside, one solver per diagonal block inside: the baselines of the n x n
// block systems (FSI), `bgs(amg)` (Gee, Kuettler, Wall 2011: "BGS(AMG)") and `block-jacobi(amg)`.
//
// For the block system A x = b with diagonal blocks A_kk, one sweep of block Gauss-Seidel is
//     for k = 0 .. n-1:   x_k += omega * M_k^-1 (b_k - sum_j A_kj x_j)
// with the newest x_j (j < k already updated), block Jacobi the same with every x_j taken from the
// start of the sweep. M_k^-1 is one V-cycle of a single-field SA-AMG hierarchy on A_kk with that
// field's near-nullspace (rigid-body modes, translations), or a direct solve (SuperLU) of A_kk.
// Applied with x = 0 as a preconditioner (a fixed number of sweeps: a linear operator).
//
// Preset parameters (kind "block-relaxation"):
//   method   "gauss-seidel" | "jacobi";   sweeps (int > 0);   damping (omega, double > 0)
//   sublist "block solvers": one sublist per block name, or "default" for the others, each with
//       solver  "amg" (the rest of the sublist is MueLu's simple parameter list) | "direct"
// The coarse level of every block hierarchy is solved by the project's SuperLU: MueLu 13.2's
// Amesos2 KLU2 is inexact on several ranks and fails on blocks whose ids do not start at 0.
#pragma once

#include "block_preconditioner.h"
#include "block_system.h"
#include "hierarchy_utils.h"

#include <Teuchos_ParameterList.hpp>
#include <Xpetra_Operator.hpp>

#include <memory>
#include <string>
#include <vector>

namespace multigrid
{
  class SuperLUDirect;

  class BlockRelaxationOperator : public Xpetra::Operator<SC, LO, GO, NO>
  {
  public:
    /// Sets up one solver per diagonal block. Throws InputError for bad parameters.
    BlockRelaxationOperator(const BlockSystem& system, const Teuchos::ParameterList& parameters);
    ~BlockRelaxationOperator() override;

    RCP<const ::multigrid::Map> getDomainMap() const override { return full_map_; }
    RCP<const ::multigrid::Map> getRangeMap() const override { return full_map_; }
    /// Y = alpha M^-1 X + beta Y, M^-1 = `sweeps` block sweeps from x = 0.
    void apply(const ::multigrid::MultiVector& X, ::multigrid::MultiVector& Y,
               Teuchos::ETransp mode = Teuchos::NO_TRANS, SC alpha = 1.0, SC beta = 0.0) const override;
    void residual(const ::multigrid::MultiVector& X, const ::multigrid::MultiVector& B,
                  ::multigrid::MultiVector& R) const override;

    /// Per level l: the rows and nonzeros of every block's hierarchy at level l (blocks whose
    /// hierarchy has fewer levels, or that are solved directly, count 0 there); the
    /// operator complexity over the diagonal blocks; one note per block (its solver).
    void describe(PreconditionerInfo& info) const;

  private:
    struct BlockSolver;
    RCP<const ::multigrid::Map>               full_map_;
    RCP<const MapExtractor>                   extractor_;
    RCP<BlockedCrsMatrix>                     A_;
    std::vector<std::string>                  names_;
    bool                                      gauss_seidel_ = true;
    int                                       sweeps_       = 1;
    double                                    damping_      = 1.0;
    std::vector<std::unique_ptr<BlockSolver>> solvers_;
  };
} // namespace multigrid
