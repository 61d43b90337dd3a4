// The sub-smoothers of the project's blocked level smoothers (SpaiSimpleSmoother,
// BlockGaussSeidelSmoother): each block's smoother is the "PreSmoother" that the "Smoother"
// factory of that block's factory manager builds on the level (internal to multigrid/).
#pragma once

#include "types.h"

#include <MueLu_FactoryManagerBase.hpp>
#include <MueLu_HierarchyUtils.hpp>
#include <MueLu_Level.hpp>
#include <MueLu_SmootherBase.hpp>

#include <vector>

namespace multigrid
{
  using FactoryManagers = std::vector<RCP<const MueLu::FactoryManagerBase>>;

  /// Declares every block's sub-smoother as an input of `level` (from DeclareInput).
  inline void declare_sub_smoothers(MueLu::Level& level, const FactoryManagers& managers)
  {
    for (const auto& manager : managers)
      {
        MueLu::SetFactoryManager scope(Teuchos::rcpFromRef(level), manager);
        level.DeclareInput("PreSmoother", manager->GetFactory("Smoother").get());
      }
  }

  /// The sub-smoother `manager` builds on `level` (from Setup).
  inline RCP<MueLu::SmootherBase<SC, LO, GO, NO>>
  sub_smoother(MueLu::Level& level, const RCP<const MueLu::FactoryManagerBase>& manager)
  {
    MueLu::SetFactoryManager scope(Teuchos::rcpFromRef(level), manager);
    return level.Get<RCP<MueLu::SmootherBase<SC, LO, GO, NO>>>("PreSmoother",
                                                               manager->GetFactory("Smoother").get());
  }
} // namespace multigrid
