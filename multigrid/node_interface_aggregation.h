// Aggregates of one block copied from another block's aggregates through a node-to-node mapping,
// a MueLu factory (named in factory lists as "NodeInterfaceAggregationFactory"):
//   - contact/meshtying (seed 000, idea 1): every multiplier node joins the aggregate of "its"
//     slave node, so coarse multipliers stay in one-to-one correspondence with coarse slave nodes
//     on every level;
//   - n x n systems (fully_coupled_amg.h, "block aggregates"): a field on another field's mesh
//     (the FSI's ALE mesh is the fluid mesh without the interface) takes the aggregates of the
//     leader field's node at the same position, so both fields' coarse levels are one coarse mesh.
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
} // namespace multigrid
