// Coarse-level rebalancing of the blocked hierarchies (the saddle-point, fully coupled and n x n
// presets): on levels whose rows per rank fall below a threshold, the rows of every block move to
// fewer ranks, so the coarse levels do not stay spread thinly over all ranks (issue 17).
//
// MueLu 13.2 has the blocked rebalancing factories (RebalanceBlockAcFactory, ...Interpolation...,
// ...Restriction...), driven by one Importer per block from a RepartitionFactory. What it lacks is
// a partitioner that keeps the blocks of a coupled system together:
//   - Zoltan2's geometric partitioners need each field's coordinates on every level, but a
//     blocked level keeps one "Coordinates" for all fields (RebalanceBlockInterpolationFactory
//     overwrites it block by block);
//   - the contact hierarchies' interface data, the map from a multiplier node to its slave
//     node, holds local ids: a multiplier and its slave node must stay on one rank.
// The project's partitioner merges ranks: with p parts and n ranks holding rows, the a-th of
// them (in rank order) sends all its rows, of every block, to rank floor(a p / n) (MueLu's
// RepartitionHeuristicFactory chooses p from the level's size, as for a single field). What was
// on one rank stays on one rank, in every block, so every interface datum moves along unchanged
// (PETSc's GAMG reduces the active ranks of its coarse levels the same way). The body labels and
// the multiplier-to-slave map are carried to the new rows by the factories here.
#pragma once

#include "types.h"

#include <MueLu_FactoryBase_fwd.hpp>
#include <Teuchos_ParameterList.hpp>

#include <map>
#include <memory>
#include <string>
#include <vector>

namespace multigrid
{
  /// The preset's sublist "repartition" (every entry optional): enable (false), start level (1),
  /// min rows per proc (800), max imbalance (1.2) - MueLu's meaning of the names.
  struct RebalanceSettings
  {
    bool   enable            = false;
    int    start_level       = 1;
    int    min_rows_per_proc = 800;
    double max_imbalance     = 1.2;
  };
  /// Reads the sublist; a value out of range is refused with a one-line InputError naming `preset`.
  RebalanceSettings rebalance_settings(const Teuchos::ParameterList& repartition, const std::string& preset);

  /// Rewires a factory-style blocked MueLu list (its "Hierarchy/AllLevel" names the blocked A, P
  /// and R factories) so that every coarse level is rebalanced by rank merging: per block a
  /// SubBlockAFactory of the unbalanced coarse A, the merge partition and MueLu's
  /// RepartitionFactory (Importer), one RepartitionHeuristicFactory for all blocks (one part
  /// count), and MueLu's RebalanceBlock{Ac,Interpolation,Restriction}Factory in the level's A, P
  /// and R slots. The blocks are the groups of the blocked prolongator (each group's "Nullspace"
  /// names the factory of the block's coarse nullspace, which moves with the rows). The contact
  /// lists' interface data follow the rows as well: the segregation labels (every
  /// SegregationLabelTransferFactory) and the multiplier-to-slave map (every
  /// InterfaceMappingTransferFactory becomes a RebalancedInterfaceMappingFactory).
  void add_block_rebalancing(Teuchos::ParameterList& muelu, const RebalanceSettings& settings);

  /// True if the list carries the rebalancing of add_block_rebalancing.
  bool has_block_rebalancing(const Teuchos::ParameterList& muelu);

  /// The factories of this file for a factory-style list (RankMergePartitionFactory,
  /// RebalancedInterfaceMappingFactory), or null if `name` is neither.
  /// `late`: the factories registered by name (project_factories.h, LateFactories), where the
  /// interface map finds the Importers and the unbalanced Galerkin product.
  RCP<const MueLu::FactoryBase>
  build_rebalancing_factory(const std::string& name, const Teuchos::ParameterList& list,
                            const std::map<std::string, RCP<const MueLu::FactoryBase>>&            factories,
                            const std::shared_ptr<const std::map<std::string, RCP<const MueLu::FactoryBase>>>& late);

  /// The rank-merge partition of rows on this rank: part floor(a * parts / active), a = this
  /// rank's index among the `active` ranks holding rows (-1 if it holds none). parts >= active:
  /// the rank keeps its rows (part = its own rank).
  int merged_part(int my_rank, int active_index, int active, int parts);
} // namespace multigrid
