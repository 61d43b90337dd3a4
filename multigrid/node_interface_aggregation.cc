#include "node_interface_aggregation.h"

#include "project_factories.h"

#include <MueLu_Aggregates.hpp>
#include <MueLu_AmalgamationInfo.hpp>
#include <MueLu_Monitor.hpp>
#include <MueLu_Utilities.hpp>

#include <Xpetra_BlockedCrsMatrix.hpp>
#include <Xpetra_MapFactory.hpp>

#include <algorithm>
#include <map>
#include <string>

namespace multigrid
{
  using MueLu::Level;
  using MueLu::NoFactory;
  using FactoryBase = MueLu::FactoryBase;

  RCP<const Teuchos::ParameterList> NodeInterfaceAggregationFactory::GetValidParameterList() const
  {
    auto list = Teuchos::rcp(new Teuchos::ParameterList());
    list->set<RCP<const FactoryBase>>("A", Teuchos::null,
                                      "Generating factory of the follower's diagonal block");
    list->set<RCP<const FactoryBase>>("Aggregates", Teuchos::null,
                                      "Generating factory of the leader's aggregates");
    list->set<RCP<const FactoryBase>>(
        "DualNodeID2PrimalNodeID", Teuchos::null,
        "Generating factory of the follower -> leader node mapping (coarse levels)");
    list->set<std::string>("level 0 mapping", "DualNodeID2PrimalNodeID",
                           "Name of the level-0 user data holding the follower -> leader node mapping");
    list->set<int>("number of DOFs per dual node", 1, "DOFs per follower node");
    list->set<RCP<const FactoryBase>>("blocked A", NoFactory::getRCP(),
                                      "Generating factory of the level's 2 x 2 blocked operator (as "
                                      "SubBlockAFactory's \"A\"), for its constraint block (1,0); read "
                                      "with \"separate inactive multipliers\"");
    list->set<bool>("separate inactive multipliers", false,
                    "Multiplier nodes whose constraint rows are all zero (inactive contact nodes: "
                    "identity rows) get aggregates apart from the active ones");
    list->set<bool>("aggregate unmatched nodes", false,
                    "Nodes without a leader node are aggregated on the follower's own node graph, "
                    "growing the copied aggregates (else: one-node aggregates)");
    list->set<bool>("leave out Dirichlet nodes", false,
                    "Nodes whose rows hold only their diagonal entry join no aggregate (zero rows of "
                    "the tentative prolongator, as MueLu's own aggregation treats Dirichlet nodes)");
    return list;
  }

  void NodeInterfaceAggregationFactory::DeclareInput(Level& level) const
  {
    Input(level, "A");
    Input(level, "Aggregates");
    if (separate())
      level.DeclareInput("A", GetFactory("blocked A").get(), this);
    if (level0_user_data(level))
      level.DeclareInput(GetParameterList().get<std::string>("level 0 mapping"), NoFactory::get(), this);
    else
      Input(level, "DualNodeID2PrimalNodeID");
  }

  void NodeInterfaceAggregationFactory::Build(Level& level) const
  {
    MueLu::FactoryMonitor monitor(*this, "Interface aggregation (node mapping)", level);
    const int             dpn    = GetParameterList().get<int>("number of DOFs per dual node");
    RCP<Matrix>           A      = Get<RCP<Matrix>>(level, "A");
    auto                  leader = Get<RCP<MueLu::Aggregates<LO, GO, NO>>>(level, "Aggregates");
    RCP<DualToPrimal>     to_leader =
        level0_user_data(level)
                ? level.Get<RCP<DualToPrimal>>(GetParameterList().get<std::string>("level 0 mapping"),
                                           NoFactory::get())
                : Get<RCP<DualToPrimal>>(level, "DualNodeID2PrimalNodeID");

    const RCP<const Map> dofs    = A->getRangeMap();
    const auto           comm    = dofs->getComm();
    const LO             n_local = static_cast<LO>(dofs->getNodeNumElements()) / dpn;
    TEUCHOS_TEST_FOR_EXCEPTION(static_cast<LO>(to_leader->size()) != n_local, MueLu::Exceptions::RuntimeError,
                               "NodeInterfaceAggregationFactory: the node mapping has "
                                   << to_leader->size() << " entries, expected " << n_local << " on level "
                                   << level.GetLevelID());
    const GO offset = dofs->getGlobalNumElements() > 0 ? dofs->getMinAllGlobalIndex() : 0;

    const bool              grow      = GetParameterList().get<bool>("aggregate unmatched nodes");
    const std::vector<bool> active    = active_nodes(level, *dofs, dpn, n_local);
    const std::vector<bool> dirichlet = dirichlet_nodes(*A, dpn, n_local);

    std::vector<GO> nodes(n_local);
    for (LO i = 0; i < n_local; ++i)
      nodes[i] = (dofs->getGlobalElement(i * dpn) - offset) / dpn;
    RCP<const Map> node_map = Xpetra::MapFactory<LO, GO, NO>::Build(
        dofs->lib(), dofs->getGlobalNumElements() / dpn, Teuchos::ArrayView<const GO>(nodes), 0, comm);

    auto aggregates = Teuchos::rcp(new MueLu::Aggregates<LO, GO, NO>(node_map));
    aggregates->setObjectLabel("interface aggregation");
    auto       vertex_to_aggregate        = aggregates->GetVertex2AggId()->getDataNonConst(0);
    auto       winner                     = aggregates->GetProcWinner()->getDataNonConst(0);
    const auto leader_vertex_to_aggregate = leader->GetVertex2AggId()->getData(0);

    auto coarse_to_leader = Teuchos::rcp(new DualToPrimal());
    // key: (leader aggregate, active)
    std::map<std::pair<LO, bool>, LO> leader_to_follower_aggregate;
    LO                                n_aggregates = 0;
    for (LO i = 0; i < n_local; ++i)
      {
        if (dirichlet[i])
          {
            // in no aggregate: UnamalgamateAggregates counts only nodes this rank "won"
            vertex_to_aggregate[i] = -1;
            winner[i]              = -1;
            continue;
          }
        const LO leader_node = to_leader->at(i);
        const LO leader_aggregate =
            leader_node == no_primal_node ? -1 : leader_vertex_to_aggregate[leader_node];
        LO aggregate;
        if (leader_aggregate < 0 && grow)
          {
            // aggregated below, on the follower's graph
            vertex_to_aggregate[i] = -1;
            winner[i]              = comm->getRank();
            continue;
          }
        if (leader_aggregate < 0)
          {
            // No leader node, or one in no aggregate (a prescribed slave node: Dirichlet rows are
            // in no aggregate): a one-node aggregate, whose coarse node again maps to no leader node.
            aggregate                      = n_aggregates++;
            (*coarse_to_leader)[aggregate] = no_primal_node;
          }
        else
          {
            const auto [it, added] =
                leader_to_follower_aggregate.try_emplace({leader_aggregate, active[i]}, n_aggregates);
            if (added) // coarse follower node -> coarse leader node
              (*coarse_to_leader)[n_aggregates++] = leader_aggregate;
            aggregate = it->second;
          }
        vertex_to_aggregate[i] = aggregate;
        winner[i]              = comm->getRank();
      }
    if (grow)
      {
        std::vector<LO> assigned(vertex_to_aggregate.begin(), vertex_to_aggregate.begin() + n_local);
        const LO        copied = n_aggregates;
        n_aggregates = aggregate_free_nodes(local_node_graph(*A, dpn, n_local), assigned, dirichlet, copied);
        for (LO a = copied; a < n_aggregates; ++a)
          (*coarse_to_leader)[a] = no_primal_node; // a coarse node of the follower only
        std::copy(assigned.begin(), assigned.end(), vertex_to_aggregate.begin()); // excluded: still -1
      }
    aggregates->SetNumAggregates(n_aggregates);
    aggregates->AggregatesCrossProcessors(false);

    // DOF <-> node translation for TentativePFactory: global DOF = offset + node * dpn + k.
    auto translation = Teuchos::rcp(new Teuchos::Array<LO>());
    for (LO i = 0; i < n_local; ++i)
      for (int k = 0; k < dpn; ++k)
        translation->push_back(i);
    auto amalgamation = Teuchos::rcp(new MueLu::AmalgamationInfo<LO, GO, NO>(
        translation, translation, node_map, node_map, dofs, dpn, offset, -1, 0, dpn));

    Set(level, "Aggregates", aggregates);
    Set(level, "UnAmalgamationInfo", amalgamation);
    Set(level, "CoarseDualNodeID2PrimalNodeID", coarse_to_leader);
  }

  /// Inactive contact nodes carry identity rows (lambda = 0, no displacement coupling); an
  /// aggregate mixing both gets the coarse row (n_inactive/n) lambda_c + sum(B_active x)/sqrt(n):
  /// its O(1) identity part outweighs B A^-1 B^T (~1e-3 on the rings) and the coarse multiplier
  /// spreads the contact force over nodes that must carry none, so the coarse level loses the
  /// contacts that hold nearly floating bodies. On coarse levels the split is exact: a coarse row
  /// of inactive nodes only is zero again.
  std::vector<bool> NodeInterfaceAggregationFactory::active_nodes(Level& level, const Map& dofs, int dpn,
                                                                  LO n_local) const
  {
    std::vector<bool> active(n_local, true);
    if (!separate())
      return active;
    auto blocked = Teuchos::rcp_dynamic_cast<Xpetra::BlockedCrsMatrix<SC, LO, GO, NO>>(
        level.Get<RCP<Matrix>>("A", GetFactory("blocked A").get()));
    TEUCHOS_TEST_FOR_EXCEPTION(blocked.is_null() || blocked->Rows() != 2 || blocked->Cols() != 2,
                               MueLu::Exceptions::RuntimeError,
                               "NodeInterfaceAggregationFactory: separate inactive multipliers "
                               "needs a 2 x 2 blocked operator on level "
                                   << level.GetLevelID());
    RCP<Matrix> B = blocked->getMatrix(1, 0);
    if (B.is_null()) // no constraint entries at all (Galerkin product of a zero block)
      return std::vector<bool>(n_local, false);
    TEUCHOS_TEST_FOR_EXCEPTION(static_cast<LO>(B->getNodeNumRows()) != n_local * dpn,
                               MueLu::Exceptions::RuntimeError,
                               "NodeInterfaceAggregationFactory: constraint block has "
                                   << B->getNodeNumRows() << " rows, expected " << n_local * dpn
                                   << " on level " << level.GetLevelID());
    const auto rows = B->getRowMap();
    for (LO i = 0; i < n_local; ++i)
      {
        bool nonzero = false;
        for (int k = 0; k < dpn; ++k)
          {
            const LO row = i * dpn + k;
            TEUCHOS_TEST_FOR_EXCEPTION(rows->getGlobalElement(row) != dofs.getGlobalElement(row),
                                       MueLu::Exceptions::RuntimeError,
                                       "NodeInterfaceAggregationFactory: constraint block rows "
                                       "are not ordered as the multiplier block's");
            Teuchos::ArrayView<const LO> columns;
            Teuchos::ArrayView<const SC> values;
            B->getLocalRowView(row, columns, values);
            for (const SC v : values)
              nonzero = nonzero || v != 0.0;
          }
        active[i] = nonzero;
      }
    return active;
  }

  std::vector<bool> NodeInterfaceAggregationFactory::dirichlet_nodes(const Matrix& A, int dpn,
                                                                     LO n_local) const
  {
    std::vector<bool> dirichlet(n_local, false);
    if (!GetParameterList().get<bool>("leave out Dirichlet nodes"))
      return dirichlet;
    // the rows MueLu's own aggregation leaves out (CoalesceDropFactory: no off-diagonal entry)
    const auto rows = MueLu::Utilities<SC, LO, GO, NO>::DetectDirichletRows(A);
    for (LO i = 0; i < n_local; ++i)
      dirichlet[i] =
          std::all_of(rows.begin() + i * dpn, rows.begin() + (i + 1) * dpn, [](bool r) { return r; });
    return dirichlet;
  }

  std::vector<std::vector<LO>> local_node_graph(const Matrix& A, int dpn, LO n_local)
  {
    const auto rows = A.getRowMap();
    const auto cols = A.getColMap();
    // column -> node of this rank's rows, -1 for a ghost
    std::vector<LO> column_node(cols->getNodeNumElements());
    for (std::size_t c = 0; c < column_node.size(); ++c)
      {
        const LO row   = rows->getLocalElement(cols->getGlobalElement(static_cast<LO>(c)));
        column_node[c] = row == Teuchos::OrdinalTraits<LO>::invalid() ? -1 : row / dpn;
      }
    std::vector<std::vector<LO>> graph(n_local);
    for (LO i = 0; i < n_local; ++i)
      {
        auto& neighbours = graph[i];
        for (int k = 0; k < dpn; ++k)
          {
            Teuchos::ArrayView<const LO> columns;
            Teuchos::ArrayView<const SC> values;
            A.getLocalRowView(i * dpn + k, columns, values);
            for (LO j = 0; j < columns.size(); ++j)
              if (values[j] != 0.0 && column_node[columns[j]] >= 0 && column_node[columns[j]] != i)
                neighbours.push_back(column_node[columns[j]]);
          }
        std::sort(neighbours.begin(), neighbours.end());
        neighbours.erase(std::unique(neighbours.begin(), neighbours.end()), neighbours.end());
      }
    return graph;
  }

  LO aggregate_free_nodes(const std::vector<std::vector<LO>>& graph, std::vector<LO>& aggregate,
                          const std::vector<bool>& excluded, LO n_aggregates)
  {
    const LO n    = static_cast<LO>(graph.size());
    auto     free = [&](LO i) { return !excluded[i] && aggregate[i] < 0; };
    // 1. roots: free nodes with free neighbours only
    for (LO i = 0; i < n; ++i)
      if (free(i) && !graph[i].empty() &&
          std::all_of(graph[i].begin(), graph[i].end(), [&](LO j) { return excluded[j] || free(j); }))
        {
          aggregate[i] = n_aggregates;
          for (const LO j : graph[i])
            if (!excluded[j])
              aggregate[j] = n_aggregates;
          ++n_aggregates;
        }
    // 2. the free nodes join the neighbouring aggregate they have the most edges to
    for (int pass = 0; pass < 2; ++pass)
      {
        const std::vector<LO> before = aggregate; // a pass attaches to the aggregates it started with
        for (LO i = 0; i < n; ++i)
          {
            if (!free(i))
              continue;
            std::map<LO, int> edges;
            for (const LO j : graph[i])
              if (!excluded[j] && before[j] >= 0)
                ++edges[before[j]];
            LO  best       = -1;
            int best_edges = 0;
            for (const auto& [a, count] : edges) // ascending a: the lower number wins a tie
              if (count > best_edges)
                {
                  best       = a;
                  best_edges = count;
                }
            if (best >= 0)
              aggregate[i] = best;
          }
      }
    // 3. what is left: new aggregates with their free neighbours
    for (LO i = 0; i < n; ++i)
      if (free(i))
        {
          aggregate[i] = n_aggregates;
          for (const LO j : graph[i])
            if (free(j))
              aggregate[j] = n_aggregates;
          ++n_aggregates;
        }
    return n_aggregates;
  }
} // namespace multigrid
