#include "project_factories.h"

#include "aggregate_export.h"
#include "block_gauss_seidel_smoother.h"
#include "block_rebalancing.h"
#include "coupled_prolongator.h"
#include "gauss_seidel_smoother.h"
#include "ilu0_smoother.h"
#include "node_interface_aggregation.h"

#include "spai_factories.h"
#include "spai_simple_smoother.h"
#include "superlu_direct.h"

#include <MueLu_Aggregates.hpp>
#include <MueLu_AmalgamationInfo.hpp>
#include <MueLu_FactoryFactory.hpp>
#include <MueLu_Level.hpp>
#include <MueLu_SingleLevelFactoryBase.hpp>
#include <MueLu_TwoLevelFactoryBase.hpp>
#include <MueLu_SmootherFactory.hpp>
#include <MueLu_SmootherPrototype.hpp>
#include <MueLu_Monitor.hpp>
#include <MueLu_Utilities.hpp>

#include <Tpetra_CrsMatrix.hpp>

#include <Xpetra_BlockedCrsMatrix.hpp>
#include <Xpetra_BlockedMultiVector.hpp>
#include <Xpetra_ExportFactory.hpp>
#include <Xpetra_ImportFactory.hpp>
#include <Xpetra_MapFactory.hpp>
#include <Xpetra_MatrixFactory.hpp>
#include <Xpetra_MultiVectorFactory.hpp>
#include <Xpetra_VectorFactory.hpp>

#include <limits>
#include <memory>
#include <stdexcept>

namespace multigrid
{
  namespace
  {
    using MueLu::Level;
    using MueLu::NoFactory;
    using FactoryBase = MueLu::FactoryBase;

    /// A_seg(i,j) = A(i,j) if DOFs i and j carry the same body label, else 0.
    class LevelSegregatedAFactory : public MueLu::SingleLevelFactoryBase
    {
    public:
      RCP<const Teuchos::ParameterList> GetValidParameterList() const override
      {
        auto list = Teuchos::rcp(new Teuchos::ParameterList());
        list->set<RCP<const FactoryBase>>("A", Teuchos::null, "Generating factory of the matrix to filter");
        list->set<RCP<const FactoryBase>>("segregation labels", Teuchos::null,
                                          "Generating factory of the body labels on coarse levels "
                                          "(SegregationLabelTransferFactory); user data on level 0");
        return list;
      }

      void DeclareInput(Level& level) const override
      {
        Input(level, "A");
        if (level.GetLevelID() == 0)
          level.DeclareInput("segregation labels", NoFactory::get(), this);
        else
          Input(level, "segregation labels");
      }

      void Build(Level& level) const override
      {
        MueLu::FactoryMonitor monitor(*this, "Segregated matrix (filtered A)", level);
        RCP<Matrix>           A = Get<RCP<Matrix>>(level, "A");
        RCP<MultiVector>      labels;
        if (level.GetLevelID() == 0)
          labels = level.Get<RCP<MultiVector>>("segregation labels", NoFactory::get());
        else
          labels = Get<RCP<MultiVector>>(level, "segregation labels");

        // Nothing to cut (one label everywhere, e.g. mesh tying of bodies without coupling in
        // A): no copy.
        double     range[2] = {-std::numeric_limits<double>::max(), -std::numeric_limits<double>::max()};
        const auto data     = labels->getData(0);
        for (const double v : data)
          range[0] = std::max(range[0], -v), range[1] = std::max(range[1], v); // -min, max
        double global[2];
        Teuchos::reduceAll(*labels->getMap()->getComm(), Teuchos::REDUCE_MAX, 2, range, global);
        Set(level, "A", global[1] == -global[0] ? A : segregated_matrix(*A, *labels));
      }
    };

    /// The body labels of the next coarser level: a coarse DOF takes the label of the fine DOFs
    /// whose rows of the tentative prolongator reach it. Aggregates of the filtered A never mix
    /// bodies, so the label is unique; where it is not (a label set built without filtering),
    /// the largest wins, which for two labels is MapTransferFactory's rule for a DOF set.
    class SegregationLabelTransferFactory : public MueLu::TwoLevelFactoryBase
    {
    public:
      RCP<const Teuchos::ParameterList> GetValidParameterList() const override
      {
        auto list = Teuchos::rcp(new Teuchos::ParameterList());
        list->set<RCP<const FactoryBase>>("P", Teuchos::null,
                                          "Generating factory of the tentative prolongator (default: the "
                                          "level's \"Ptent\")");
        list->set<std::string>("importer key", "",
                               "With coarse-level rebalancing (block_rebalancing.h): the name the "
                               "primal block's Importer is registered as; the coarse labels move "
                               "with the rows");
        return list;
      }

      void DeclareInput(Level& fine, Level& coarse) const override
      {
        if (fine.GetLevelID() == 0)
          fine.DeclareInput("segregation labels", NoFactory::get(), this);
        else
          fine.DeclareInput("segregation labels", this, this);
        coarse.DeclareInput("P", tentative_prolongator(coarse).get(), this);
        if (auto importer = importer_factory(); !importer.is_null())
          coarse.DeclareInput("Importer", importer.get(), this);
      }

      void Build(Level& fine, Level& coarse) const override
      {
        MueLu::FactoryMonitor monitor(*this, "Body labels of the coarse level", coarse);
        RCP<MultiVector>      labels = fine.GetLevelID() == 0
                                           ? fine.Get<RCP<MultiVector>>("segregation labels", NoFactory::get())
                                           : fine.Get<RCP<MultiVector>>("segregation labels", this);
        RCP<Matrix>           P      = coarse.Get<RCP<Matrix>>("P", tentative_prolongator(coarse).get());
        // label + 1 on the columns of P this rank's rows reach, then the largest per coarse DOF.
        auto       on_columns = Xpetra::MultiVectorFactory<SC, LO, GO, NO>::Build(P->getColMap(), 1, true);
        auto       column     = on_columns->getDataNonConst(0);
        const auto fine_label = labels->getData(0);
        const auto label_map  = labels->getMap(); // a fresh wrapper per call: keep it alive
        for (std::size_t row = 0; row < P->getNodeNumRows(); ++row)
          {
            const LO i = label_map->getLocalElement(P->getRowMap()->getGlobalElement(row));
            TEUCHOS_TEST_FOR_EXCEPTION(i == Teuchos::OrdinalTraits<LO>::invalid(), MueLu::Exceptions::RuntimeError,
                                       "SegregationLabelTransferFactory: no label for row "
                                           << P->getRowMap()->getGlobalElement(row) << " on level "
                                           << fine.GetLevelID());
            Teuchos::ArrayView<const LO> cols;
            Teuchos::ArrayView<const SC> vals;
            P->getLocalRowView(row, cols, vals);
            for (LO k = 0; k < cols.size(); ++k)
              column[cols[k]] = std::max(column[cols[k]], fine_label[i] + 1.0);
          }
        auto coarse_labels = Xpetra::MultiVectorFactory<SC, LO, GO, NO>::Build(P->getDomainMap(), 1, true);
        auto exporter      = Xpetra::ExportFactory<LO, GO, NO>::Build(P->getColMap(), P->getDomainMap());
        coarse_labels->doExport(*on_columns, *exporter, Xpetra::ABSMAX);
        auto data = coarse_labels->getDataNonConst(0);
        for (auto& v : data)
          v = std::max(v - 1.0, 0.0); // a coarse DOF no row reaches (none in practice): label 0
        Set(coarse, "segregation labels", rebalanced(coarse, coarse_labels));
      }

      void set_late_factories(std::shared_ptr<const LateFactories> late) { late_ = std::move(late); }

    private:
      std::shared_ptr<const LateFactories> late_;

      RCP<const FactoryBase> importer_factory() const
      {
        const auto& key = GetParameterList().get<std::string>("importer key");
        if (key.empty())
          return Teuchos::null;
        return registered_factory(late_, key, "SegregationLabelTransferFactory");
      }

      /// The labels on the rebalanced rows of the coarse level (unchanged where it is not rebalanced).
      RCP<MultiVector> rebalanced(Level& coarse, const RCP<MultiVector>& labels) const
      {
        const auto factory = importer_factory();
        if (factory.is_null())
          return labels;
        const auto importer = coarse.Get<RCP<const Xpetra::Import<LO, GO, NO>>>("Importer", factory.get());
        if (importer.is_null())
          return labels;
        auto moved = Xpetra::MultiVectorFactory<SC, LO, GO, NO>::Build(importer->getTargetMap(), 1);
        moved->doImport(*labels, *importer, Xpetra::INSERT);
        return moved;
      }

      /// As MapTransferFactory: "P" if given, else the coarse level's "Ptent" (Ptent00 in the presets).
      RCP<const FactoryBase> tentative_prolongator(Level& coarse) const
      {
        RCP<const FactoryBase> P = GetFactory("P");
        return P.is_null() ? coarse.GetFactoryManager()->GetFactory("Ptent") : P;
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
        SuperLUOptions options;
        options.unit_diagonal_on_empty_rows = true;
        options.iterative_refinement        = false; // an exact-to-rounding coarse solve is enough
        solver_ = std::make_shared<SuperLUDirect>(bA.is_null() ? A : bA->Merge(), options);
        this->IsSetup(true);
      }

      std::shared_ptr<SuperLUDirect> solver_;
    };
  } // namespace

  RCP<MueLu::SmootherBase<SC, LO, GO, NO>> superlu_coarse_solver(const RCP<Matrix>& A)
  {
    return Teuchos::rcp(new SuperLUSmoother(A));
  }

  RCP<Matrix> segregated_matrix(const Matrix& A_matrix, const MultiVector& labels)
  {
    using TpetraCrs    = Tpetra::CrsMatrix<SC, LO, GO, NO>;
    const TpetraCrs& A = Xpetra::Helpers<SC, LO, GO, NO>::Op2TpetraCrs(A_matrix);

    // Label of every row (looked up by global id), then of every column (imported: the column
    // owner decides).
    auto row_labels = Xpetra::VectorFactory<SC, LO, GO, NO>::Build(A_matrix.getRowMap(), true);
    {
      auto        data  = row_labels->getDataNonConst(0);
      const auto  given = labels.getData(0);
      const auto  map   = labels.getMap(); // Xpetra wraps a new map object on every call: keep it
      const auto& rows  = *A.getRowMap();
      for (decltype(data.size()) i = 0; i < data.size(); ++i)
        {
          const LO k = map->getLocalElement(rows.getGlobalElement(i));
          if (k == Teuchos::OrdinalTraits<LO>::invalid())
            throw std::invalid_argument("segregated_matrix: no body label for row " +
                                        std::to_string(rows.getGlobalElement(i)));
          data[i] = given[k];
        }
    }
    auto col_labels = Xpetra::VectorFactory<SC, LO, GO, NO>::Build(A_matrix.getColMap(), true);
    auto importer   = Xpetra::ImportFactory<LO, GO, NO>::Build(A_matrix.getRowMap(), A_matrix.getColMap());
    col_labels->doImport(*row_labels, *importer, Xpetra::INSERT);
    const auto row_label = row_labels->getData(0);
    const auto col_label = col_labels->getData(0);

    // The kept entries in compressed rows, in A's column ids, counted first so that the arrays
    // are allocated once and exactly. (Inserting row by row into a matrix sized for A's longest
    // row allocated and zeroed rows x that length, which for the contact rows' long multiplier
    // couplings was most of the filter's time.) The filtered matrix keeps A's column map, so it
    // keeps A's importer too: no fillComplete has to find the column owners again.
    const auto n_rows = static_cast<LO>(A.getNodeNumRows());
    const auto kept   = [&](LO i, LO column) { return row_label[i] == col_label[column]; };
    typename TpetraCrs::local_graph_device_type::row_map_type::non_const_type offsets("row offsets",
                                                                                      n_rows + 1);
    typename TpetraCrs::local_inds_host_view_type                             columns;
    typename TpetraCrs::values_host_view_type                                 values;
    for (LO i = 0; i < n_rows; ++i)
      {
        A.getLocalRowView(i, columns, values);
        std::size_t n = 0;
        for (std::size_t k = 0; k < columns.extent(0); ++k)
          n += kept(i, columns(k));
        offsets(i + 1) = offsets(i) + n;
      }
    typename TpetraCrs::local_graph_device_type::entries_type::non_const_type kept_columns(
        Kokkos::ViewAllocateWithoutInitializing("column indices"), offsets(n_rows));
    typename TpetraCrs::local_matrix_device_type::values_type kept_values(
        Kokkos::ViewAllocateWithoutInitializing("values"), offsets(n_rows));
    for (LO i = 0; i < n_rows; ++i)
      {
        A.getLocalRowView(i, columns, values);
        std::size_t n = offsets(i);
        for (std::size_t k = 0; k < columns.extent(0); ++k)
          if (kept(i, columns(k)))
            {
              kept_columns(n) = columns(k);
              kept_values(n)  = values(k);
              ++n;
            }
      }
    auto filtered =
        Teuchos::rcp(new TpetraCrs(A.getRowMap(), A.getColMap(), offsets, kept_columns, kept_values));
    filtered->expertStaticFillComplete(A.getDomainMap(), A.getRangeMap(), A.getGraph()->getImporter(),
                                       A.getGraph()->getExporter());
    RCP<Matrix> result = MueLu::TpetraCrs_To_XpetraMatrix(filtered);
    result->SetFixedBlockSize(A_matrix.GetFixedBlockSize());
    return result;
  }

  RCP<Matrix> segregated_matrix(const Matrix& A, const Map& set)
  {
    auto labels = Xpetra::MultiVectorFactory<SC, LO, GO, NO>::Build(A.getRowMap(), 1, true);
    auto data   = labels->getDataNonConst(0);
    for (decltype(data.size()) i = 0; i < data.size(); ++i)
      data[i] = set.isNodeGlobalElement(A.getRowMap()->getGlobalElement(i)) ? 1.0 : 0.0;
    return segregated_matrix(A, *labels);
  }

  RCP<const MueLu::FactoryBase> registered_factory(const std::shared_ptr<const LateFactories>& late,
                                                   const std::string& name, const std::string& who)
  {
    const auto found = late ? late->find(name) : LateFactories::const_iterator();
    TEUCHOS_TEST_FOR_EXCEPTION(!late || found == late->end(), MueLu::Exceptions::RuntimeError,
                               who << ": no factory registered as '" << name << "'");
    return found->second;
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
    // An entry others find by name when the hierarchy is set up (LateFactories).
    if (list.isType<std::string>("register as"))
      {
        const std::string as = list.get<std::string>("register as");
        list.remove("register as");
        const auto built = BuildFactory(Teuchos::ParameterEntry(list), factories, managers);
        (*late_)[as]     = built;
        return built;
      }
    if (name == "SegregationLabelTransferFactory")
      {
        auto built = this->template Build2<SegregationLabelTransferFactory>(list, factories, managers);
        built->set_late_factories(late_);
        return built;
      }
    if (name == "NodeInterfaceAggregationFactory")
      return this->template Build2<NodeInterfaceAggregationFactory>(list, factories, managers);
    if (name == "AggregateRecordFactory")
      {
        const auto aggregates = factories.find(list.get<std::string>("Aggregates", ""));
        if (aggregates == factories.end())
          throw InputError("AggregateRecordFactory: 'Aggregates' names no factory defined before it");
        return build_aggregate_record_factory(list, aggregates->second);
      }
    if (name == "SuperLUDirectSolver")
      return Teuchos::rcp(new MueLu::SmootherFactory<double, int, long long, ::multigrid::NO>(
          Teuchos::rcp(new SuperLUSmoother()), Teuchos::null));
    if (name == "Ilu0Smoother")
      return Teuchos::rcp(new MueLu::SmootherFactory<double, int, long long, ::multigrid::NO>(
          Teuchos::rcp(new Ilu0Smoother(ilu0_thresholds(list, "ParameterList", "factory Ilu0Smoother")))));
    if (name == "GaussSeidelSmoother")
      return Teuchos::rcp(new MueLu::SmootherFactory<double, int, long long, ::multigrid::NO>(
          Teuchos::rcp(new GaussSeidelSmoother(
              gauss_seidel_settings(list, "ParameterList", "factory GaussSeidelSmoother")))));
    if (name == "CoupledSaPFactory")
      return this->template Build2<CoupledSaPFactory>(list, factories, managers);
    if (name == "BlockedTransposeFactory")
      return this->template Build2<BlockedTransposeFactory>(list, factories, managers);
    if (name == "BlockedGalerkinFactory")
      return this->template BuildRAPFactory<BlockedGalerkinFactory>(list, factories, managers);
    if (name == "SpaiSimpleSmoother")
      return this->template BuildBlockedSmoother<SpaiSimpleSmoother>(list, factories, managers);
    if (name == "BlockGaussSeidelSmoother")
      return this->template BuildBlockedSmoother<BlockGaussSeidelSmoother>(list, factories, managers);
    if (auto spai = build_spai_factory(name, list, factories); !spai.is_null())
      return spai;
    if (auto rebalancing = build_rebalancing_factory(name, list, factories, late_); !rebalancing.is_null())
      return rebalancing;
    return Base::BuildFactory(param, factories, managers);
  }
} // namespace multigrid
