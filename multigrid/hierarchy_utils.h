// Small helpers around MueLu hierarchies shared by the preconditioner classes (internal to
// multigrid/).
#pragma once

#include "types.h"

#include <Teuchos_ParameterList.hpp>

#include <string>
#include <utility>
#include <vector>

namespace MueLu
{
  template <class SC, class LO, class GO, class NO>
  class Hierarchy;
}

namespace multigrid
{
  using Hierarchy = MueLu::Hierarchy<SC, LO, GO, NO>;

  /// Single-field MueLu hierarchy from MueLu's (simple or factory-style) parameter list, with the
  /// near-nullspace set on level 0 (rigid-body modes make SA elasticity-aware) and, where given,
  /// the nodal coordinates (what MueLu's coarse-level repartitioning with Zoltan2 reads:
  /// "repartition: enable" in the list; a list asking for it without coordinates is refused).
  /// With `keep_transfers` every coarse level keeps its prolongator and restriction, for
  /// refresh_single_field_hierarchy.
  RCP<Hierarchy> build_single_field_hierarchy(const RCP<Matrix>& A, int dofs_per_node,
                                              const RCP<MultiVector>&       nullspace,
                                              const Teuchos::ParameterList& muelu_parameters,
                                              const RCP<MultiVector>&       coordinates    = Teuchos::null,
                                              bool                          keep_transfers = false);

  /// Sets a hierarchy built with keep_transfers up again for `A` (the row map of the first
  /// one's; any sparsity pattern): coarse operators, smoothers and coarse solver anew on the
  /// kept transfers (Hierarchy::SetupRe). `muelu_parameters`: the list it was built from.
  void refresh_single_field_hierarchy(Hierarchy& H, const RCP<Matrix>& A,
                                      const Teuchos::ParameterList& muelu_parameters);

  /// Hierarchy::SetupRe of a hierarchy whose coarse levels keep their P and R, for the new
  /// level-0 operator `A`: every other coarse-level datum is recomputed.
  void set_up_on_kept_transfers(Hierarchy& H, const RCP<Matrix>& A);

  /// Replaces the coarse solver of a set-up hierarchy by the project's SuperLU (on the coarsest
  /// level's operator).
  void use_superlu_coarse_solver(Hierarchy& H);

  /// The parameter `name` of `list`, or `fallback` when it is absent.
  template <typename T>
  T value_or(const Teuchos::ParameterList& list, const std::string& name, T fallback)
  {
    return list.isParameter(name) ? list.get<T>(name) : fallback;
  }

  /// (rows, nonzeros) of every level's operator, fine first.
  std::vector<std::pair<long long, long long>> level_sizes(Hierarchy& H);
} // namespace multigrid
