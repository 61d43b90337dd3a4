// BlockPreconditioner: the one class that hides MueLu. Built from a BlockSystem and a Preset, it is
// an Xpetra operator approximating A^-1 (one V-cycle, one CheapSIMPLE application, or a direct
// solve) plus a description of what was built: levels, sizes, operator complexity, setup time.
#pragma once

#include "aggregate_export.h"
#include "block_system.h"
#include "presets.h"

#include <Xpetra_Operator.hpp>

#include <memory>
#include <string>
#include <vector>

namespace MueLu
{
  template <class SC, class LO, class GO, class NO>
  class Hierarchy;
}

namespace multigrid
{
  class CheapSimpleOperator;

  struct LevelInfo
  {
    long long              rows     = 0;
    long long              nonzeros = 0;
    std::vector<long long> block_rows; ///< per block, for blocked hierarchies
    int                    ranks = 0;  ///< ranks holding rows (blocked hierarchies; 0: not counted)
  };

  struct PreconditionerInfo
  {
    std::string              preset;
    std::string              kind;
    double                   setup_seconds = 0.0;
    /// The fully coupled level smoother's contraction check (SetupOptions::check_level_smoother),
    /// timed apart from setup_seconds: a check of the preset that a run pays once, not a part of
    /// the preconditioner that every Newton system's set-up pays.
    double                   smoother_check_seconds = 0.0;
    std::vector<LevelInfo>   levels; ///< level 0 = fine; empty for direct/cheapsimple outer
    double                   operator_complexity = 1.0;
    std::string              coarse_solver;
    std::vector<std::string> notes; ///< e.g. the inner solvers of CheapSIMPLE
    /// Set up by BlockPreconditioner::refresh() with the transfers of an earlier matrix.
    bool transfers_reused = false;
  };

  /// Whether the preset builds a blocked MueLu hierarchy (kinds saddle-point-amg, muelu,
  /// fully-coupled-amg): the presets whose aggregates can be kept and exported.
  bool builds_blocked_hierarchy(const Preset& preset);

  /// What a BlockPreconditioner keeps beyond what applying it needs.
  struct SetupOptions
  {
    /// The aggregates of every field and level, for aggregates() (blocked MueLu hierarchies
    /// only: InputError for other kinds).
    bool keep_aggregates = false;
    /// Every coarse level's transfers P and R, for refresh() (the MueLu hierarchies of the kinds
    /// saddle-point-amg, muelu, fully-coupled-amg, amg and the inner ones of cheapsimple; other
    /// kinds ignore it, and their refresh() returns false).
    bool keep_transfers = false;
    /// fully-coupled-amg: apply the level smoother to a random error and refuse the preset if
    /// it does not contract (check_level_smoother in fully_coupled_amg.h). A check of the
    /// preset: a solver that sets up one preset for many systems checks its first set-up only
    /// (refresh() does not check either), since the check costs a quarter of the set-up on the 3D
    /// tube and a smoother that diverges on a later system shows as a GMRES solve that does not
    /// converge.
    bool check_level_smoother = true;
  };

  class BlockPreconditioner
  {
  public:
    /// Builds (sets up) the preconditioner. Throws InputError if the preset does not fit the
    /// system (e.g. a saddle-point preset on a system without interface data).
    BlockPreconditioner(const BlockSystem& system, const Preset& preset, SetupOptions options = {});
    ~BlockPreconditioner();

    /// Sets the hierarchy up again for `system`'s matrix with the transfers kept from the first
    /// set-up: the coarse operators R A P, the level smoothers (with their Schur complements) and
    /// the coarse solver are recomputed, the aggregates and prolongators are not (MueLu's
    /// Hierarchy::SetupRe; cheapsimple: Â, the Schur complement and the update's Â anew, the
    /// inner hierarchies on their kept transfers). The new matrix may have another sparsity
    /// pattern. Returns false, changing nothing, where that is not possible: a preconditioner
    /// built without keep_transfers or of another kind, or a system whose block maps differ from
    /// those it was built for. Throws like the constructor if the set-up fails.
    bool refresh(const BlockSystem& system);

    RCP<Xpetra::Operator<SC, LO, GO, NO>> op() const { return op_; }

    /// Diagnostics of MueLu-based presets: block `block` of the prolongator from level
    /// `level` + 1 to `level` (level 0 = fine). Throws InputError for other kinds or levels.
    RCP<const Matrix>         prolongator_block(int level, int block) const;
    /// The whole prolongator from level `level` + 1 to `level` (a BlockedCrsMatrix for blocked
    /// hierarchies; cheapsimple: its inner primal AMG's). Throws InputError like prolongator_block.
    RCP<const Matrix> prolongator(int level) const;
    /// The operator of coarse level `level` (>= 1) of the hierarchy prolongator() reads (a
    /// BlockedCrsMatrix for blocked hierarchies). Throws InputError for other kinds or levels.
    RCP<const Matrix>         coarse_operator(int level) const;
    const PreconditionerInfo& info() const { return info_; }
    /// Every field's aggregates per coarse level (empty unless built with keep_aggregates).
    const std::vector<FieldAggregates>& aggregates() const { return aggregates_; }

  private:
    /// With the preset's "repartition/enable": adds the coarse-level rebalancing of
    /// block_rebalancing.h to the blocked list `muelu`.
    void rebalance_coarse_levels(Teuchos::ParameterList& muelu, const SetupOptions& options);

    RCP<Xpetra::Operator<SC, LO, GO, NO>> op_;
    RCP<MueLu::Hierarchy<SC, LO, GO, NO>> hierarchy_;
    RCP<CheapSimpleOperator>              cheap_simple_; ///< kind cheapsimple (also in op_)
    Preset                                preset_;
    bool                                  transfers_kept_ = false;
    bool                                  rebalanced_     = false; ///< coarse levels rebalanced
    std::vector<RCP<const Map>>           block_maps_; ///< of the system the transfers were built for
    PreconditionerInfo                    info_;
    std::vector<FieldAggregates>          aggregates_;
  };
} // namespace multigrid
