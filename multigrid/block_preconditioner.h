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
  struct LevelInfo
  {
    long long              rows     = 0;
    long long              nonzeros = 0;
    std::vector<long long> block_rows; ///< per block, for blocked hierarchies
  };

  struct PreconditionerInfo
  {
    std::string              preset;
    std::string              kind;
    double                   setup_seconds = 0.0;
    std::vector<LevelInfo>   levels; ///< level 0 = fine; empty for direct/cheapsimple outer
    double                   operator_complexity = 1.0;
    std::string              coarse_solver;
    std::vector<std::string> notes; ///< e.g. the inner solvers of CheapSIMPLE
  };

  /// Whether the preset builds a blocked MueLu hierarchy (kinds saddle-point-amg, muelu,
  /// fully-coupled-amg): the presets whose aggregates can be kept and exported.
  bool builds_blocked_hierarchy(const Preset& preset);

  class BlockPreconditioner
  {
  public:
    /// Builds (sets up) the preconditioner. Throws InputError if the preset does not fit the
    /// system (e.g. a saddle-point preset on a system without interface data). With
    /// `keep_aggregates`, the aggregates of every field and level are kept for aggregates()
    /// (blocked MueLu hierarchies only: InputError for other kinds).
    BlockPreconditioner(const BlockSystem& system, const Preset& preset, bool keep_aggregates = false);
    ~BlockPreconditioner();

    RCP<Xpetra::Operator<SC, LO, GO, NO>> op() const { return op_; }

    /// Diagnostics of MueLu-based presets: block `block` of the prolongator from level
    /// `level` + 1 to `level` (level 0 = fine). Throws InputError for other kinds or levels.
    RCP<const Matrix>         prolongator_block(int level, int block) const;
    /// The whole prolongator from level `level` + 1 to `level` (a BlockedCrsMatrix for blocked
    /// hierarchies). Throws InputError like prolongator_block.
    RCP<const Matrix> prolongator(int level) const;
    const PreconditionerInfo& info() const { return info_; }
    /// Every field's aggregates per coarse level (empty unless built with keep_aggregates).
    const std::vector<FieldAggregates>& aggregates() const { return aggregates_; }

  private:
    RCP<Xpetra::Operator<SC, LO, GO, NO>> op_;
    RCP<MueLu::Hierarchy<SC, LO, GO, NO>> hierarchy_;
    PreconditionerInfo                    info_;
    std::vector<FieldAggregates>          aggregates_;
  };
} // namespace multigrid
