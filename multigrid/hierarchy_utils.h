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
  RCP<Hierarchy> build_single_field_hierarchy(const RCP<Matrix>& A, int dofs_per_node,
                                              const RCP<MultiVector>&       nullspace,
                                              const Teuchos::ParameterList& muelu_parameters,
                                              const RCP<MultiVector>&       coordinates = Teuchos::null);

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
