#include "block_preconditioner.h"
#include "block_rebalancing.h"

#include "block_relaxation.h"
#include "cheap_simple.h"
#include "fully_coupled_amg.h"
#include "gauss_seidel_smoother.h"
#include "ilu0_smoother.h"
#include "hierarchy_utils.h"
#include "muelu_xml_compat.h"
#include "project_factories.h"
#include "superlu_direct.h"

#include <MueLu_Hierarchy.hpp>
#include <MueLu_Level.hpp>
#include <MueLu_NoFactory.hpp>
#include <MueLu_ParameterListInterpreter.hpp>

#include <Teuchos_XMLParameterListHelpers.hpp>
#include <Teuchos_Time.hpp>
#include <Xpetra_BlockedCrsMatrix.hpp>
#include <Xpetra_MapFactory.hpp>
#include <Xpetra_MultiVectorFactory.hpp>
#include <Xpetra_VectorFactory.hpp>

#include <functional>
#include <map>

namespace multigrid
{
  namespace
  {
    /// One V-cycle of a MueLu hierarchy as an Xpetra operator (right preconditioner for Belos).
    class HierarchyOperator : public Xpetra::Operator<SC, LO, GO, NO>
    {
    public:
      HierarchyOperator(RCP<Hierarchy> H, RCP<const ::multigrid::Map> map)
          : H_(std::move(H))
          , map_(std::move(map))
      {
      }
      RCP<const ::multigrid::Map> getDomainMap() const override { return map_; }
      RCP<const ::multigrid::Map> getRangeMap() const override { return map_; }
      void apply(const ::multigrid::MultiVector& X, ::multigrid::MultiVector& Y, Teuchos::ETransp mode,
                 SC alpha, SC beta) const override
      {
        if (mode != Teuchos::NO_TRANS)
          throw std::logic_error("HierarchyOperator: transposed apply is not supported");
        if (alpha == 1.0 && beta == 0.0)
          {
            Y.putScalar(0.0);
            H_->Iterate(X, Y, 1, true);
            return;
          }
        auto Z = Xpetra::MultiVectorFactory<SC, LO, GO, NO>::Build(Y.getMap(), Y.getNumVectors(), true);
        H_->Iterate(X, *Z, 1, true);
        Y.update(alpha, *Z, beta);
      }
      void residual(const ::multigrid::MultiVector&, const ::multigrid::MultiVector&,
                    ::multigrid::MultiVector&) const override
      {
        throw std::logic_error("HierarchyOperator: residual() is not defined for a preconditioner");
      }

    private:
      RCP<Hierarchy>              H_;
      RCP<const ::multigrid::Map> map_;
    };

    /// The project's SuperLU replaces Amesos2's KLU2 as the coarse solver of single-field
    /// hierarchies on every rank count:
    /// - on several ranks KLU2 is not exact under MueLu 13.2: on the 4.1k-DOF Schur complement of
    ///   beam_solid_block (r = 2), 2 ranks, a 2-level SA-AMG with a 348-row coarse level needs 12
    ///   GMRES iterations against 7 with a third level (24 rows) and 6 on one rank; a one-level
    ///   "hierarchy" (KLU2 on the whole matrix) needs 14 instead of 1, and it crashes when the
    ///   row GIDs do not start at 0;
    /// - on one rank MueLu 13.2's Amesos2Smoother::Setup does not factor: Amesos2 factors in the
    ///   first solve, so the factorization was counted in the first GMRES iteration, and KLU's
    ///   factorization is slow on the dense-ish coarse levels of 3D elasticity. On the 3D contact
    ///   benchmark's 66 k system (cheapsimple(sa-amg), 4.6 k coarse rows with 158 entries each)
    ///   KLU2 cost about 1.1 s inside the solve, SuperLU 0.26 s inside the set-up; the whole
    ///   run fell from 0.77 + 2.9-3.2 s to 1.02-1.05 + 1.5 s with the same iterations.
    /// SuperLU gathers the coarse matrix to rank 0, as KLU2 would.
    bool replaces_amesos2(const Teuchos::ParameterList& list)
    {
      const std::string coarse = value_or<std::string>(list, "coarse: type", "KLU2");
      return coarse == "KLU2" || coarse == "Klu2" || coarse == "KLU" || coarse == "Klu";
    }

    /// MueLu 13.2's easy-style lists name Ifpack2's smoothers only. "smoother: type" or
    /// "coarse: type" = "ILU(0)" or "SGS" asks for the project's (ilu0_smoother.h,
    /// gauss_seidel_smoother.h): MueLu sets the hierarchy up with a placeholder (one Jacobi
    /// sweep, cheap to set up) in its place, and use_project_smoothers puts the project's
    /// smoother there afterwards.
    using ProjectSmoother = std::function<RCP<MueLu::SmootherBase<SC, LO, GO, NO>>(const RCP<Matrix>&)>;
    struct ProjectSmoothers
    {
      ProjectSmoother level;  ///< on every level but the coarsest (empty: MueLu's)
      ProjectSmoother coarse; ///< on the coarsest level
    };

    /// A sublist's path as the preset file and `--set` write it ("primal solver"): Teuchos names
    /// a sublist "PARENT->NAME", the root of a preset "ANONYMOUS".
    std::string preset_path(const Teuchos::ParameterList& list)
    {
      std::string       path = list.name();
      const std::string root = "ANONYMOUS->";
      if (path.rfind(root, 0) == 0)
        path.erase(0, root.size());
      for (std::size_t at; (at = path.find("->")) != std::string::npos;)
        path.replace(at, 2, "/");
      return path;
    }

    /// Takes the project's smoothers out of `list` (placeholders instead) and returns them.
    ProjectSmoothers take_project_smoothers(Teuchos::ParameterList& list)
    {
      ProjectSmoothers found;
      for (const std::string which : {"smoother", "coarse"})
        {
          const std::string type   = value_or<std::string>(list, which + ": type", "");
          const std::string params = which + ": params";
          const std::string where  = "'" + preset_path(list) + "/" + params + "'";
          ProjectSmoother   make;
          if (type == "ILU(0)")
            make = [thresholds = ilu0_thresholds(list, params, where)](const RCP<Matrix>& A) {
              return Teuchos::rcp(new Ilu0Smoother(A, thresholds));
            };
          else if (type == "SGS")
            make = [settings = gauss_seidel_settings(list, params, where)](const RCP<Matrix>& A) {
              return Teuchos::rcp(new GaussSeidelSmoother(A, settings));
            };
          else
            continue;
          (which == "smoother" ? found.level : found.coarse) = make;
          list.set(which + ": type", std::string("RELAXATION"));
          list.remove(params, false);
          list.sublist(params).set("relaxation: type", std::string("Jacobi"));
        }
      return found;
    }

    void use_project_smoothers(Hierarchy& H, const ProjectSmoothers& smoothers)
    {
      const int coarsest = H.GetNumLevels() - 1;
      for (int l = 0; l <= coarsest; ++l)
        {
          const auto& make  = l < coarsest ? smoothers.level : smoothers.coarse;
          auto        level = H.GetLevel(l);
          if (!make || !level->IsAvailable("PreSmoother"))
            continue;
          // The places MueLu filled: pre- and post-smoother above the coarsest level, the
          // pre-smoother only on the coarsest (the coarse solve, applied once).
          RCP<MueLu::SmootherBase<SC, LO, GO, NO>> smoother = make(level->Get<RCP<Matrix>>("A"));
          level->Set("PreSmoother", smoother);
          if (level->IsAvailable("PostSmoother"))
            level->Set("PostSmoother", smoother);
        }
    }

    std::string coarse_solver_name(const Teuchos::ParameterList& list)
    {
      return replaces_amesos2(list) ? "SuperLU (project adaptor, in place of Amesos2's KLU2)"
                                    : value_or<std::string>(list, "coarse: type", "KLU2");
    }

    /// Level table and operator complexity (sum of nonzeros over the fine level's).
    void fill_levels(PreconditionerInfo& info, const std::vector<std::pair<long long, long long>>& sizes)
    {
      long long total = 0;
      for (const auto& [rows, nnz] : sizes)
        {
          info.levels.push_back({rows, nnz, {}});
          total += nnz;
        }
      if (!info.levels.empty() && info.levels[0].nonzeros > 0)
        info.operator_complexity = static_cast<double>(total) / info.levels[0].nonzeros;
    }

    /// Rethrows MueLu/Teuchos setup failures as a one-line InputError naming the preset.
    template <typename F>
    auto with_preset_context(const std::string& preset, F&& f)
    {
      try
        {
          return f();
        }
      catch (const InputError&)
        {
          throw;
        }
      catch (const std::exception& e)
        {
          throw InputError("preset '" + preset + "': setup failed: " + one_line_message(e.what()));
        }
    }

    /// The level smoother's contraction check (fully_coupled_amg.h) where asked for, as a note.
    std::string smoother_check_note(Hierarchy& H, const BlockSystem& system, const Preset& preset, bool check)
    {
      if (!check)
        return "level smoother: contraction not checked in this set-up";
      const double growth =
          with_preset_context(preset.name, [&] { return check_level_smoother(H, system, preset); });
      return "level smoother: ||A e|| x " + std::to_string(growth) +
             " in 5 applications (fine level, from a random e)";
    }

    /// MueLu's interpreter of a parameter list (factory- or easy-style) that can also mark every
    /// coarse level's transfers to be kept. A kept datum survives Hierarchy::Clear(), and a factory whose
    /// output is available is neither asked for its inputs nor built again: Hierarchy::SetupRe()
    /// on a new fine matrix then recomputes R A P and the smoothers with the old P and R and
    /// skips the aggregation and the prolongator smoothing. (MueLu's "reuse: type" sets such
    /// flags for easy-style lists only, and its "RP" also keeps the graphs of A P and R A P to
    /// refill them, which fails for a new matrix of another sparsity pattern: a contact Newton
    /// step's, whose mortar linearization couples other nodes. The keep list of HierarchyManager
    /// is protected, hence the derived class.)
    using ListInterpreter = MueLu::ParameterListInterpreter<SC, LO, GO, NO>;

    class Interpreter : public ListInterpreter
    {
    public:
      using ListInterpreter::ListInterpreter;

      void keep_transfers()
      {
        // Level l's P and R come from level l's factory manager (Hierarchy::Setup builds the
        // coarse level's transfers with the coarse level's manager).
        for (int level = 1; level < this->numDesiredLevel_; ++level)
          {
            const auto manager = this->GetFactoryManager(level);
            for (const char* name : {"P", "R"})
              this->keep_[level].emplace_back(name, manager->GetFactory(name).get());
          }
      }
    };

    /// A blocked MueLu hierarchy from a factory-style list (Factories + Hierarchy) on the
    /// system's n x n operator; block k's near-nullspace is level 0's "Nullspace<k+1>".
    RCP<Hierarchy> build_blocked_hierarchy(const BlockSystem& system, const Teuchos::ParameterList& muelu,
                                           const SetupOptions& options, const LeaderNodeMaps& node_maps = {})
    {
      auto comm = system.comm();
      Teuchos::ParameterList list = muelu;
      if (options.keep_aggregates)
        record_aggregates(list);
      Interpreter interpreter(list, comm, Teuchos::rcp(new ProjectFactoryFactory()));
      if (options.keep_transfers)
        interpreter.keep_transfers();
      RCP<Hierarchy> H = interpreter.CreateHierarchy();
      H->IsPreconditioner(true);
      auto L0 = H->GetLevel(0);
      L0->Set("A", Teuchos::rcp_dynamic_cast<Matrix>(system.blocked_matrix()));
      for (std::size_t k = 0; k < system.n_blocks(); ++k)
        L0->Set("Nullspace" + std::to_string(k + 1), system.nullspace_or_translations(k));
      // n x n systems: the node maps of blocks that copy another block's aggregates
      for (const auto& [name, map] : node_maps)
        L0->Set(name, Teuchos::rcp(new std::map<LO, LO>(map)));
      // Contact/meshtying systems: the interface data of the saddle-point template (block systems
      // without an interface, e.g. beam/solid, use templates that do not ask for it).
      if (system.has_interface())
        {
          const auto& interface = system.interface();
          L0->Set("DualNodeID2PrimalNodeID", Teuchos::rcp(new std::map<LO, LO>(interface.dual_to_primal_node)));
          // For user XML with MueLu's dof-based InterfaceAggregationFactory (the presets use the
          // node-based mapping above).
          L0->Set("Primal interface DOF map", interface.primal_interface_dofs);
          L0->Set("segregation labels", system.segregation_labels());
        }
      interpreter.SetupHierarchy(*H);
      return H;
    }

    /// The Schur-complement block template (beam/solid presets) aggregates every block on its own
    /// diagonal block; an empty one (the multipliers of a contact or mesh-tying system) would
    /// reach MueLu's graph construction as a null matrix and crash it.
    void check_diagonal_blocks(const Preset& preset, const BlockSystem& system)
    {
      const auto& p = preset.parameters;
      if (p.get<std::string>("template") != "schur_block_amg.xml.in")
        return;
      auto A = system.blocked_matrix();
      for (std::size_t k = 0; k < system.n_blocks(); ++k)
        {
          const auto block = A->getMatrix(k, k);
          if (block.is_null() || block->getGlobalNumEntries() == 0)
            throw InputError("preset '" + preset.name +
                             "' aggregates every block on its own diagonal block, and block '" +
                             system.block(k).name +
                             "' of this system has none (a saddle-point system: use a saddle-point preset, "
                             "e.g. fully-coupled-sa-amg(simple))");
          // The smoothed prolongator divides by the block's diagonal (D^-1 A): a zero there (the
          // constraint rows of active contact nodes) gives MueLu's "Prolongator damping factor
          // needs to be finite".
          auto diagonal = Xpetra::VectorFactory<SC, LO, GO, NO>::Build(block->getRowMap(), true);
          block->getLocalDiagCopy(*diagonal);
          const auto values = diagonal->getData(0);
          long long  local = 0, zero = 0;
          for (const SC v : values)
            local += v == 0.0 ? 1 : 0;
          Teuchos::reduceAll(*block->getRowMap()->getComm(), Teuchos::REDUCE_SUM, 1, &local, &zero);
          if (zero > 0)
            throw InputError(
                "preset '" + preset.name + "' smooths its prolongators with the inverse diagonal of " +
                "every diagonal block, and block '" + system.block(k).name + "' has " + std::to_string(zero) +
                " zero diagonal entries (a saddle-point system: use a saddle-point preset, e.g. "
                "fully-coupled-sa-amg(simple))");
        }
    }

    /// Every level's rows per block (blocked hierarchies).
    void fill_block_rows(PreconditionerInfo& info, Hierarchy& H)
    {
      for (int l = 0; l < H.GetNumLevels() && l < static_cast<int>(info.levels.size()); ++l)
        {
          auto bA = Teuchos::rcp_dynamic_cast<BlockedCrsMatrix>(H.GetLevel(l)->Get<RCP<Matrix>>("A"));
          if (bA.is_null())
            continue;
          for (std::size_t k = 0; k < bA->Rows(); ++k)
            info.levels[l].block_rows.push_back(bA->getRangeMap(k)->getGlobalNumElements());
          // Coarse-level rebalancing moves a level onto fewer ranks: count those holding rows.
          const int holds = bA->getRangeMap()->getNodeNumElements() > 0 ? 1 : 0;
          Teuchos::reduceAll(*bA->getRangeMap()->getComm(), Teuchos::REDUCE_SUM, 1, &holds,
                             &info.levels[l].ranks);
        }
    }
  } // namespace

  RCP<Hierarchy> build_single_field_hierarchy(const RCP<Matrix>& A, int dofs_per_node,
                                              const RCP<MultiVector>&       nullspace,
                                              const Teuchos::ParameterList& parameters,
                                              const RCP<MultiVector>& coordinates, bool keep_transfers)
  {
    Teuchos::ParameterList list    = parameters;
    const ProjectSmoothers project = take_project_smoothers(list);
    if (value_or<bool>(list, "repartition: enable", false) && coordinates.is_null())
      throw InputError("'repartition: enable' needs the nodes' coordinates (Zoltan2's geometric "
                       "partitioner), and this field has none");
    // Ranks left without rows on a repartitioned coarse level stay in its communicator (with
    // empty rows): the project's coarse solver and level reports call collectives on every rank.
    if (value_or<bool>(list, "repartition: enable", false) &&
        !list.isParameter("repartition: use subcommunicators"))
      list.set("repartition: use subcommunicators", false);
    if (!list.isParameter("number of equations"))
      list.set("number of equations", dofs_per_node);
    A->SetFixedBlockSize(dofs_per_node);
    Interpreter interpreter(list, A->getRowMap()->getComm());
    if (keep_transfers)
      interpreter.keep_transfers();
    RCP<Hierarchy> H = interpreter.CreateHierarchy();
    H->IsPreconditioner(true);
    H->GetLevel(0)->Set("A", A);
    if (!nullspace.is_null())
      H->GetLevel(0)->Set("Nullspace", nullspace);
    if (!coordinates.is_null())
      H->GetLevel(0)->Set("Coordinates", coordinates);
    interpreter.SetupHierarchy(*H);
    use_project_smoothers(*H, project);
    // KLU2 (MueLu's default coarse solve): the project's SuperLU takes the coarsest level's place
    // on every rank count (replaces_amesos2 says why).
    if (replaces_amesos2(parameters))
      use_superlu_coarse_solver(*H);
    return H;
  }

  void set_up_on_kept_transfers(Hierarchy& H, const RCP<Matrix>& A)
  {
    H.GetLevel(0)->Set("A", A);
    // The coarsest level still holds requests that the set-up declared for a next level it did
    // not build (MueLu's CoarseMap -> Nullspace chain, the segregation labels' request of the
    // tentative P), and Level::Clear() in SetupRe refuses data with open requests. On the coarse
    // levels everything but the kept transfers goes (ExpertClear keeps only data flagged Keep);
    // level 0 holds the user's data and has no open requests.
    for (int l = 1; l < H.GetNumLevels(); ++l)
      H.GetLevel(l)->ExpertClear();
    H.SetupRe();
  }

  void refresh_single_field_hierarchy(Hierarchy& H, const RCP<Matrix>& A,
                                      const Teuchos::ParameterList& parameters)
  {
    A->SetFixedBlockSize(H.GetLevel(0)->Get<RCP<Matrix>>("A")->GetFixedBlockSize());
    set_up_on_kept_transfers(H, A);
    Teuchos::ParameterList list = parameters;
    use_project_smoothers(H, take_project_smoothers(list));
    if (replaces_amesos2(parameters))
      use_superlu_coarse_solver(H);
  }

  void use_superlu_coarse_solver(Hierarchy& H)
  {
    // MueLu's coarse solver slot is the coarsest level's "PreSmoother".
    auto coarsest = H.GetLevel(H.GetNumLevels() - 1);
    auto Ac       = coarsest->Get<RCP<Matrix>>("A");
    coarsest->Set("PreSmoother", superlu_coarse_solver(Ac));
    if (coarsest->IsAvailable("PostSmoother"))
      coarsest->Delete("PostSmoother", MueLu::NoFactory::get());
  }

  std::vector<std::pair<long long, long long>> level_sizes(Hierarchy& H)
  {
    std::vector<std::pair<long long, long long>> sizes;
    for (int l = 0; l < H.GetNumLevels(); ++l)
      {
        auto level = H.GetLevel(l);
        if (!level->IsAvailable("A"))
          break;
        auto A = level->Get<RCP<Matrix>>("A");
        sizes.emplace_back(static_cast<long long>(A->getGlobalNumRows()),
                           static_cast<long long>(A->getGlobalNumEntries()));
      }
    return sizes;
  }

  bool builds_blocked_hierarchy(const Preset& preset)
  {
    return preset.kind == "saddle-point-amg" || preset.kind == "muelu" || preset.kind == "fully-coupled-amg";
  }

  BlockPreconditioner::BlockPreconditioner(const BlockSystem& system, const Preset& preset,
                                           SetupOptions options)
      : preset_(preset)
  {
    const bool keep_aggregates = options.keep_aggregates;
    if (keep_aggregates && !builds_blocked_hierarchy(preset))
      throw InputError("preset '" + preset.name + "' (kind " + preset.kind +
                       ") builds no blocked AMG hierarchy whose aggregates could be exported");
    info_.preset = preset.name;
    info_.kind   = preset.kind;
    Teuchos::Time timer("setup");
    timer.start(true);
    const auto& p = preset.parameters;

    if (preset.kind == "direct")
      {
        auto direct = with_preset_context(
            preset.name, [&] { return Teuchos::rcp(new DirectSolverOperator(system.merged_matrix())); });
        info_.coarse_solver = "SuperLU (whole system)";
        info_.notes.push_back("L+U nonzeros " + std::to_string(direct->solver().factor_nonzeros()));
        op_ = direct;
      }
    else if (preset.kind == "cheapsimple")
      {
        auto cs                  = with_preset_context(preset.name, [&] {
          return Teuchos::rcp(new CheapSimpleOperator(system, p, options.keep_transfers));
        });
        cheap_simple_            = cs;
        const auto primal_levels = cs->primal_levels();
        const bool amg_predictor = !primal_levels.empty();
        fill_levels(info_, amg_predictor ? primal_levels : cs->schur_levels());
        info_.notes.push_back(amg_predictor ? "levels are those of the inner primal solver"
                                            : "levels are those of the Schur-complement solver");
        info_.notes.push_back("Schur complement nonzeros " + std::to_string(cs->schur_nonzeros()));
        info_.notes.push_back("inverse approximation nonzeros " +
                              std::to_string(cs->inverse_approximation_nonzeros()));
        info_.coarse_solver = amg_predictor ? "primal: " + coarse_solver_name(p.sublist("primal solver"))
                                            : "Schur: " + coarse_solver_name(p.sublist("schur solver"));
        op_                 = cs;
      }
    else if (preset.kind == "amg")
      {
        if (system.n_blocks() != 1)
          throw InputError("preset '" + preset.name + "' is a single-field AMG, but the system has " +
                           std::to_string(system.n_blocks()) +
                           " blocks (use a saddle-point or cheapsimple preset)");
        auto H = with_preset_context(preset.name, [&] {
          return build_single_field_hierarchy(system.merged_matrix(), system.block(0).dofs_per_node,
                                              system.nullspace_or_translations(0), p.sublist("MueLu"),
                                              system.block(0).coordinates, options.keep_transfers);
        });
        fill_levels(info_, level_sizes(*H));
        hierarchy_          = H;
        info_.coarse_solver = coarse_solver_name(p.sublist("MueLu"));
        op_                 = Teuchos::rcp(new HierarchyOperator(H, system.full_map()));
      }
    else if (preset.kind == "saddle-point-amg" || preset.kind == "muelu")
      {
        Teuchos::ParameterList muelu;
        if (preset.kind == "saddle-point-amg")
          {
            check_diagonal_blocks(preset, system);
            const std::string xml =
                expand_template(preset, system.block(0).dofs_per_node,
                                system.n_blocks() > 1 ? system.block(1).dofs_per_node : 1);
            muelu             = *Teuchos::getParametersFromXmlString(xml);
            const auto coarse = p.sublist("template parameters").get<std::string>("COARSE_SOLVER");
            info_.coarse_solver =
                coarse == "CoarseSuperLU" ? "SuperLU (project adaptor, blocks merged)" : coarse;
          }
        else
          {
            muelu = p;
            muelu.remove("kind", false);
            muelu.remove("description", false);
            for (auto& line : adapt_muelu_xml_to_13_2(muelu))
              info_.notes.push_back(line);
          }
        if (system.n_blocks() != 2)
          throw InputError("saddle-point AMG needs a 2 x 2 block system, got " +
                           std::to_string(system.n_blocks()) + " blocks");
        rebalance_coarse_levels(muelu, options);
        auto H =
            with_preset_context(preset.name, [&] { return build_blocked_hierarchy(system, muelu, options); });
        fill_levels(info_, level_sizes(*H));
        fill_block_rows(info_, *H);
        hierarchy_ = H;
        op_        = Teuchos::rcp(new HierarchyOperator(H, system.full_map()));
      }
    else if (preset.kind == "fully-coupled-amg")
      {
        check_fully_coupled(preset, system);
        auto muelu     = fully_coupled_muelu_list(preset, system);
        auto node_maps = follower_node_maps(preset, system, info_.notes);
        rebalance_coarse_levels(muelu, options);
        auto H = with_preset_context(
            preset.name, [&] { return build_blocked_hierarchy(system, muelu, options, node_maps); });
        fill_levels(info_, level_sizes(*H));
        fill_block_rows(info_, *H);
        info_.coarse_solver = "SuperLU (project adaptor, blocks merged)";
        Teuchos::Time check("smoother check");
        check.start(true);
        info_.notes.push_back(smoother_check_note(*H, system, preset, options.check_level_smoother));
        info_.smoother_check_seconds = check.stop();
        hierarchy_ = H;
        op_        = Teuchos::rcp(new HierarchyOperator(H, system.full_map()));
      }
    else if (preset.kind == "block-relaxation")
      {
        auto outer = with_preset_context(preset.name,
                                         [&] { return Teuchos::rcp(new BlockRelaxationOperator(system, p)); });
        outer->describe(info_);
        op_ = outer;
      }
    else
      throw InputError("preset '" + preset.name + "': unknown kind '" + preset.kind + "'");
    info_.setup_seconds = timer.stop() - info_.smoother_check_seconds;
    if (keep_aggregates && !hierarchy_.is_null())
      aggregates_ =
          with_preset_context(preset.name, [&] { return recorded_aggregates(*hierarchy_, system); });
    transfers_kept_ =
        options.keep_transfers && !rebalanced_ &&
        (builds_blocked_hierarchy(preset) || preset.kind == "amg" || preset.kind == "cheapsimple");
    if (transfers_kept_)
      for (std::size_t k = 0; k < system.n_blocks(); ++k)
        block_maps_.push_back(system.map_extractor()->getMap(k));
  }

  void BlockPreconditioner::rebalance_coarse_levels(Teuchos::ParameterList& muelu,
                                                    const SetupOptions&     options)
  {
    const auto& p = preset_.parameters;
    if (!p.isSublist("repartition") || !rebalance_settings(p.sublist("repartition"), preset_.name).enable)
      return;
    // The aggregate export composes the levels' aggregates through local ids, which only hold
    // while a coarse node stays on the rank of its aggregate.
    if (options.keep_aggregates)
      throw InputError("preset '" + preset_.name +
                       "': exporting aggregates needs 'repartition/enable' = false (a rebalanced "
                       "level's nodes are no longer on the ranks of their aggregates)");
    add_block_rebalancing(muelu, rebalance_settings(p.sublist("repartition"), preset_.name));
    rebalanced_ = true;
    info_.notes.push_back("coarse levels rebalanced by rank merging (repartition/enable)");
    // Kept transfers would keep the rebalanced P and R but recompute the aggregates and
    // importers beneath them: every Newton step builds the hierarchy afresh instead.
    if (options.keep_transfers)
      info_.notes.push_back("kept transfers not used with coarse-level rebalancing: fresh set-ups");
  }

  bool BlockPreconditioner::refresh(const BlockSystem& system)
  {
    if (!transfers_kept_ || system.n_blocks() != block_maps_.size())
      return false;
    // The kept P of level 1 maps onto the old fine level's rows: a new matrix must have the same
    // row distribution in every block (isSameAs is collective, every rank asks).
    for (std::size_t k = 0; k < block_maps_.size(); ++k)
      if (!system.map_extractor()->getMap(k)->isSameAs(*block_maps_[k]))
        return false;
    Teuchos::Time timer("refresh");
    timer.start(true);
    with_preset_context(preset_.name, [&] {
      if (!cheap_simple_.is_null())
        cheap_simple_->refresh(system);
      else if (preset_.kind == "amg")
        refresh_single_field_hierarchy(*hierarchy_, system.merged_matrix(),
                                       preset_.parameters.sublist("MueLu"));
      else
        set_up_on_kept_transfers(*hierarchy_, Teuchos::rcp_dynamic_cast<Matrix>(system.blocked_matrix()));
    });
    info_.levels.clear();
    if (!cheap_simple_.is_null())
      {
        const auto primal_levels = cheap_simple_->primal_levels();
        fill_levels(info_, primal_levels.empty() ? cheap_simple_->schur_levels() : primal_levels);
      }
    else
      {
        fill_levels(info_, level_sizes(*hierarchy_));
        fill_block_rows(info_, *hierarchy_); // blocked hierarchies only
      }
    if (preset_.kind == "fully-coupled-amg")
      info_.notes.back() = smoother_check_note(*hierarchy_, system, preset_, false);
    info_.setup_seconds          = timer.stop();
    info_.smoother_check_seconds = 0.0; // refresh() does not check
    info_.transfers_reused       = true;
    return true;
  }

  BlockPreconditioner::~BlockPreconditioner() = default;

  RCP<const Matrix> BlockPreconditioner::prolongator(int level) const
  {
    const auto H = cheap_simple_.is_null() ? hierarchy_ : cheap_simple_->primal_hierarchy();
    if (H.is_null() || level + 1 >= H->GetNumLevels())
      throw InputError("preset '" + info_.preset + "' has no prolongator below level " +
                       std::to_string(level));
    return H->GetLevel(level + 1)->Get<RCP<Matrix>>("P");
  }

  RCP<const Matrix> BlockPreconditioner::coarse_operator(int level) const
  {
    const auto H = cheap_simple_.is_null() ? hierarchy_ : cheap_simple_->primal_hierarchy();
    if (H.is_null() || level < 1 || level >= H->GetNumLevels())
      throw InputError("preset '" + info_.preset + "' has no coarse operator on level " +
                       std::to_string(level));
    return H->GetLevel(level)->Get<RCP<Matrix>>("A");
  }

  RCP<const Matrix> BlockPreconditioner::prolongator_block(int level, int block) const
  {
    auto P  = prolongator(level);
    auto bP = Teuchos::rcp_dynamic_cast<const BlockedCrsMatrix>(P);
    if (bP.is_null())
      return P;
    return bP->getMatrix(block, block);
  }
} // namespace multigrid
