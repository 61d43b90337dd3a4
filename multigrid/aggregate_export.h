// The aggregates of a blocked AMG hierarchy, for the pictures of the seeds' aggregation slides and
// for checking them: which fine-level nodes of each field form one coarse node on each coarser
// level, and whether an aggregate ever crosses a contact interface (it must not: the primal block
// is aggregated on the segregated matrix of every level).
//
// How they are obtained. MueLu keeps no aggregates after the set-up, and a blocked hierarchy's
// aggregation factories live inside its factory groups, out of reach of the hierarchy's keep
// flags. So the blocked list gets one more transfer factory per field, hung on its Galerkin
// product (the "TransferFactories" of BlockedRAPFactory or of the project's BlockedGalerkinFactory,
// run once per coarse level): it asks the field's aggregation factory for its aggregates of the
// finer level and stores, as user data on that
// level, the local aggregate of every owned node. After the set-up, the levels are composed: the
// nodes of level l + 1 are the aggregates of level l in their local order (MueLu's coarse maps
// number them so, and without repartitioning a coarse node stays on the rank of its aggregate),
// so the level-l aggregate of a fine node is a_l(... a_1(a_0(node))).
#pragma once

#include "block_system.h"
#include "types.h"

#include <Teuchos_ParameterList.hpp>

#include <string>
#include <vector>

namespace MueLu
{
  class FactoryBase;
  template <class SC, class LO, class GO, class NO>
  class Hierarchy;
} // namespace MueLu

namespace multigrid
{
  /// One field's aggregates, seen from its fine level.
  struct FieldAggregates
  {
    std::size_t block = 0;
    /// levels[l][i]: global id of the aggregate of level l (1 = the first coarse level's nodes)
    /// that contains this rank's owned fine-level node i of the field (block-local node order);
    /// -1 where the node belongs to none (e.g. a node without couplings).
    std::vector<std::vector<GO>> levels;
  };

  /// Adds the recording transfer factories to a factory-style blocked MueLu list (one with a
  /// BlockedPFactory whose groups name their "Aggregates", and a BlockedRAPFactory or
  /// BlockedGalerkinFactory). Throws InputError when the list has no such structure (e.g. a
  /// single-field preset).
  void record_aggregates(Teuchos::ParameterList& muelu);

  /// The recorder named "AggregateRecordFactory" in a MueLu list (for ProjectFactoryFactory):
  /// `list` holds "block"; `aggregates` is the factory its "Aggregates" names.
  RCP<const MueLu::FactoryBase>
  build_aggregate_record_factory(const Teuchos::ParameterList&        list,
                                 const RCP<const MueLu::FactoryBase>& aggregates);

  /// The recorded aggregates of every field of a set-up hierarchy built from a list passed
  /// through record_aggregates. Collective.
  std::vector<FieldAggregates> recorded_aggregates(MueLu::Hierarchy<SC, LO, GO, NO>& H,
                                                   const BlockSystem&                system);

  /// Writes the fields' fine-level nodes as a VTK point set (`path`.pvtu and one .vtu per rank,
  /// each written under a temporary name and renamed) with the point arrays "field" (block
  /// index), "body" (the segregation label of the primal block's node, -1 elsewhere), "rank" and
  /// "aggregate_level_L" for every coarse level. Node positions: the block's coordinates; the
  /// multiplier block of a contact system (no coordinates) sits at its primal slave nodes. A
  /// block without either is left out. Collective.
  void write_aggregates(const BlockSystem& system, const std::vector<FieldAggregates>& aggregates,
                        const std::string& path);

  /// Aggregates of level `level` that contain primal nodes of two different bodies (global
  /// count; 0 when the segregation works). Collective.
  long long aggregates_crossing_bodies(const BlockSystem& system, const FieldAggregates& primal, int level);
} // namespace multigrid
