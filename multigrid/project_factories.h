// The project's own MueLu factories, for what MueLu 13.2 lacks, and the FactoryFactory that lets
// preset XML files name them like MueLu's own factories:
//   LevelSegregatedAFactory  the seeds' "filtered A" on every level: drops all entries that couple
//                            DOFs of two different bodies (a body label per primal DOF). MueLu
//                            13.2's SegregatedAFactory knows one DOF set (two bodies), reads a
//                            non-const map, which MapTransferFactory cannot provide on coarse
//                            levels, and decides column membership with the row owner's map only;
//                            this one imports the column labels.
//   SegregationLabelTransferFactory
//                            the body labels of the next level (through the tentative prolongator).
//   NodeInterfaceAggregationFactory
//                            multiplier aggregates copied from the slave-side primal aggregates
//                            (node-based), with an amalgamation that is consistent for a dual
//                            block numbered after the primal one (MueLu 13.2's is not); also a
//                            field's aggregates copied from another field on the same mesh
//                            (node_interface_aggregation.h).
//   AggregateRecordFactory   keeps a field's aggregates for export (aggregate_export.h).
//   SuperLUDirectSolver      coarse-level direct solver through the project's SuperLU adaptor,
//                            for single and blocked (merged on the fly) operators.
//   Ilu0Smoother             ILU(0) with faster triangular solves than Ifpack2's RILUK
//                            (ilu0_smoother.h), the sub-smoother type "ILU(0)".
//   GaussSeidelSmoother      symmetric Gauss-Seidel, faster sweeps than Ifpack2's
//                            (gauss_seidel_smoother.h), the sub-smoother type "SGS".
#pragma once

#include "types.h"

#include <MueLu_FactoryFactory_decl.hpp>
#include <MueLu_SmootherBase.hpp>

#include <map>
#include <memory>
#include <string>

namespace multigrid
{
  /// The seeds' "filtered A": A_seg(i,j) = A(i,j) if DOFs i and j carry the same body label,
  /// else 0 (the entry is removed). `labels`: one column holding the label of every owned row of
  /// A (looked up by global id); column labels are imported from the owners of the columns.
  RCP<Matrix> segregated_matrix(const Matrix& A, const MultiVector& labels);
  /// Two bodies given as one DOF set: label 1 inside `set`, 0 outside.
  RCP<Matrix> segregated_matrix(const Matrix& A, const Map& set);

  /// The SuperLUDirectSolver coarse solver, set up on A, for MueLu's coarse-solver slot of a
  /// hierarchy built from a simple parameter list (where preset XML cannot name it).
  RCP<MueLu::SmootherBase<SC, LO, GO, NO>> superlu_coarse_solver(const RCP<Matrix>& A);

  /// In a multiplier-to-slave node map ("DualNodeID2PrimalNodeID" of the coarse levels): a
  /// multiplier node whose slave node has every displacement component prescribed. MueLu leaves
  /// such Dirichlet nodes out of the primal aggregates; the multiplier still acts on the master
  /// side (M^T lambda), so NodeInterfaceAggregationFactory keeps it as a one-node aggregate on
  /// every level, mapped to no primal node.
  constexpr LO no_primal_node = -1;

  using FactoryMap        = std::map<std::string, RCP<const MueLu::FactoryBase>>;
  using FactoryManagerMap = std::map<std::string, RCP<MueLu::FactoryManagerBase>>;

  /// Factories a list entry registered under a name ("register as" NAME in its sublist), for
  /// entries defined before it that need it on coarse levels (block_rebalancing.h: the
  /// segregation labels and the interface map follow the Importers of the rebalanced Galerkin
  /// product, which the list defines after them). Looked up when the hierarchy is set up.
  using LateFactories = std::map<std::string, RCP<const MueLu::FactoryBase>>;

  /// The factory registered as `name` in `late`; throws (naming `who`) if there is none.
  RCP<const MueLu::FactoryBase> registered_factory(const std::shared_ptr<const LateFactories>& late,
                                                   const std::string& name, const std::string& who);

  class ProjectFactoryFactory : public MueLu::FactoryFactory<double, int, long long, ::multigrid::NO>
  {
    using Base = MueLu::FactoryFactory<double, int, long long, ::multigrid::NO>;

  public:
    RCP<const MueLu::FactoryBase> BuildFactory(const Teuchos::ParameterEntry&        param,
                                               const ::multigrid::FactoryMap&        factories,
                                               const ::multigrid::FactoryManagerMap& managers) const override;

  private:
    std::shared_ptr<LateFactories> late_ = std::make_shared<LateFactories>();
  };
} // namespace multigrid
