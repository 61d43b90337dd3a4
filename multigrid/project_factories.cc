#include "project_factories.h"

#include "spai_factories.h"
#include "spai_simple_smoother.h"
#include "superlu_direct.h"

#include <MueLu_Aggregates.hpp>
#include <MueLu_AmalgamationInfo.hpp>
#include <MueLu_FactoryFactory.hpp>
#include <MueLu_Level.hpp>
#include <MueLu_SingleLevelFactoryBase.hpp>
#include <MueLu_SmootherFactory.hpp>
#include <MueLu_SmootherPrototype.hpp>
#include <MueLu_Monitor.hpp>

#include <Xpetra_BlockedCrsMatrix.hpp>
#include <Xpetra_BlockedMultiVector.hpp>
#include <Xpetra_ImportFactory.hpp>
#include <Xpetra_MapFactory.hpp>
#include <Xpetra_MatrixFactory.hpp>
#include <Xpetra_VectorFactory.hpp>

#include <memory>

namespace multigrid
{
  namespace
  {
    using MueLu::Level;
    using MueLu::NoFactory;
    using FactoryBase = MueLu::FactoryBase;

    /// A_seg(i,j) = A(i,j) if i and j are both in the segregation set or both outside, else 0.
    class LevelSegregatedAFactory : public MueLu::SingleLevelFactoryBase
    {
    public:
      RCP<const Teuchos::ParameterList> GetValidParameterList() const override
      {
        auto list = Teuchos::rcp(new Teuchos::ParameterList());
        list->set<RCP<const FactoryBase>>("A", Teuchos::null, "Generating factory of the matrix to filter");
        list->set<RCP<const FactoryBase>>("segregation dofs", Teuchos::null,
                                          "Generating factory of the segregation DOF map on coarse "
                                          "levels (MapTransferFactory); user data on level 0");
        return list;
      }

      void DeclareInput(Level& level) const override
      {
        Input(level, "A");
        if (level.GetLevelID() == 0)
          level.DeclareInput("segregation dofs", NoFactory::get(), this);
        else
          Input(level, "segregation dofs");
      }

      void Build(Level& level) const override
      {
        MueLu::FactoryMonitor monitor(*this, "Segregated matrix (filtered A)", level);
        RCP<Matrix>           A = Get<RCP<Matrix>>(level, "A");
        RCP<const Map>        set;
        if (level.GetLevelID() == 0)
          set = level.Get<RCP<const Map>>("segregation dofs", NoFactory::get());
        else
          set = Get<RCP<const Map>>(level, "segregation dofs");

        // Nothing to cut (e.g. mesh tying of bodies without coupling in A): no copy.
        RCP<Matrix> filtered = set->getGlobalNumElements() == 0 ? A : segregated_matrix(*A, *set);
        Set(level, "A", filtered);
      }
    };

    /// Interface aggregation for the multipliers (seed 000, idea 1): every multiplier node joins the
    /// aggregate of "its" slave node, so coarse multipliers stay in one-to-one correspondence with
    /// coarse slave nodes on every level. Node-based: the dual -> primal node mapping is user data
    /// on level 0 and the coarsened mapping produced here ("CoarseDualNodeID2PrimalNodeID") on the
    /// levels below. Unlike MueLu 13.2's factory it numbers multiplier nodes relative to the first
    /// multiplier DOF, so that the amalgamation it hands to TentativePFactory is consistent for a
    /// dual block that does not start at global id 0 (Xpetra numbering).
    class NodeInterfaceAggregationFactory : public MueLu::SingleLevelFactoryBase
    {
    public:
      using DualToPrimal = std::map<LO, LO>;

      RCP<const Teuchos::ParameterList> GetValidParameterList() const override
      {
        auto list = Teuchos::rcp(new Teuchos::ParameterList());
        list->set<RCP<const FactoryBase>>("A", Teuchos::null,
                                          "Generating factory of the dual diagonal block");
        list->set<RCP<const FactoryBase>>("Aggregates", Teuchos::null,
                                          "Generating factory of the primal aggregates");
        list->set<RCP<const FactoryBase>>(
            "DualNodeID2PrimalNodeID", Teuchos::null,
            "Generating factory of the dual -> primal node mapping (coarse levels)");
        list->set<int>("number of DOFs per dual node", 1, "Multiplier DOFs per multiplier node");
        return list;
      }

      void DeclareInput(Level& level) const override
      {
        Input(level, "A");
        Input(level, "Aggregates");
        if (level.GetLevelID() == 0)
          level.DeclareInput("DualNodeID2PrimalNodeID", NoFactory::get(), this);
        else
          Input(level, "DualNodeID2PrimalNodeID");
      }

      void Build(Level& level) const override
      {
        MueLu::FactoryMonitor monitor(*this, "Interface aggregation (multipliers)", level);
        const int             dpn    = GetParameterList().get<int>("number of DOFs per dual node");
        RCP<Matrix>           A      = Get<RCP<Matrix>>(level, "A");
        auto                  primal = Get<RCP<MueLu::Aggregates<LO, GO, NO>>>(level, "Aggregates");
        RCP<DualToPrimal>     dual_to_primal =
            level.GetLevelID() == 0
                    ? level.Get<RCP<DualToPrimal>>("DualNodeID2PrimalNodeID", NoFactory::get())
                    : Get<RCP<DualToPrimal>>(level, "DualNodeID2PrimalNodeID");

        const RCP<const Map> dofs    = A->getRangeMap();
        const auto           comm    = dofs->getComm();
        const LO             n_local = static_cast<LO>(dofs->getNodeNumElements()) / dpn;
        TEUCHOS_TEST_FOR_EXCEPTION(static_cast<LO>(dual_to_primal->size()) != n_local,
                                   MueLu::Exceptions::RuntimeError,
                                   "NodeInterfaceAggregationFactory: dual-to-primal mapping has "
                                       << dual_to_primal->size() << " entries, expected " << n_local
                                       << " on level " << level.GetLevelID());
        const GO offset = dofs->getGlobalNumElements() > 0 ? dofs->getMinAllGlobalIndex() : 0;

        std::vector<GO> nodes(n_local);
        for (LO i = 0; i < n_local; ++i)
          nodes[i] = (dofs->getGlobalElement(i * dpn) - offset) / dpn;
        RCP<const Map> node_map = Xpetra::MapFactory<LO, GO, NO>::Build(
            dofs->lib(), dofs->getGlobalNumElements() / dpn, Teuchos::ArrayView<const GO>(nodes), 0, comm);

        auto aggregates = Teuchos::rcp(new MueLu::Aggregates<LO, GO, NO>(node_map));
        aggregates->setObjectLabel("interface aggregation");
        auto       vertex_to_aggregate        = aggregates->GetVertex2AggId()->getDataNonConst(0);
        auto       winner                     = aggregates->GetProcWinner()->getDataNonConst(0);
        const auto primal_vertex_to_aggregate = primal->GetVertex2AggId()->getData(0);

        auto             coarse_dual_to_primal = Teuchos::rcp(new DualToPrimal());
        std::map<LO, LO> primal_to_dual_aggregate;
        for (LO i = 0; i < n_local; ++i)
          {
            const LO primal_aggregate = primal_vertex_to_aggregate[dual_to_primal->at(i)];
            TEUCHOS_TEST_FOR_EXCEPTION(primal_aggregate < 0, MueLu::Exceptions::RuntimeError,
                                       "NodeInterfaceAggregationFactory: slave node "
                                           << dual_to_primal->at(i) << " is in no aggregate");
            auto it = primal_to_dual_aggregate.find(primal_aggregate);
            if (it == primal_to_dual_aggregate.end())
              {
                const LO k                  = static_cast<LO>(primal_to_dual_aggregate.size());
                it                          = primal_to_dual_aggregate.emplace(primal_aggregate, k).first;
                (*coarse_dual_to_primal)[k] = primal_aggregate; // coarse dual node -> coarse primal node
              }
            vertex_to_aggregate[i] = it->second;
            winner[i]              = comm->getRank();
          }
        aggregates->SetNumAggregates(static_cast<LO>(primal_to_dual_aggregate.size()));
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
        Set(level, "CoarseDualNodeID2PrimalNodeID", coarse_dual_to_primal);
      }
    };

    /// Direct solve with the project's SuperLU adaptor (a SmootherPrototype for the coarsest level).
    class SuperLUSmoother : public MueLu::SmootherPrototype<SC, LO, GO, NO>
    {
    public:
      SuperLUSmoother() = default;
      /// Already set up on A (for a hierarchy built elsewhere: superlu_coarse_solver()).
      explicit SuperLUSmoother(const RCP<::multigrid::Matrix>& A)
      {
        factorize(A);
      }

      RCP<const Teuchos::ParameterList> GetValidParameterList() const override
      {
        auto list = Teuchos::rcp(new Teuchos::ParameterList());
        list->set<RCP<const MueLu::FactoryBase>>("A", Teuchos::null,
                                                 "Generating factory of the coarse matrix");
        return list;
      }
      void DeclareInput(MueLu::Level& level) const override { this->Input(level, "A"); }

      void Setup(MueLu::Level& level) override
      {
        MueLu::FactoryMonitor    monitor(*this, "SuperLU coarse solver", level);
        factorize(this->template Get<RCP<::multigrid::Matrix>>(level, "A"));
      }

      void Apply(::multigrid::MultiVector& X, const ::multigrid::MultiVector& B,
                 bool /*InitialGuessIsZero*/) const override
      {
        using BlockedMultiVector = Xpetra::BlockedMultiVector<double, int, long long, ::multigrid::NO>;
        auto                                bX = dynamic_cast<BlockedMultiVector*>(&X);
        auto                                bB = dynamic_cast<const BlockedMultiVector*>(&B);
        RCP<const ::multigrid::MultiVector> b;
        if (bB)
          b = bB->Merge();
        else
          b = Teuchos::rcpFromRef(B);
        if (!bX)
          {
            solver_->solve(*b, X);
            return;
          }
        RCP<::multigrid::MultiVector> x = bX->Merge();
        solver_->solve(*b, *x);
        BlockedMultiVector result(bX->getBlockedMap(), x);
        X.update(1.0, result, 0.0);
      }

      RCP<MueLu::SmootherPrototype<double, int, long long, ::multigrid::NO>> Copy() const override
      {
        return Teuchos::rcp(new SuperLUSmoother(*this));
      }

      std::string description() const override { return "SuperLU direct solver (project adaptor)"; }
      /// Complexity measure MueLu asks smoothers for: the nonzeros of the factors (global).
      size_t getNodeSmootherComplexity() const override
      {
        return solver_ ? static_cast<size_t>(solver_->factor_nonzeros()) : 0;
      }

    private:
      void factorize(const RCP<::multigrid::Matrix>& A)
      {
        auto bA = Teuchos::rcp_dynamic_cast<::multigrid::BlockedCrsMatrix>(A);
        // A coarse DOF that P does not reach (an aggregate with fewer DOFs than nullspace vectors)
        // has an empty row and column; it decouples, so a unit diagonal makes the solve defined.
        solver_ = std::make_shared<SuperLUDirect>(bA.is_null() ? A : bA->Merge(), true);
        this->IsSetup(true);
      }

      std::shared_ptr<SuperLUDirect> solver_;
    };
  } // namespace

  RCP<MueLu::SmootherBase<SC, LO, GO, NO>> superlu_coarse_solver(const RCP<Matrix>& A)
  {
    return Teuchos::rcp(new SuperLUSmoother(A));
  }

  RCP<Matrix> segregated_matrix(const Matrix& A, const Map& set)
  {
    // Membership flag of every row, then of every column (imported: the column owner decides).
    auto in_set_rows = Xpetra::VectorFactory<SC, LO, GO, NO>::Build(A.getRowMap(), true);
    {
      auto data = in_set_rows->getDataNonConst(0);
      for (decltype(data.size()) i = 0; i < data.size(); ++i)
        data[i] = set.isNodeGlobalElement(A.getRowMap()->getGlobalElement(i)) ? 1.0 : 0.0;
    }
    auto in_set_cols = Xpetra::VectorFactory<SC, LO, GO, NO>::Build(A.getColMap(), true);
    auto importer    = Xpetra::ImportFactory<LO, GO, NO>::Build(A.getRowMap(), A.getColMap());
    in_set_cols->doImport(*in_set_rows, *importer, Xpetra::INSERT);
    const auto row_flag = in_set_rows->getData(0);
    const auto col_flag = in_set_cols->getData(0);

    RCP<Matrix> filtered = Xpetra::MatrixFactory<SC, LO, GO, NO>::Build(A.getRowMap(), A.getColMap(),
                                                                        A.getNodeMaxNumRowEntries());
    for (std::size_t i = 0; i < A.getNodeNumRows(); ++i)
      {
        Teuchos::ArrayView<const LO> cols;
        Teuchos::ArrayView<const SC> vals;
        A.getLocalRowView(i, cols, vals);
        std::vector<LO> keep_cols;
        std::vector<SC> keep_vals;
        for (LO k = 0; k < cols.size(); ++k)
          if (row_flag[i] == col_flag[cols[k]])
            {
              keep_cols.push_back(cols[k]);
              keep_vals.push_back(vals[k]);
            }
        filtered->insertLocalValues(i, keep_cols, keep_vals);
      }
    filtered->fillComplete(A.getDomainMap(), A.getRangeMap());
    filtered->SetFixedBlockSize(A.GetFixedBlockSize());
    return filtered;
  }

  RCP<const MueLu::FactoryBase>
  ProjectFactoryFactory::BuildFactory(const Teuchos::ParameterEntry&        param,
                                      const ::multigrid::FactoryMap&        factories,
                                      const ::multigrid::FactoryManagerMap& managers) const
  {
    std::string            name;
    Teuchos::ParameterList list;
    if (param.isList())
      {
        list = Teuchos::getValue<Teuchos::ParameterList>(param);
        name = list.get<std::string>("factory", "");
      }
    else
      name = Teuchos::getValue<std::string>(param);

    if (name == "LevelSegregatedAFactory")
      return this->template Build2<LevelSegregatedAFactory>(list, factories, managers);
    if (name == "NodeInterfaceAggregationFactory")
      return this->template Build2<NodeInterfaceAggregationFactory>(list, factories, managers);
    if (name == "SuperLUDirectSolver")
      return Teuchos::rcp(new MueLu::SmootherFactory<double, int, long long, ::multigrid::NO>(
          Teuchos::rcp(new SuperLUSmoother()), Teuchos::null));
    if (name == "SpaiSimpleSmoother")
      return this->template BuildBlockedSmoother<SpaiSimpleSmoother>(list, factories, managers);
    if (auto spai = build_spai_factory(name, list, factories); !spai.is_null())
      return spai;
    return Base::BuildFactory(param, factories, managers);
  }
} // namespace multigrid
