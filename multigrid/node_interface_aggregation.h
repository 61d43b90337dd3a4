// Aggregates of one block copied from another block's aggregates through a node-to-node mapping,
// a MueLu factory (named in factory lists as "NodeInterfaceAggregationFactory"):
//   - contact/meshtying (seed 000, idea 1): every multiplier node joins the aggregate of "its"
//     slave node, so coarse multipliers stay in one-to-one correspondence with coarse slave nodes
//     on every level;
//   - n x n systems (fully_coupled_amg.h, "block aggregates"): a field on another field's mesh
//     (the FSI's ALE mesh is the fluid mesh without the interface) takes the aggregates of the
//     leader field's node at the same position, so both fields' coarse levels are one coarse mesh;
//   - n x n systems, fields that share only an interface (the FSI fluid's interface nodes lie on
//     the structure's), with "aggregate unmatched nodes": the matched nodes take the leader's
//     aggregates, the others are aggregated on the follower's own node graph, where the copied
//     aggregates grow by a layer of the follower's nodes (aggregate_free_nodes), so that the
//     coarse interface is one coarse mesh for both fields.
// Node-based: the follower -> leader node mapping (local ids on the same rank) is user data on
// level 0 ("level 0 mapping") and the coarsened mapping produced here
// ("CoarseDualNodeID2PrimalNodeID", moved to the next level by MueLu's
// InterfaceMappingTransferFactory) on the levels below. Unlike MueLu 13.2's
// InterfaceAggregationFactory it numbers the follower's nodes relative to its first DOF, so that
// the amalgamation it hands to TentativePFactory is consistent for a block that does not start
// at global id 0 (Xpetra numbering).
#pragma once

#include "types.h"

#include <MueLu_Level.hpp>
#include <MueLu_SingleLevelFactoryBase.hpp>

#include <map>
#include <vector>

namespace multigrid
{
  class NodeInterfaceAggregationFactory : public MueLu::SingleLevelFactoryBase
  {
  public:
    using DualToPrimal = std::map<LO, LO>;

    RCP<const Teuchos::ParameterList> GetValidParameterList() const override;
    void                              DeclareInput(MueLu::Level& level) const override;
    void                              Build(MueLu::Level& level) const override;

  private:
    bool separate() const { return GetParameterList().get<bool>("separate inactive multipliers"); }
    bool level0_user_data(const MueLu::Level& level) const { return level.GetLevelID() == 0; }

    /// Active multiplier nodes: some constraint row of the node has a non-zero entry (all nodes
    /// when "separate inactive multipliers" is false).
    std::vector<bool> active_nodes(MueLu::Level& level, const Map& dofs, int dpn, LO n_local) const;
    /// Nodes all of whose rows of A hold nothing but their diagonal entry (Dirichlet rows), when
    /// "leave out Dirichlet nodes" is true (else none).
    std::vector<bool> dirichlet_nodes(const Matrix& A, int dpn, LO n_local) const;
  };

  /// The node graph of A's rows on this rank (dpn rows per node, node-major): for each node the
  /// other nodes of this rank its rows have non-zero entries in (ghost columns left out).
  std::vector<std::vector<LO>> local_node_graph(const Matrix& A, int dpn, LO n_local);

  /// Aggregates for the free nodes (aggregate < 0 and not `excluded`) of a node graph whose other
  /// nodes already have aggregates 0 .. n_aggregates - 1, MueLu's uncoupled phases in short:
  ///   1. a free node whose neighbours are all free becomes a new aggregate with them;
  ///   2. a free node joins the neighbouring aggregate it has the most edges to (ties: the lower
  ///      number), two passes, the second for the nodes next to those the first attached;
  ///   3. a node still free becomes a new aggregate with its free neighbours.
  /// Returns the new number of aggregates; new ones are numbered from n_aggregates on.
  LO aggregate_free_nodes(const std::vector<std::vector<LO>>& graph, std::vector<LO>& aggregate,
                          const std::vector<bool>& excluded, LO n_aggregates);
} // namespace multigrid
