// SIMPLE block smoother for [[A00, A01], [A10, A11]] whose final update uses an explicit
// Â ≈ A00^-1 of its own choice ("Ainv": any InverseApproximationFactory - diag(A00)^-1 for
// SIMPLE, the absolute-row-sum lumped inverse for SIMPLEC, a SPAI for seed 001's beam/solid),
// independent of the Â inside the Schur complement S of the corrector. One sweep is
//   1. r = b - A x
//   2. predictor      dx1 ≈ A00^-1 r1            (sub-smoother of factory manager 1)
//   3. Schur residual r2' = r2 - A10 dx1
//   4. corrector      dx2 ≈ S^-1 r2'             (sub-smoother of factory manager 2 on S)
//   5. update         x1 += dx1 - Â A01 (omega dx2),   x2 += omega dx2
//      ("Undamped update": x1 += dx1 - Â A01 dx2, the 1/omega of seed 000's CheapSIMPLE slide).
// With S = A11 - A10 Â A01 (SpaiSchurComplementFactory) and exact sub-solves this is the exact
// block factorization of [[Â^-1, A01], [A10, A11]]. MueLu 13.2's SimpleSmoother is the same
// algorithm with diag(A00)^-1 in step 5, which is inconsistent with a SPAI Schur complement when
// A00 is far from diagonally dominant (the penalty-dominated beam block).
// With "Ainv" = diag(A00)^-1 and S = A11 - A10 diag(A00)^-1 A01 it is MueLu's SimpleSmoother,
// with both the absolute row sum MueLu's UseSIMPLEC.
// In the XML: factory "SpaiSimpleSmoother" with "Sweeps", "Damping factor", "Undamped update",
// "Ainv" (the InverseApproximationFactory of A00) and sublists block1 / block2 as for MueLu's
// SimpleSmoother.
#pragma once

#include "types.h"

#include <MueLu_FactoryManagerBase.hpp>
#include <MueLu_SmootherBase.hpp>
#include <MueLu_SmootherPrototype.hpp>

#include <Xpetra_MapExtractor.hpp>

#include <vector>

namespace multigrid
{
  class SpaiSimpleSmoother : public MueLu::SmootherPrototype<double, int, long long, ::multigrid::NO>
  {
  public:
    RCP<const Teuchos::ParameterList> GetValidParameterList() const override;
    void                              DeclareInput(MueLu::Level& level) const override;
    /// pos 0: predictor on A00, pos 1: corrector on the Schur complement (as MueLu's SIMPLE).
    void AddFactoryManager(RCP<const MueLu::FactoryManagerBase> manager, int pos);

    void Setup(MueLu::Level& level) override;
    void Apply(::multigrid::MultiVector& X, const ::multigrid::MultiVector& B, bool initial_guess_is_zero = false) const override;

    RCP<MueLu::SmootherPrototype<double, int, long long, ::multigrid::NO>> Copy() const override;
    std::string                                    description() const override { return "SIMPLE with an explicit inverse approximation in the update"; }
    size_t                                         getNodeSmootherComplexity() const override;

  private:
    std::vector<RCP<const MueLu::FactoryManagerBase>> managers_;
    RCP<::multigrid::Matrix>                           A_, A01_, A10_, inverse_;
    RCP<const ::multigrid::MapExtractor>    range_, domain_;
    RCP<MueLu::SmootherBase<double, int, long long, ::multigrid::NO>>           predictor_, corrector_;
  };
} // namespace multigrid
