#include "block_rebalancing.h"

#include "hierarchy_utils.h"
#include "project_factories.h"

#include <MueLu_Exceptions.hpp>
#include <MueLu_Factory.hpp>
#include <MueLu_FactoryManagerBase.hpp>
#include <MueLu_Level.hpp>
#include <MueLu_Monitor.hpp>
#include <MueLu_SingleLevelFactoryBase.hpp>
#include <MueLu_TwoLevelFactoryBase.hpp>

#include <Xpetra_BlockedCrsMatrix.hpp>
#include <Xpetra_Import.hpp>
#include <Xpetra_MatrixFactory.hpp>
#include <Xpetra_StridedMap.hpp>
#include <Xpetra_VectorFactory.hpp>

#include <Teuchos_CommHelpers.hpp>

#include <vector>

namespace multigrid
{
  namespace
  {
    using MueLu::Level;
    using FactoryBase = MueLu::FactoryBase;
    using Import      = Xpetra::Import<LO, GO, NO>;
    using GOVector    = Xpetra::Vector<GO, LO, GO, NO>;
    using List        = Teuchos::ParameterList;
    using Late        = std::map<std::string, RCP<const FactoryBase>>;

    // Names of the entries add_block_rebalancing adds to the "Factories" list.
    const std::string heuristic_name    = "RebalanceHeuristic";
    const std::string sub_a_prefix      = "RebalanceA";
    const std::string partition_prefix  = "RebalancePartition";
    const std::string importer_prefix   = "RebalanceImporter";
    const std::string group_prefix      = "RebalanceGroup";
    const std::string rebalanced_a_name = "RebalancedA";
    const std::string completed_name    = "RebalanceCompletedA";
    /// The name block k's Importer is registered as (project_factories.h, LateFactories):
    /// factories defined before the Galerkin product (the segregation labels, the interface map)
    /// find it when the hierarchy is set up (naming it in the list would be a definition cycle:
    /// labels -> importer -> R A P -> P -> aggregates -> filtered A -> labels).
    std::string importer_key(std::size_t k)
    {
      return "Importer of block " + std::to_string(k);
    }
    /// ... and of the Galerkin product before rebalancing.
    const std::string unbalanced_key = "Unbalanced A";

    /// The rank-merge partition of the rows of "A" (one block of the unbalanced coarse level):
    /// "Partition" holds, for every row, the rank it moves to (MueLu's RepartitionFactory, with
    /// "repartition: remap parts" = false, sends part p to rank p).
    class RankMergePartitionFactory : public MueLu::SingleLevelFactoryBase
    {
    public:
      RCP<const List> GetValidParameterList() const override
      {
        auto list = Teuchos::rcp(new List());
        list->set<RCP<const FactoryBase>>("A", Teuchos::null, "Generating factory of the block to partition");
        list->set<RCP<const FactoryBase>>("level A", Teuchos::null,
                                          "Generating factory of the whole unbalanced level operator");
        list->set<RCP<const FactoryBase>>("number of partitions", Teuchos::null,
                                          "Generating factory of the number of parts");
        return list;
      }

      void DeclareInput(Level& level) const override
      {
        Input(level, "A");
        level.DeclareInput("A", GetFactory("level A").get(), this); // a product named "A"
        Input(level, "number of partitions");
      }

      void Build(Level& level) const override
      {
        MueLu::FactoryMonitor monitor(*this, "Rank-merge partition", level);
        const RCP<Matrix> A     = Get<RCP<Matrix>>(level, "A");
        const int         parts = Get<int>(level, "number of partitions");
        if (parts == -1) // no rebalancing on this level: RepartitionFactory does not read it
          {
            Set(level, "Partition", RCP<GOVector>());
            return;
          }
        const auto rows   = A->getRowMap();
        const auto comm   = rows->getComm();
        const int  n_rank = comm->getSize();
        // Which ranks hold rows of the level (the whole level: every block is asked, and a
        // rank holding rows of another block only still counts, so all blocks agree).
        const auto whole = level.Get<RCP<Matrix>>("A", GetFactory("level A").get());
        const int  holds = whole->getRowMap()->getNodeNumElements() > 0 ? 1 : 0;
        std::vector<int> all(n_rank, 0);
        Teuchos::gatherAll(*comm, 1, &holds, n_rank, all.data());
        int active = 0, index = -1;
        for (int r = 0; r < n_rank; ++r)
          {
            if (r == comm->getRank() && all[r] == 1)
              index = active;
            active += all[r];
          }
        const int part          = merged_part(comm->getRank(), index, active, parts);
        auto      decomposition = Xpetra::VectorFactory<GO, LO, GO, NO>::Build(rows, false);
        decomposition->putScalar(part);
        Set(level, "Partition", decomposition);
      }
    };

    /// The multiplier-to-slave node map of the coarse level, in the rebalanced numbering. Input:
    /// the finer level's "CoarseDualNodeID2PrimalNodeID" (local ids of the unbalanced coarse
    /// level) and both blocks' Importers; a multiplier node and its slave node moved to one rank
    /// (the rank-merge partition), so the map is rewritten through global ids: each multiplier
    /// DOF carries the global id of its slave node's first DOF to its new rank.
    class RebalancedInterfaceMappingFactory : public MueLu::TwoLevelFactoryBase
    {
    public:
      using DualToPrimal = std::map<LO, LO>;

      RCP<const List> GetValidParameterList() const override
      {
        auto list = Teuchos::rcp(new List());
        list->set<RCP<const FactoryBase>>("CoarseDualNodeID2PrimalNodeID", Teuchos::null,
                                          "Generating factory of the coarse map (the multipliers' "
                                          "aggregation, on the finer level)");
        list->set<int>("number of DOFs per dual node", 1, "Multiplier DOFs per multiplier node");
        return list;
      }

      void DeclareInput(Level& fine, Level& coarse) const override
      {
        Input(fine, "CoarseDualNodeID2PrimalNodeID");
        coarse.DeclareInput("A", unbalanced_operator().get(), this);
        for (std::size_t k = 0; k < 2; ++k)
          coarse.DeclareInput("Importer", importer_factory(k).get(), this);
      }

      void Build(Level& fine, Level& coarse) const override
      {
        MueLu::FactoryMonitor monitor(*this, "Multiplier-to-slave map of the rebalanced level", coarse);
        auto map = Get<RCP<DualToPrimal>>(fine, "CoarseDualNodeID2PrimalNodeID");
        const RCP<const Import> primal = coarse.Get<RCP<const Import>>("Importer", importer_factory(0).get());
        const RCP<const Import> dual   = coarse.Get<RCP<const Import>>("Importer", importer_factory(1).get());
        TEUCHOS_TEST_FOR_EXCEPTION(primal.is_null() != dual.is_null(), MueLu::Exceptions::RuntimeError,
                                   "RebalancedInterfaceMappingFactory: one block rebalanced, the other not, "
                                   "on level " << coarse.GetLevelID());
        if (primal.is_null())
          {
            Set(coarse, "DualNodeID2PrimalNodeID", map);
            return;
          }
        const int  dual_dpn   = GetParameterList().get<int>("number of DOFs per dual node");
        const int  primal_dpn = primal_dofs_per_node(coarse);
        const auto source     = dual->getSourceMap();
        TEUCHOS_TEST_FOR_EXCEPTION(static_cast<std::size_t>(source->getNodeNumElements()) !=
                                       map->size() * static_cast<std::size_t>(dual_dpn),
                                   MueLu::Exceptions::RuntimeError,
                                   "RebalancedInterfaceMappingFactory: " << map->size()
                                       << " multiplier nodes for " << source->getNodeNumElements()
                                       << " DOFs on level " << coarse.GetLevelID());
        auto slave = Xpetra::VectorFactory<GO, LO, GO, NO>::Build(source, false);
        {
          auto data = slave->getDataNonConst(0);
          for (const auto& [dual_node, primal_node] : *map)
            for (int k = 0; k < dual_dpn; ++k)
              data[dual_node * dual_dpn + k] =
                  primal_node == no_primal_node
                      ? GO(-1)
                      : primal->getSourceMap()->getGlobalElement(primal_node * primal_dpn);
        }
        auto moved = Xpetra::VectorFactory<GO, LO, GO, NO>::Build(dual->getTargetMap(), false);
        moved->doImport(*slave, *dual, Xpetra::INSERT);

        const auto target  = primal->getTargetMap();
        const auto data    = moved->getData(0);
        auto       rebuilt = Teuchos::rcp(new DualToPrimal());
        for (LO node = 0; node * dual_dpn < static_cast<LO>(data.size()); ++node)
          {
            const GO slave_dof = data[node * dual_dpn];
            if (slave_dof < 0)
              {
                (*rebuilt)[node] = no_primal_node;
                continue;
              }
            const LO local = target->getLocalElement(slave_dof);
            TEUCHOS_TEST_FOR_EXCEPTION(local == Teuchos::OrdinalTraits<LO>::invalid() || local % primal_dpn != 0,
                                       MueLu::Exceptions::RuntimeError,
                                       "RebalancedInterfaceMappingFactory: multiplier node "
                                           << node << " and its slave node (DOF " << slave_dof
                                           << ") are not on one rank after rebalancing level "
                                           << coarse.GetLevelID());
            (*rebuilt)[node] = local / primal_dpn;
          }
        Set(coarse, "DualNodeID2PrimalNodeID", rebuilt);
      }

      void set_late_factories(std::shared_ptr<const Late> late) { late_ = std::move(late); }

    private:
      std::shared_ptr<const Late> late_;

      RCP<const FactoryBase> registered(const std::string& name) const
      {
        return registered_factory(late_, name, "RebalancedInterfaceMappingFactory");
      }
      RCP<const FactoryBase> importer_factory(std::size_t k) const { return registered(importer_key(k)); }
      RCP<const FactoryBase> unbalanced_operator() const { return registered(unbalanced_key); }

      /// DOFs per coarse primal node: the striding of block 0 of the unbalanced coarse operator
      /// (the primal block's nullspace dimension, set by the coarse map factory).
      int primal_dofs_per_node(Level& coarse) const
      {
        auto blocked = Teuchos::rcp_dynamic_cast<BlockedCrsMatrix>(
            coarse.Get<RCP<Matrix>>("A", unbalanced_operator().get()));
        TEUCHOS_TEST_FOR_EXCEPTION(blocked.is_null(), MueLu::Exceptions::RuntimeError,
                                   "RebalancedInterfaceMappingFactory: the coarse operator is not blocked");
        auto strided = Teuchos::rcp_dynamic_cast<const StridedMap>(blocked->getRangeMapExtractor()->getMap(0));
        TEUCHOS_TEST_FOR_EXCEPTION(strided.is_null(), MueLu::Exceptions::RuntimeError,
                                   "RebalancedInterfaceMappingFactory: block 0 of level "
                                       << coarse.GetLevelID() << " has no striding information");
        return static_cast<int>(strided->getFixedBlockSize());
      }
    };

    /// The unbalanced blocked coarse operator with an empty matrix (of the block's strided maps)
    /// wherever a diagonal block is missing: the Galerkin product drops an all-zero block (the
    /// multipliers' C of mesh tying or of an all-active contact set), and MueLu's
    /// RebalanceBlockAcFactory builds the rebalanced block maps from the diagonal blocks only.
    class CompletedDiagonalFactory : public MueLu::SingleLevelFactoryBase
    {
    public:
      RCP<const List> GetValidParameterList() const override
      {
        auto list = Teuchos::rcp(new List());
        list->set<RCP<const FactoryBase>>("A", Teuchos::null, "Generating factory of the blocked operator");
        return list;
      }

      void DeclareInput(Level& level) const override { Input(level, "A"); }

      void Build(Level& level) const override
      {
        MueLu::FactoryMonitor monitor(*this, "Empty diagonal blocks for rebalancing", level);
        const RCP<Matrix>     A       = Get<RCP<Matrix>>(level, "A");
        auto                  blocked = Teuchos::rcp_dynamic_cast<BlockedCrsMatrix>(A);
        TEUCHOS_TEST_FOR_EXCEPTION(blocked.is_null(), MueLu::Exceptions::RuntimeError,
                                   "CompletedDiagonalFactory: the operator of level " << level.GetLevelID()
                                                                                      << " is not blocked");
        bool complete = true;
        for (std::size_t k = 0; k < blocked->Rows(); ++k)
          complete = complete && !blocked->getMatrix(k, k).is_null();
        if (complete)
          {
            Set(level, "A", A);
            return;
          }
        auto range  = blocked->getRangeMapExtractor();
        auto domain = blocked->getDomainMapExtractor();
        auto filled = Teuchos::rcp(new BlockedCrsMatrix(range, domain, 0));
        for (std::size_t i = 0; i < blocked->Rows(); ++i)
          for (std::size_t j = 0; j < blocked->Cols(); ++j)
            {
              RCP<Matrix> block = blocked->getMatrix(i, j);
              if (block.is_null() && i == j)
                {
                  block =
                      Xpetra::MatrixFactory<SC, LO, GO, NO>::Build(range->getMap(i), domain->getMap(j), 0);
                  block->fillComplete(domain->getMap(j), range->getMap(i));
                }
              if (!block.is_null())
                filled->setMatrix(i, j, block);
            }
        filled->fillComplete();
        Set(level, "A", Teuchos::rcp_dynamic_cast<Matrix>(filled));
      }
    };

    List& factory(List& factories, const std::string& name, const std::string& type)
    {
      List& f = factories.sublist(name);
      f.set("factory", type);
      return f;
    }

    /// The FactoryManager groups of the blocked prolongator, in block order.
    std::vector<std::string> field_groups(const List& factories, const std::string& blocked_p)
    {
      std::vector<std::string> groups;
      const List&              p = factories.sublist(blocked_p);
      for (std::size_t k = 1; p.isSublist("block" + std::to_string(k)); ++k)
        groups.push_back(p.sublist("block" + std::to_string(k)).get<std::string>("group"));
      if (groups.empty())
        throw InputError("coarse-level rebalancing: the blocked prolongator '" + blocked_p + "' names no block groups");
      return groups;
    }

    /// Names the factories of type `type` in `factories`.
    std::vector<std::string> factories_of_type(const List& factories, const std::string& type)
    {
      std::vector<std::string> names;
      for (auto it = factories.begin(); it != factories.end(); ++it)
        if (factories.entry(it).isList())
          {
            const List& f = factories.sublist(factories.name(it));
            if (f.isType<std::string>("factory") && f.get<std::string>("factory") == type)
              names.push_back(factories.name(it));
          }
      return names;
    }

    /// The contact lists' interface data follow the rows: the segregation labels through block 0's
    /// Importer, the multiplier-to-slave map through both.
    void rebalance_interface_data(List& factories)
    {
      for (const auto& name : factories_of_type(factories, "SegregationLabelTransferFactory"))
        factories.sublist(name).set("importer key", importer_key(0));
      for (const auto& name : factories_of_type(factories, "InterfaceMappingTransferFactory"))
        {
          List&             old        = factories.sublist(name);
          const std::string aggregates = old.get<std::string>("CoarseDualNodeID2PrimalNodeID");
          const int         dpn =
              value_or<int>(factories.sublist(aggregates), "number of DOFs per dual node", 1);
          List replacement;
          replacement.set("factory", std::string("RebalancedInterfaceMappingFactory"));
          replacement.set("CoarseDualNodeID2PrimalNodeID", aggregates);
          replacement.set("number of DOFs per dual node", dpn);
          old = replacement;
        }
    }
  } // namespace

  int merged_part(int my_rank, int active_index, int active, int parts)
  {
    if (active_index < 0 || parts >= active)
      return my_rank;
    return static_cast<int>(static_cast<long long>(active_index) * parts / active);
  }

  RebalanceSettings rebalance_settings(const Teuchos::ParameterList& r, const std::string& preset)
  {
    RebalanceSettings s;
    s.enable            = value_or<bool>(r, "enable", s.enable);
    s.start_level       = value_or<int>(r, "start level", s.start_level);
    s.min_rows_per_proc = value_or<int>(r, "min rows per proc", s.min_rows_per_proc);
    s.max_imbalance     = value_or<double>(r, "max imbalance", s.max_imbalance);
    if (s.start_level < 1 || s.min_rows_per_proc < 0 || s.max_imbalance < 1.0)
      throw InputError("preset '" + preset +
                       "': repartition expects 'start level' >= 1, 'min rows per proc' >= 0 and "
                       "'max imbalance' >= 1");
    return s;
  }

  void add_block_rebalancing(Teuchos::ParameterList& muelu, const RebalanceSettings& settings)
  {
    List&             f   = muelu.sublist("Factories");
    List&             all = muelu.sublist("Hierarchy").sublist("AllLevel");
    const std::string rap = all.get<std::string>("A"), P = all.get<std::string>("P"),
                      R      = all.get<std::string>("R");
    const auto groups        = field_groups(f, P);

    // One heuristic for all blocks: one part count, decided on the whole unbalanced level.
    List& heuristic = factory(f, heuristic_name, "RepartitionHeuristicFactory");
    heuristic.set("A", rap);
    heuristic.set("repartition: start level", settings.start_level);
    heuristic.set("repartition: min rows per proc", settings.min_rows_per_proc);
    heuristic.set("repartition: max imbalance", settings.max_imbalance);

    factory(f, completed_name, "CompletedDiagonalFactory").set("A", rap);
    // MueLu builds the list in order: a name must be defined before an entry uses it.
    for (std::size_t k = 0; k < groups.size(); ++k)
      {
        const std::string s   = std::to_string(k);
        // Only the block's rows matter to the partition: its maps, without a copy of its entries.
        List& sub = factory(f, sub_a_prefix + s, "ZeroSubBlockAFactory");
        sub.set("A", completed_name);
        sub.set("block row", static_cast<int>(k));
        sub.set("block col", static_cast<int>(k));
        List& partition = factory(f, partition_prefix + s, "RankMergePartitionFactory");
        partition.set("A", sub_a_prefix + s);
        partition.set("level A", rap);
        partition.set("number of partitions", heuristic_name);
        List& importer = factory(f, importer_prefix + s, "RepartitionFactory");
        importer.set("A", sub_a_prefix + s);
        importer.set("Partition", partition_prefix + s);
        importer.set("number of partitions", heuristic_name);
        importer.set("repartition: remap parts", false);
        // The block's coarse nullspace moves with its rows (RebalanceBlockRestrictionFactory).
        List& group = f.sublist(group_prefix + s);
        group.set("group", std::string("FactoryManager"));
        group.set("Importer", importer_prefix + s);
        group.set("Nullspace", f.sublist(groups[k]).get<std::string>("Nullspace"));
        importer.set("register as", importer_key(k));
      }
    List& rebalanced_p = factory(f, "RebalancedP", "RebalanceBlockInterpolationFactory");
    List& rebalanced_r = factory(f, "RebalancedR", "RebalanceBlockRestrictionFactory");
    List& rebalanced_a = factory(f, rebalanced_a_name, "RebalanceBlockAcFactory");
    for (std::size_t k = 0; k < groups.size(); ++k)
      for (List* r : {&rebalanced_p, &rebalanced_r, &rebalanced_a})
        r->sublist("block" + std::to_string(k + 1)).set("group", group_prefix + std::to_string(k));
    // Ranks left without rows keep empty rows in the level's communicator: the project's coarse
    // solver and level reports call collectives on every rank.
    rebalanced_p.set("P", P);
    rebalanced_p.set("A", rap);
    rebalanced_r.set("R", R);
    rebalanced_a.set("A", completed_name);
    for (List* r : {&rebalanced_p, &rebalanced_r, &rebalanced_a})
      r->set("repartition: use subcommunicators", false);
    rebalance_interface_data(f);
    f.sublist(rap).set("register as", unbalanced_key);
    all.set("A", rebalanced_a_name);
    all.set("P", std::string("RebalancedP"));
    all.set("R", std::string("RebalancedR"));
  }

  bool has_block_rebalancing(const Teuchos::ParameterList& muelu)
  {
    return muelu.isSublist("Factories") && muelu.sublist("Factories").isSublist(heuristic_name);
  }

  RCP<const MueLu::FactoryBase>
  build_rebalancing_factory(const std::string& name, const Teuchos::ParameterList& list,
                            const std::map<std::string, RCP<const MueLu::FactoryBase>>& factories,
                            const std::shared_ptr<const Late>&                          late)
  {
    RCP<MueLu::Factory> built;
    if (name == "RankMergePartitionFactory")
      built = Teuchos::rcp(new RankMergePartitionFactory());
    else if (name == "CompletedDiagonalFactory")
      built = Teuchos::rcp(new CompletedDiagonalFactory());
    else if (name == "RebalancedInterfaceMappingFactory")
      {
        auto mapping = Teuchos::rcp(new RebalancedInterfaceMappingFactory());
        mapping->SetParameter("number of DOFs per dual node",
                              Teuchos::ParameterEntry(value_or<int>(list, "number of DOFs per dual node", 1)));
        mapping->set_late_factories(late);
        built = mapping;
      }
    else
      return Teuchos::null;
    for (auto it = list.begin(); it != list.end(); ++it)
      {
        const std::string& input = list.name(it);
        if (input == "factory" || input == "number of DOFs per dual node")
          continue;
        const auto found = factories.find(list.get<std::string>(input));
        if (found == factories.end())
          throw InputError(name + ": '" + input + "' names no factory defined before it ('" +
                           list.get<std::string>(input) + "')");
        built->SetFactory(input, found->second);
      }
    return built;
  }
} // namespace multigrid
