// The sub-smoothers of the project's blocked level smoothers (SpaiSimpleSmoother,
// BlockGaussSeidelSmoother): each block's smoother is the "PreSmoother" that the "Smoother"
// factory of that block's factory manager builds on the level (internal to multigrid/).
#pragma once

#include "types.h"

#include <MueLu_FactoryManagerBase.hpp>
#include <MueLu_HierarchyUtils.hpp>
#include <MueLu_Level.hpp>
#include <MueLu_SmootherBase.hpp>

#include <Xpetra_BlockedCrsMatrix.hpp>
#include <Xpetra_BlockedMultiVector.hpp>

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

  /// X and B of a blocked smoother's Apply as blocked vectors of A's maps: the hierarchy hands
  /// over blocked vectors on coarse levels (then x is X itself) and merged ones on the finest
  /// (then x is a split copy, which write_back merges into X at the end).
  struct BlockedViews
  {
    using Vectors = Xpetra::BlockedMultiVector<SC, LO, GO, NO>;
    BlockedViews(const BlockedCrsMatrix& A, MultiVector& X, const MultiVector& B)
        : x(Teuchos::rcp_dynamic_cast<Vectors>(Teuchos::rcpFromRef(X)))
        , b(Teuchos::rcp_dynamic_cast<const Vectors>(Teuchos::rcpFromRef(B)))
        , merged_x(x.is_null())
    {
      if (merged_x)
        x = Teuchos::rcp(new Vectors(A.getBlockedDomainMap(), Teuchos::rcpFromRef(X).getConst()));
      if (b.is_null())
        b = Teuchos::rcp(new Vectors(A.getBlockedRangeMap(), Teuchos::rcpFromRef(B)));
    }
    void write_back(MultiVector& X) const
    {
      if (merged_x)
        X.update(1.0, *x->Merge(), 0.0);
    }
    RCP<Vectors>       x;
    RCP<const Vectors> b;
    bool               merged_x;
  };
} // namespace multigrid
