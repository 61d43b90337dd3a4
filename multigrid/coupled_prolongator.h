// Smoothed aggregation across the blocks of an n x n system: one damped-Jacobi step of the whole
// blocked operator applied to the block-diagonal tentative prolongator,
//
//   P = (I - omega D^-1 A) diag(Pt_11, ..., Pt_nn),   D = diag(A),   omega = damping / lambda_max(D^-1 A),
//
// so that P_ij = delta_ij Pt_jj - omega D_i^-1 A_ij Pt_jj. MueLu's blocked SA (BlockedPFactory of
// per-block SaPFactory, the seeds' P = diag(P_1, ..., P_n)) smooths each field's basis functions
// with its own diagonal block only. Where two fields are tied strongly (the beam/solid penalty
// coupling: the beam follows the solid's motion), a coarse solid function then moves the solid
// alone and pulls against the tied beam, and the coarse space misses the coupled system's
// low-energy modes; the coupled step gives every coarse function of one field the response of the
// fields tied to it (on the beam/solid systems both directions are needed: P_BS, the beam
// following a coarse solid motion, or P_SB alone leaves the iteration counts as they were). The
// price: P is no longer block-diagonal, and the coarse operators R A P are denser (MueLu's
// BlockedRAPFactory multiplies such a P for two blocks; BlockedGalerkinFactory below for more).
//
// XML (a project factory, registered by name in ProjectFactoryFactory):
//   <ParameterList name="CoupledP">
//     <Parameter name="factory" type="string" value="CoupledSaPFactory"/>
//     <Parameter name="P" type="string" value="BlockedPtent"/>   a BlockedPFactory of tentative Ps
//     <Parameter name="sa: damping factor" type="double" value="1.33"/>
//   </ParameterList>
// and BlockedTransposeFactory with P = CoupledP for R = P^T (GenericRFactory works as well, but
// makes the factory compute P a second time).
#pragma once

#include "types.h"

#include <MueLu_PFactory.hpp>

#include <set>
#include <vector>

namespace multigrid
{
  /// Settings of the smoothing step.
  struct CoupledSmoothing
  {
    double damping          = 4.0 / 3.0; ///< omega = damping / lambda_max(D^-1 A)
    int    power_iterations = 10;        ///< power-method steps for lambda_max
    /// Block rows kept tentative (P_ii = Pt_ii, no off-diagonal blocks in row i): a field whose
    /// own SA smoothing is not wanted (the FSI fluid, a saddle point).
    std::set<std::size_t> tentative_rows;
  };

  /// P = (I - omega D^-1 A) Pt for the blocked operator `A` and the block-diagonal tentative
  /// prolongator `Pt`, lambda from the power method on D^-1 A (the whole blocked operator). Throws
  /// InputError if `Pt` is not block-diagonal with A's block structure or a diagonal block of A
  /// is empty.
  RCP<BlockedCrsMatrix> coupled_smoothed_prolongator(const BlockedCrsMatrix& A, const BlockedCrsMatrix& Pt,
                                                     const CoupledSmoothing& settings);

  /// R A P block by block (any blocks of P and R, each block's sums fill-complete). With
  /// block-diagonal P and R each block is R_ii A_ij P_jj, A_ij multiplied first with the transfer
  /// that has fewer entries per row of P (the same product, fewer flops where the fields' transfers
  /// differ: a tentative fluid beside a smoothed ALE field).
  RCP<BlockedCrsMatrix> blocked_galerkin_product(const BlockedCrsMatrix& R, const BlockedCrsMatrix& A,
                                                 const BlockedCrsMatrix& P);

  /// The blocked R = P^T of a blocked P (R_ji = P_ij^T).
  RCP<BlockedCrsMatrix> blocked_transpose(const BlockedCrsMatrix& P);

  /// The MueLu factory: "P" from the coarse level's blocked tentative prolongator (the factory
  /// named "P"), "A" the fine level's blocked operator; parameters "sa: damping factor",
  /// "sa: eigenvalue estimate num iterations" and "tentative blocks" (block numbers separated by
  /// spaces). In restriction mode (GenericRFactory) it sets "R" = P^T.
  class CoupledSaPFactory : public MueLu::PFactory
  {
  public:
    RCP<const Teuchos::ParameterList> GetValidParameterList() const override;
    void                              DeclareInput(MueLu::Level& fine, MueLu::Level& coarse) const override;
    void                              Build(MueLu::Level& fine, MueLu::Level& coarse) const override;
    void                              BuildP(MueLu::Level& fine, MueLu::Level& coarse) const override;
  };

  /// "R" = P^T of the coarse level's blocked "P" (MueLu 13.2's TransPFactory takes no blocked P).
  class BlockedTransposeFactory : public MueLu::TwoLevelFactoryBase
  {
  public:
    RCP<const Teuchos::ParameterList> GetValidParameterList() const override;
    void                              DeclareInput(MueLu::Level& fine, MueLu::Level& coarse) const override;
    void                              Build(MueLu::Level& fine, MueLu::Level& coarse) const override;
  };

  /// "A" = R A P of the blocked operators (MueLu 13.2's BlockedRAPFactory fails where a block of
  /// the product sums more than two products, as a 3 x 3 system with a coupled P does, and forms
  /// A P first in every block). Like BlockedRAPFactory it runs the factories of its XML sublist
  /// "TransferFactories" after each product (aggregate_export.h hangs its recorders there).
  class BlockedGalerkinFactory : public MueLu::TwoLevelFactoryBase
  {
  public:
    RCP<const Teuchos::ParameterList> GetValidParameterList() const override;
    void                              DeclareInput(MueLu::Level& fine, MueLu::Level& coarse) const override;
    void                              Build(MueLu::Level& fine, MueLu::Level& coarse) const override;
    /// A factory built on the coarse level after the product (MueLu's FactoryFactory calls this
    /// for every entry of "TransferFactories").
    void AddTransferFactory(const RCP<const MueLu::FactoryBase>& factory) { transfers_.push_back(factory); }

  private:
    std::vector<RCP<const MueLu::FactoryBase>> transfers_;
  };
} // namespace multigrid
