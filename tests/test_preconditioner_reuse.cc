// BlockPreconditioner::refresh: a MueLu hierarchy set up again on a new matrix with the transfers
// of the first set-up (blocked presets, CheapSIMPLE's inner AMG, a single-field AMG).
//  - The prolongators are the same objects before and after, and every coarse operator of a
//    blocked hierarchy is the Galerkin product of the new matrix: A_1 x = R (A' (P x)) block by
//    block to rounding, for the contact presets (the tied-blocks saddle-point system at level 1,
//    Poisson's ratio 0.3 -> 0.33, its stored zeros dropped: another sparsity pattern) and the n x n FSI
//    preset (the 3-block model system at level 2, coupled -> lower triangular); for CheapSIMPLE the same
//    holds for its inner primal AMG on the new primal block (its Schur complement is formed anew).
//  - Refreshed on its own matrix, the preconditioner is the one first built (one application
//    of each to the same vector agrees to rounding), and GMRES with the refreshed one on the new
//    system converges in the iterations of a fresh one (within 2).
//  - Where transfers cannot be reused, refresh() says so and changes nothing: a preconditioner
//    built without keeping them, a preset kind without a MueLu hierarchy (direct), a system of
//    another size.
#include "block_preconditioner.h"
#include "coupled_fields.h"
#include "krylov_solver.h"
#include "model_problems.h"
#include "presets.h"

#include <Xpetra_BlockedCrsMatrix.hpp>
#include <Xpetra_MatrixFactory.hpp>
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

  /// Block (i, j) of `A`: of a BlockedCrsMatrix, or `A` itself as the one block (0, 0).
  RCP<const Matrix> block(const RCP<const Matrix>& A, std::size_t i, std::size_t j)
  {
    auto blocked = Teuchos::rcp_dynamic_cast<const BlockedCrsMatrix>(A);
    return blocked.is_null() ? A : RCP<const Matrix>(blocked->getMatrix(i, j));
  }

  /// max over the nonzero blocks (i, j) of every coarse level l >= 1 of ||A_l,ij x - R_ii
  /// (A_ij (P_jj x))|| / ||A_l,ij x|| for a random x, where A is level l - 1's operator (level 0:
  /// `fine`, the matrix the hierarchy's level 0 holds); R = P^T in every shipped preset. 1 where a
  /// block is missing on one side.
  double galerkin_defect(const BlockPreconditioner& M, RCP<const Matrix> finer)
  {
    double worst = 0;
    for (std::size_t l = 0; l + 1 < M.info().levels.size(); ++l)
      {
        const auto        P       = M.prolongator(l);
        const auto        coarse  = M.coarse_operator(l + 1);
        auto              blocked = Teuchos::rcp_dynamic_cast<const BlockedCrsMatrix>(finer);
        const std::size_t n       = blocked.is_null() ? 1 : blocked->Rows();
        for (std::size_t i = 0; i < n; ++i)
          for (std::size_t j = 0; j < n; ++j)
            {
              auto Aij = block(finer, i, j), Cij = block(coarse, i, j);
              if (Aij.is_null() || Aij->getGlobalNumEntries() == 0)
                continue;
              if (Cij.is_null())
                return 1.0;
              auto Pii = block(P, i, i), Pjj = block(P, j, j);
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
    if (preset.parameters.isSublist("primal solver"))
      apply_overrides(preset, {"primal solver/coarse: max size=300"});
    if (preset.kind == "amg")
      apply_overrides(preset, {"MueLu/coarse: max size=300"});
    BlockPreconditioner M(system, preset, keeping_transfers());
    ASSERT_GE(M.info().levels.size(), 2u);
    const auto P1       = M.prolongator(0);
    auto       x        = MVF::Build(system.full_map(), 1);
    x->randomize();
    const auto first = apply(M, *x);

    ASSERT_TRUE(M.refresh(changed));
    EXPECT_TRUE(M.info().transfers_reused);
    EXPECT_EQ(M.prolongator(0).get(), P1.get()) << "the level-1 prolongator was built again";
    // The hierarchy's fine level: the whole matrix, or CheapSIMPLE's primal block. The coarse
    // operators are those of the new matrix, not the old one's (MueLu may recompute them in
    // place: the same objects).
    const auto fine = [&](const BlockSystem& s) -> RCP<const Matrix> {
      if (builds_blocked_hierarchy(preset))
        return s.blocked_matrix();
      if (preset.kind == "cheapsimple")
        return s.blocked_matrix()->getMatrix(0, 0);
      return s.merged_matrix();
    };
    EXPECT_LT(galerkin_defect(M, fine(changed)), 1e-12);
    EXPECT_GT(galerkin_defect(M, fine(system)), 1e-6) << "the coarse operators are the old matrix's";

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

namespace
{
  /// `system` with the entries of its matrix that are exactly zero dropped: the same maps, another
  /// sparsity pattern (the dual multipliers' D stores its zero off-diagonal entries), as a contact
  /// Newton step's matrix whose mortar linearization couples other nodes than the last one's.
  BlockSystem without_zeros(const BlockSystem& system)
  {
    const auto& A = *system.merged_matrix();
    auto        B = Xpetra::MatrixFactory<SC, LO, GO, NO>::Build(A.getRowMap(), A.getNodeMaxNumRowEntries());
    Teuchos::ArrayView<const LO> columns;
    Teuchos::ArrayView<const SC> values;
    for (LO i = 0; i < static_cast<LO>(A.getNodeNumRows()); ++i)
      {
        A.getLocalRowView(i, columns, values);
        std::vector<GO> kept_columns;
        std::vector<SC> kept_values;
        for (int k = 0; k < columns.size(); ++k)
          if (values[k] != 0.0)
            {
              kept_columns.push_back(A.getColMap()->getGlobalElement(columns[k]));
              kept_values.push_back(values[k]);
            }
        B->insertGlobalValues(A.getRowMap()->getGlobalElement(i), kept_columns, kept_values);
      }
    B->fillComplete(A.getDomainMap(), A.getRangeMap());
    std::vector<std::vector<GO>> owned(system.n_blocks());
    std::vector<BlockInfo>       blocks;
    for (std::size_t k = 0; k < system.n_blocks(); ++k)
      {
        blocks.push_back(system.block(k));
        for (LO i = 0; i < static_cast<LO>(system.block(k).map->getNodeNumElements()); ++i)
          owned[k].push_back(system.block(k).map->getGlobalElement(i));
      }
    EXPECT_LT(B->getGlobalNumEntries(), A.getGlobalNumEntries()) << "no stored zeros to drop";
    auto pruned = BlockSystem::from_merged(comm(), blocks, owned, B, system.rhs());
    if (system.has_interface())
      pruned.set_interface(system.interface());
    return pruned;
  }
} // namespace

TEST(TransferReuse, ContactPresets)
{
  TiedBlocksOptions options;
  options.level         = 1;
  const auto system     = tied_blocks_2d(comm(), options);
  options.poisson_ratio = 0.33;
  const auto changed    = without_zeros(tied_blocks_2d(comm(), options));
  for (const auto* name : {"emin(cheapsimple)", "sa-amg(cheapsimple)", "fully-coupled-sa-amg(simple)",
                           "cheapsimple(sa-amg)", "cheapsimple(pa-amg)"})
    check_refresh(name, system, changed);
}

namespace
{
  /// The primal block of a tied-blocks system as a one-field system (both bodies held by their
  /// Dirichlet boundaries: SPD).
  BlockSystem primal_only(const BlockSystem& system)
  {
    auto                         map = system.block(0).map;
    std::vector<std::vector<GO>> owned(1);
    for (LO i = 0; i < static_cast<LO>(map->getNodeNumElements()); ++i)
      owned[0].push_back(map->getGlobalElement(i));
    auto b = MVF::Build(map, 1);
    b->putScalar(1.0);
    auto one               = BlockSystem::from_merged(comm(), {system.block(0)}, owned,
                                                      system.blocked_matrix()->getMatrix(0, 0), b);
    one.block(0).nullspace = system.block(0).nullspace;
    return one;
  }
} // namespace

TEST(TransferReuse, SingleFieldPreset)
{
  TiedBlocksOptions options;
  options.level         = 1;
  const auto system     = primal_only(tied_blocks_2d(comm(), options));
  options.poisson_ratio = 0.33;
  check_refresh("sa-amg", system, primal_only(tied_blocks_2d(comm(), options)));
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
  BlockPreconditioner direct(system, load_preset("direct(superlu)"), keeping_transfers());
  EXPECT_FALSE(direct.refresh(system));

  BlockPreconditioner M(system, load_preset("emin(cheapsimple)"), keeping_transfers());
  const auto          P1 = M.prolongator(0);
  EXPECT_FALSE(M.refresh(other_size));
  EXPECT_FALSE(M.info().transfers_reused);
  EXPECT_EQ(M.prolongator(0).get(), P1.get());
}
