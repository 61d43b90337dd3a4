// BlockPreconditioner::refresh: a blocked hierarchy set up again on a new matrix with the transfers
// of the first set-up.
//  - The prolongators are the same objects before and after, and every coarse operator is the
//    Galerkin product of the new matrix: A_1 x = R (A' (P x)) block by block to rounding, for a
//    contact preset (the tied-blocks saddle-point system, Poisson's ratio 0.3 -> 0.45) and for
//    the n x n FSI preset (the 3-block model system at level 1, coupled -> lower triangular).
//  - Refreshed on its own matrix, the preconditioner is the one first built (one application
//    of each to the same vector agrees to rounding), and GMRES with the refreshed one on the new
//    system converges in the iterations of a fresh one (within 2).
//  - Where transfers cannot be reused, refresh() says so and changes nothing: a preconditioner
//    built without keeping them, a preset kind without a blocked hierarchy, a system of another
//    size.
#include "block_preconditioner.h"
#include "coupled_fields.h"
#include "krylov_solver.h"
#include "model_problems.h"
#include "presets.h"

#include <Xpetra_BlockedCrsMatrix.hpp>
#include <Xpetra_MultiVectorFactory.hpp>
#include <gtest/gtest.h>

#include "test_helpers.h"

using namespace multigrid;
using test_helpers::comm;

namespace
{
  using MVF = Xpetra::MultiVectorFactory<SC, LO, GO, NO>;

  SetupOptions keeping_transfers()
  {
    SetupOptions options;
    options.keep_transfers = true;
    return options;
  }

  /// max over the nonzero blocks (i, j) of every coarse level l >= 1 of ||A_l,ij x - R_ii
  /// (A_ij (P_jj x))|| / ||A_l,ij x|| for a random x, where A is level l - 1's operator (level 0:
  /// `fine`); R = P^T in every shipped blocked preset. 1 where a block is missing on one side.
  double galerkin_defect(const BlockPreconditioner& M, const BlockSystem& fine)
  {
    double                      worst = 0;
    RCP<const BlockedCrsMatrix> finer = fine.blocked_matrix();
    for (std::size_t l = 0; l + 1 < M.info().levels.size(); ++l)
      {
        auto P      = Teuchos::rcp_dynamic_cast<const BlockedCrsMatrix>(M.prolongator(l));
        auto coarse = M.coarse_operator(l + 1);
        if (P.is_null())
          return 1.0;
        for (std::size_t i = 0; i < finer->Rows(); ++i)
          for (std::size_t j = 0; j < finer->Cols(); ++j)
            {
              auto Aij = finer->getMatrix(i, j), Cij = coarse->getMatrix(i, j);
              if (Aij.is_null() || Aij->getGlobalNumEntries() == 0)
                continue;
              if (Cij.is_null())
                return 1.0;
              auto Pii = P->getMatrix(i, i), Pjj = P->getMatrix(j, j);
              auto x = MVF::Build(Pjj->getDomainMap(), 1);
              x->randomize();
              auto Px = MVF::Build(Pjj->getRangeMap(), 1), APx = MVF::Build(Aij->getRangeMap(), 1);
              auto RAPx = MVF::Build(Pii->getDomainMap(), 1), Cx = MVF::Build(Cij->getRangeMap(), 1);
              Pjj->apply(*x, *Px);
              Aij->apply(*Px, *APx);
              Pii->apply(*APx, *RAPx, Teuchos::TRANS);
              Cij->apply(*x, *Cx);
              const double norm = Cx->getVector(0)->norm2();
              Cx->update(-1.0, *RAPx, 1.0);
              worst = std::max(worst, Cx->getVector(0)->norm2() / norm);
            }
        finer = coarse;
      }
    return worst;
  }

  RCP<MultiVector> apply(const BlockPreconditioner& M, const MultiVector& x)
  {
    auto y = MVF::Build(x.getMap(), 1);
    M.op()->apply(x, *y);
    return y;
  }

  /// The checks of the file's header for one preset on `system` and its variant `changed`.
  void check_refresh(const std::string& preset_name, const BlockSystem& system, const BlockSystem& changed)
  {
    SCOPED_TRACE(preset_name);
    auto preset = load_preset(preset_name);
    if (preset.parameters.isSublist("template parameters")) // a coarse level on these small systems
      apply_overrides(preset, {"template parameters/COARSE_MAX_SIZE=300"});
    BlockPreconditioner M(system, preset, keeping_transfers());
    ASSERT_GE(M.info().levels.size(), 2u);
    const auto P1       = M.prolongator(0);
    const auto coarse_1 = M.coarse_operator(1);
    auto       x        = MVF::Build(system.full_map(), 1);
    x->randomize();
    const auto first = apply(M, *x);

    ASSERT_TRUE(M.refresh(changed));
    EXPECT_TRUE(M.info().transfers_reused);
    EXPECT_EQ(M.prolongator(0).get(), P1.get()) << "the level-1 prolongator was built again";
    EXPECT_NE(M.coarse_operator(1).get(), coarse_1.get()) << "the coarse operator was not recomputed";
    EXPECT_LT(galerkin_defect(M, changed), 1e-12);

    auto b = MVF::Build(changed.full_map(), 1);
    b->putScalar(1.0);
    auto       x_refreshed = MVF::Build(changed.full_map(), 1), x_fresh = MVF::Build(changed.full_map(), 1);
    const auto refreshed = solve(changed, M, *x_refreshed, {});
    BlockPreconditioner fresh_M(changed, preset);
    const auto          fresh = solve(changed, fresh_M, *x_fresh, {});
    EXPECT_TRUE(refreshed.converged);
    EXPECT_LE(refreshed.iterations, fresh.iterations + 2);
    if (comm()->getRank() == 0)
      std::cout << preset_name << ": GMRES on the changed system " << refreshed.iterations
                << " (refreshed transfers), " << fresh.iterations << " (fresh hierarchy)\n";

    // Back on the first matrix: the preconditioner first built.
    ASSERT_TRUE(M.refresh(system));
    const auto again = apply(M, *x);
    again->update(-1.0, *first, 1.0);
    EXPECT_LT(again->getVector(0)->norm2(), 1e-12 * first->getVector(0)->norm2());
  }
} // namespace

TEST(TransferReuse, ContactPresets)
{
  TiedBlocksOptions options;
  options.level         = 1;
  const auto system     = tied_blocks_2d(comm(), options);
  options.poisson_ratio = 0.33;
  const auto changed    = tied_blocks_2d(comm(), options);
  for (const auto* name : {"emin(cheapsimple)", "sa-amg(cheapsimple)", "fully-coupled-sa-amg(simple)"})
    check_refresh(name, system, changed);
}

TEST(TransferReuse, NxNPreset)
{
  CoupledFieldsOptions options;
  options.level            = 2;
  const auto system        = coupled_fields_2d(comm(), options);
  options.lower_triangular = true;
  check_refresh("fully-coupled-sa-amg(bgs)", system, coupled_fields_2d(comm(), options));
}

TEST(TransferReuse, RefusedWhereNotPossible)
{
  const auto        system = tied_blocks_2d(comm(), {});
  TiedBlocksOptions larger;
  larger.level          = 1;
  const auto other_size = tied_blocks_2d(comm(), larger);

  BlockPreconditioner without(system, load_preset("emin(cheapsimple)"));
  EXPECT_FALSE(without.refresh(system));
  BlockPreconditioner cheapsimple(system, load_preset("cheapsimple(sa-amg)"), keeping_transfers());
  EXPECT_FALSE(cheapsimple.refresh(system));

  BlockPreconditioner M(system, load_preset("emin(cheapsimple)"), keeping_transfers());
  const auto          P1 = M.prolongator(0);
  EXPECT_FALSE(M.refresh(other_size));
  EXPECT_FALSE(M.info().transfers_reused);
  EXPECT_EQ(M.prolongator(0).get(), P1.get());
}
