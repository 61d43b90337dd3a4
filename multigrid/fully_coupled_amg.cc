#include "fully_coupled_amg.h"

#include <MueLu_Hierarchy.hpp>
#include <MueLu_Level.hpp>
#include <MueLu_SmootherBase.hpp>

#include <Xpetra_MultiVectorFactory.hpp>

#include <cmath>
#include <map>
#include <sstream>
#include <string>

namespace multigrid
{
  namespace
  {
    using List = Teuchos::ParameterList;

    /// A factory entry of MueLu's "Factories" list: sublist `name` with "factory" = `type`.
    List& factory(List& factories, const std::string& name, const std::string& type)
    {
      List& f = factories.sublist(name);
      f.set("factory", type);
      return f;
    }

    /// A FactoryManager group: which factory produces which product for one block.
    List& group(List& factories, const std::string& name)
    {
      List& g = factories.sublist(name);
      g.set("group", std::string("FactoryManager"));
      return g;
    }

    /// "block1" ... "blockN" sublists of a blocked factory or smoother, naming the groups.
    void name_block_groups(List& blocked, const std::string& group_prefix, std::size_t n)
    {
      for (std::size_t k = 0; k < n; ++k)
        blocked.sublist("block" + std::to_string(k + 1)).set("group", group_prefix + std::to_string(k));
    }

    /// The sub-smoother settings of block `name`: its own sublist of "block smoothers", else "default".
    const List& block_smoother(const List& p, const std::string& name, const std::string& preset)
    {
      const List& all = p.sublist("block smoothers");
      if (all.isSublist(name))
        return all.sublist(name);
      if (all.isSublist("default"))
        return all.sublist("default");
      throw InputError("preset '" + preset + "': 'block smoothers' has no sublist '" + name +
                       "' nor 'default'");
    }

    /// "smoothed" or "tentative" for block `name`: its entry in the sublist "block prolongators"
    /// if there is one, else "prolongator".
    std::string prolongator_of(const List& p, const std::string& name)
    {
      if (p.isSublist("block prolongators") && p.sublist("block prolongators").isType<std::string>(name))
        return p.sublist("block prolongators").get<std::string>(name);
      return p.get<std::string>("prolongator");
    }

    /// Aggregation, tentative and (smoothed) prolongator and coarse nullspace of block k,
    /// collected in the group "Field<k>".
    void add_field_transfer(List& f, std::size_t k, const List& p, bool smoothed)
    {
      const std::string s = std::to_string(k);
      List&             A = factory(f, "A" + s, "SubBlockAFactory");
      A.set("block row", static_cast<int>(k));
      A.set("block col", static_cast<int>(k));
      // no striding here: SubBlockAFactory takes it from the block's strided map on every level
      // (DOFs per node on level 0, the nullspace dimension below).
      factory(f, "Amalgamation" + s, "AmalgamationFactory").set("A", "A" + s);
      List& graph = factory(f, "Graph" + s, "CoalesceDropFactory");
      graph.set("A", "A" + s);
      graph.set("UnAmalgamationInfo", "Amalgamation" + s);
      graph.set("aggregation: drop tol", 0.0);
      List& aggregates = factory(f, "Aggregates" + s, "UncoupledAggregationFactory");
      aggregates.set("Graph", "Graph" + s);
      aggregates.set("DofsPerNode", "Graph" + s);
      aggregates.set("aggregation: ordering", std::string("graph"));
      aggregates.set("aggregation: min agg size", p.get<int>("aggregation: min agg size"));
      aggregates.set("aggregation: max selected neighbors", 0);
      // Coarse DOF ids: block k's follow block k-1's (Xpetra numbering on every level).
      List& coarse_map = factory(f, "CoarseMap" + s, k == 0 ? "CoarseMapFactory" : "BlockedCoarseMapFactory");
      coarse_map.set("Aggregates", "Aggregates" + s);
      if (k > 0)
        coarse_map.set("CoarseMap", "CoarseMap" + std::to_string(k - 1));
      List& ptent = factory(f, "Ptent" + s, "TentativePFactory");
      ptent.set("A", "A" + s);
      ptent.set("Aggregates", "Aggregates" + s);
      ptent.set("CoarseMap", "CoarseMap" + s);
      ptent.set("UnAmalgamationInfo", "Amalgamation" + s);
      // Level 0: the user's "Nullspace<k+1>"; below: the coarse nullspace Ptent computed.
      const std::string user = "Nullspace" + std::to_string(k + 1);
      List&             ns   = factory(f, "Nullspace" + s, "NullspaceFactory");
      ns.set("Fine level nullspace", user);
      ns.set(user, "Ptent" + s);
      if (smoothed)
        {
          List& sa = factory(f, "Psa" + s, "SaPFactory");
          sa.set("A", "A" + s);
          sa.set("P", "Ptent" + s);
          sa.set("sa: damping factor", p.get<double>("sa: damping factor"));
        }
      List& field = group(f, "Field" + s);
      field.set("A", "A" + s);
      field.set("P", (smoothed ? "Psa" : "Ptent") + s);
      field.set("Ptent", "Ptent" + s);
      field.set("Aggregates", "Aggregates" + s);
      field.set("Nullspace", "Nullspace" + s);
      field.set("CoarseMap", "CoarseMap" + s);
      field.set("UnAmalgamationInfo", "Amalgamation" + s);
    }

    /// The level smoother's factory: the project's block Gauss-Seidel (block_gauss_seidel_smoother.h)
    /// or, for comparison, MueLu's BlockedGaussSeidelSmoother (the same iteration, with a residual
    /// of the whole system per block row and sub-smoothers that recompute their zero start).
    std::string block_gauss_seidel_factory(const List& p, const std::string& preset)
    {
      const std::string implementation = p.isType<std::string>("smoother: implementation")
                                             ? p.get<std::string>("smoother: implementation")
                                             : "project";
      if (implementation == "project")
        return "BlockGaussSeidelSmoother";
      if (implementation == "muelu")
        return "BlockedGaussSeidelSmoother";
      throw InputError("preset '" + preset + "': 'smoother: implementation' is '" + implementation +
                       "', expected project or muelu");
    }

    /// The sub-smoother of block k inside the block Gauss-Seidel smoother, group "SmootherGroup<k>".
    void add_block_smoother(List& f, std::size_t k, const List& settings, const std::string& preset)
    {
      const std::string s    = std::to_string(k);
      const std::string type = settings.isType<std::string>("type") ? settings.get<std::string>("type") : "";
      if (type.empty())
        throw InputError("preset '" + preset + "': a 'block smoothers' sublist has no 'type'");
      if (type == "SuperLU")
        factory(f, "Smoother" + s, "SuperLUDirectSolver");
      else
        {
          // the project's ILU(0) (ilu0_smoother.h) or symmetric Gauss-Seidel
          // (gauss_seidel_smoother.h), or an Ifpack2 type through MueLu's TrilinosSmoother
          const std::map<std::string, std::string> own{{"ILU(0)", "Ilu0Smoother"},
                                                       {"SGS", "GaussSeidelSmoother"}};
          const auto                               o = own.find(type);
          List& t = factory(f, "Smoother" + s, o != own.end() ? o->second : "TrilinosSmoother");
          if (o == own.end())
            t.set("type", type);
          List& parameters = t.sublist("ParameterList");
          if (settings.isSublist("ParameterList"))
            parameters.setParameters(settings.sublist("ParameterList"));
        }
      List& g = group(f, "SmootherGroup" + s);
      g.set("A", "A" + s);
      g.set("Smoother", "Smoother" + s);
    }
  } // namespace

  void check_fully_coupled(const Preset& preset, const BlockSystem& system)
  {
    const auto& p         = preset.parameters;
    const int   min_agg   = p.get<int>("aggregation: min agg size");
    const int   max_size  = p.get<int>("coarse: max size");
    const int   max_level = p.get<int>("max levels");
    for (std::size_t k = 0; k < system.n_blocks(); ++k)
      {
        const auto prolong = prolongator_of(p, system.block(k).name);
        if (prolong != "smoothed" && prolong != "tentative")
          throw InputError("preset '" + preset.name + "': the prolongator of block '" + system.block(k).name +
                           "' is '" + prolong + "', expected smoothed or tentative");
      }
    if (min_agg < 1 || max_size < 1 || max_level < 1)
      throw InputError("preset '" + preset.name +
                       "': expected 'aggregation: min agg size', 'coarse: max size' and 'max levels' >= 1");
    // A system at most `coarse: max size` large (or a one-level hierarchy) is solved directly.
    if (system.global_size() <= max_size || max_level == 1)
      return;
    for (std::size_t k = 0; k < system.n_blocks(); ++k)
      {
        const auto& b     = system.block(k);
        const GO    nodes = b.global_size / b.dofs_per_node;
        if (nodes < min_agg)
          throw InputError(
              "preset '" + preset.name + "': block '" + b.name + "' has " + std::to_string(nodes) +
              " nodes, fewer than one aggregate ('aggregation: min agg size' = " + std::to_string(min_agg) +
              "); lower it, or raise 'coarse: max size' to " + std::to_string(system.global_size()) +
              " for a direct solve");
      }
  }

  Teuchos::ParameterList fully_coupled_muelu_list(const Preset& preset, const BlockSystem& system)
  {
    const auto&       p = preset.parameters;
    const std::size_t n = system.n_blocks();
    List              muelu("MueLu");
    List&             f = muelu.sublist("Factories");

    // 1.-2. per field: aggregates, Ptent (nullspace), P, coarse nullspace.
    for (std::size_t k = 0; k < n; ++k)
      add_field_transfer(f, k, p, prolongator_of(p, system.block(k).name) == "smoothed");
    // 3. block-diagonal P, R = P^T, Galerkin product of the whole n x n operator.
    name_block_groups(factory(f, "BlockedP", "BlockedPFactory"), "Field", n);
    factory(f, "BlockedR", "GenericRFactory").set("P", "BlockedP");
    List& rap = factory(f, "BlockedRAP", "BlockedRAPFactory");
    rap.set("P", "BlockedP");
    rap.set("R", "BlockedR");
    // 4. block Gauss-Seidel with one sub-smoother per field.
    for (std::size_t k = 0; k < n; ++k)
      add_block_smoother(f, k, block_smoother(p, system.block(k).name, preset.name), preset.name);
    List& bgs = factory(f, "BlockGaussSeidel", block_gauss_seidel_factory(p, preset.name));
    bgs.set("Sweeps", p.get<int>("smoother: sweeps"));
    bgs.set("Damping factor", p.get<double>("smoother: damping"));
    name_block_groups(bgs, "SmootherGroup", n);
    // 5. coarse level: SuperLU on the merged coarse operator.
    factory(f, "CoarseSuperLU", "SuperLUDirectSolver");

    List& h = muelu.sublist("Hierarchy");
    h.set("max levels", p.get<int>("max levels"));
    h.set("coarse: max size", p.get<int>("coarse: max size"));
    h.set("verbosity", std::string("None"));
    List& all = h.sublist("AllLevel");
    all.set("startLevel", 0);
    all.set("Smoother", std::string("BlockGaussSeidel"));
    all.set("CoarseSolver", std::string("CoarseSuperLU"));
    all.set("P", std::string("BlockedP"));
    all.set("R", std::string("BlockedR"));
    all.set("A", std::string("BlockedRAP"));
    return muelu;
  }

  double check_level_smoother(Hierarchy& H, const BlockSystem& system, const Preset& preset)
  {
    auto level = H.GetLevel(0);
    if (H.GetNumLevels() < 2 || !level->IsAvailable("PreSmoother"))
      return 0.0; // one level: the coarse (direct) solve only
    auto smoother = level->Get<RCP<MueLu::SmootherBase<SC, LO, GO, NO>>>("PreSmoother");
    auto A        = system.merged_matrix();
    auto x        = Xpetra::MultiVectorFactory<SC, LO, GO, NO>::Build(system.full_map(), 1);
    auto zero     = Xpetra::MultiVectorFactory<SC, LO, GO, NO>::Build(system.full_map(), 1, true);
    auto r        = Xpetra::MultiVectorFactory<SC, LO, GO, NO>::Build(system.full_map(), 1);
    auto residual = [&] {
      A->apply(*x, *r);
      Teuchos::Array<double> norm(1);
      r->norm2(norm);
      return norm[0];
    };
    x->randomize();
    const double r0 = residual();
    for (int i = 0; i < 5; ++i)
      smoother->Apply(*x, *zero, false);
    const double growth   = r0 > 0 ? residual() / r0 : 0.0;
    const double max_grow = preset.parameters.get<double>("smoother: max growth");
    if (!std::isfinite(growth) || growth > max_grow)
      {
        std::ostringstream s;
        s << "preset '" << preset.name << "': the level smoother does not contract: ||A e|| grows by "
          << growth << " in 5 applications on the fine level (limit 'smoother: max growth' = " << max_grow
          << "); lower 'smoother: damping' or choose other 'block smoothers'";
        throw InputError(s.str());
      }
    return growth;
  }
} // namespace multigrid
