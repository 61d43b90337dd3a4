// Block Gauss-Seidel level smoother for an n x n blocked matrix (the fully coupled FSI AMG's,
// seed 001: 3x BGS(0.8) with one sub-smoother per field). One sweep is
//     for k = 0 .. n-1:   r_k  = b_k - sum_j A_kj x_j          (the newest x_j)
//                         dx_k = M_k^-1 r_k                    (sub-smoother, from dx_k = 0)
//                         x_k += omega dx_k
// The same algorithm as MueLu 13.2's BlockedGaussSeidelSmoother, which computes it differently:
// it forms every block row's residual in a vector of the whole system (a copy of b per block and
// sweep), and hands the sub-smoother its zero start as an unknown guess, so that ILU(0) (MueLu's
// Ifpack2Smoother) first computes B - A 0 with a product by A_kk and Chebyshev spends one more
// product on the residual of that guess. Here the residual is formed per block row and the
// sub-smoother is told that it starts from zero (profile of the fully coupled preset's solve on the
// 3D tube at 75 k DOFs: those two residuals were 1/8 of it). From a zero initial guess the first
// sweep skips the products with the blocks j >= k, whose x_j are still zero.
// In the XML: factory "BlockGaussSeidelSmoother" with "Sweeps", "Damping factor" and sublists
// block1 .. blockN naming a factory manager with "A" (the diagonal block) and "Smoother".
#pragma once

#include "types.h"

#include <MueLu_FactoryManagerBase.hpp>
#include <MueLu_SmootherBase.hpp>
#include <MueLu_SmootherPrototype.hpp>

#include <vector>

namespace multigrid
{
  class BlockGaussSeidelSmoother
      : public MueLu::SmootherPrototype<::multigrid::SC, ::multigrid::LO, ::multigrid::GO, ::multigrid::NO>
  {
  public:
    RCP<const Teuchos::ParameterList> GetValidParameterList() const override;
    void                              DeclareInput(MueLu::Level& level) const override;
    /// The factory manager of block row `pos` (0-based): its "Smoother" is M_pos.
    void AddFactoryManager(RCP<const MueLu::FactoryManagerBase> manager, int pos);

    void Setup(MueLu::Level& level) override;
    void Apply(::multigrid::MultiVector& X, const ::multigrid::MultiVector& B,
               bool initial_guess_is_zero = false) const override;

    RCP<MueLu::SmootherPrototype<::multigrid::SC, ::multigrid::LO, ::multigrid::GO, ::multigrid::NO>>
                Copy() const override;
    std::string description() const override { return "block Gauss-Seidel (project)"; }
    /// The sub-smoothers' complexities summed (invalid if one of them does not know its own).
    size_t getNodeSmootherComplexity() const override;

  private:
    std::vector<RCP<const MueLu::FactoryManagerBase>>        managers_;
    RCP<::multigrid::Matrix>                                 A_;
    std::vector<std::vector<RCP<const ::multigrid::Matrix>>> blocks_; ///< A_kj, null where zero
    std::vector<
        RCP<const MueLu::SmootherBase<::multigrid::SC, ::multigrid::LO, ::multigrid::GO, ::multigrid::NO>>>
        inverses_;
  };
} // namespace multigrid
