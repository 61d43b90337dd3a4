#include "fully_coupled_amg.h"

#include "project_factories.h"
#include "spatial_order.h"

#include <MueLu_Hierarchy.hpp>
#include <MueLu_Level.hpp>
#include <MueLu_SmootherBase.hpp>

#include <Teuchos_CommHelpers.hpp>

#include <Xpetra_MultiVectorFactory.hpp>

#include <algorithm>
#include <cmath>
#include <map>
#include <optional>
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

    /// "LeaderNodes<k>": the level-0 user data holding block k's follower -> leader node mapping.
    std::string leader_map_name(std::size_t k)
    {
      return "LeaderNodes" + std::to_string(k);
    }

    /// The block whose aggregates block k copies: its entry in the optional sublist
    /// "block aggregates" (FOLLOWER = LEADER, block names; LEADER "own": none), else none. The leader must
    /// come before block k (the factory list refers to factories defined before) and aggregate on its own.
    std::optional<std::size_t> leader_of(const List& p, const BlockSystem& system, std::size_t k,
                                         const std::string& preset)
    {
      const std::string& name = system.block(k).name;
      if (!p.isSublist("block aggregates") || !p.sublist("block aggregates").isParameter(name))
        return std::nullopt;
      const List& follow = p.sublist("block aggregates");
      if (!follow.isType<std::string>(name))
        throw InputError("preset '" + preset + "': 'block aggregates/" + name + "' must be a block name");
      const std::string leader = follow.get<std::string>(name);
      if (leader == "own")
        return std::nullopt;
      for (std::size_t l = 0; l < k; ++l)
        if (system.block(l).name == leader)
          {
            if (leader_of(p, system, l, preset))
              throw InputError("preset '" + preset + "': block '" + name + "' follows block '" + leader +
                               "', which follows another block; name that one");
            return l;
          }
      throw InputError("preset '" + preset + "': 'block aggregates/" + name + "' = '" + leader +
                       "' names no block before '" + name + "' in this system");
    }

    /// This rank's node positions of a block, node-major.
    std::vector<double> local_positions(const BlockInfo& b)
    {
      const auto&         xyz = *b.coordinates;
      const std::size_t   dim = xyz.getNumVectors(), n = xyz.getLocalLength();
      std::vector<double> x(n * dim);
      for (std::size_t c = 0; c < dim; ++c)
        {
          const auto column = xyz.getData(c);
          for (std::size_t i = 0; i < n; ++i)
            x[i * dim + c] = column[i];
        }
      return x;
    }

    /// The largest extent over the directions of node-major positions (0 for none).
    double largest_extent(const std::vector<double>& xyz, int dim)
    {
      double extent = 0;
      for (int c = 0; c < dim && xyz.size() >= static_cast<std::size_t>(dim); ++c)
        {
          double lo = xyz[c], hi = xyz[c];
          for (std::size_t i = c; i < xyz.size(); i += dim)
            {
              lo = std::min(lo, xyz[i]);
              hi = std::max(hi, xyz[i]);
            }
          extent = std::max(extent, hi - lo);
        }
      return extent;
    }

    /// Block k's aggregates from its own diagonal block: MueLu's uncoupled aggregation of the
    /// node graph (striding from the block's map), "Amalgamation<k>" the DOF <-> node translation.
    void add_own_aggregation(List& f, std::size_t k, const List& p)
    {
      const std::string s = std::to_string(k);
      factory(f, "Amalgamation" + s, "AmalgamationFactory").set("A", "A" + s);
      List& graph = factory(f, "Graph" + s, "CoalesceDropFactory");
      graph.set("A", "A" + s);
      graph.set("UnAmalgamationInfo", "Amalgamation" + s);
      graph.set("aggregation: drop tol", 0.0);
      List& aggregates = factory(f, "Aggregates" + s, "UncoupledAggregationFactory");
      aggregates.set("Graph", "Graph" + s);
      aggregates.set("DofsPerNode", "Graph" + s);
      aggregates.set("aggregation: ordering", p.isType<std::string>("aggregation: ordering")
                                                  ? p.get<std::string>("aggregation: ordering")
                                                  : std::string("graph"));
      aggregates.set("aggregation: min agg size", p.get<int>("aggregation: min agg size"));
      aggregates.set("aggregation: max selected neighbors", 0);
    }

    /// Block k's aggregates copied from block `leader`'s (node_interface_aggregation.h): each
    /// node joins the aggregate of the leader's node at its position (level 0: the user data
    /// "LeaderNodes<k>", follower_node_maps), so that both fields coarsen onto one coarse mesh.
    /// The factory also provides the DOF <-> node translation ("UnAmalgamationInfo") and the
    /// coarse mapping, moved to the next level by "LeaderMapping<k>".
    void add_follower_aggregation(List& f, std::size_t k, std::size_t leader, int dofs_per_node)
    {
      const std::string s          = std::to_string(k);
      List&             aggregates = factory(f, "Aggregates" + s, "NodeInterfaceAggregationFactory");
      aggregates.set("A", "A" + s);
      aggregates.set("Aggregates", "Aggregates" + std::to_string(leader));
      aggregates.set("number of DOFs per dual node", dofs_per_node);
      aggregates.set("level 0 mapping", leader_map_name(k));
      aggregates.set("leave out Dirichlet nodes", true);
      // a follower that shares only an interface with its leader (the fluid following the
      // structure) aggregates its other nodes on its own graph
      aggregates.set("aggregate unmatched nodes", true);
      // its coarse levels' mapping: "DualNodeID2PrimalNodeID" of the group "Field<k>" (defined
      // after this entry, which it reads)
      factory(f, "LeaderMapping" + s, "InterfaceMappingTransferFactory")
          .set("CoarseDualNodeID2PrimalNodeID", "Aggregates" + s);
    }

    /// Aggregation, tentative and (smoothed) prolongator and coarse nullspace of block k,
    /// collected in the group "Field<k>"; `leader`: the block whose aggregates block k copies.
    void add_field_transfer(List& f, std::size_t k, const List& p, bool smoothed,
                            std::optional<std::size_t> leader, int dofs_per_node)
    {
      const std::string s = std::to_string(k);
      List&             A = factory(f, "A" + s, "SubBlockAFactory");
      A.set("block row", static_cast<int>(k));
      A.set("block col", static_cast<int>(k));
      // no striding here: SubBlockAFactory takes it from the block's strided map on every level
      // (DOFs per node on level 0, the nullspace dimension below).
      if (leader)
        add_follower_aggregation(f, k, *leader, dofs_per_node);
      else
        add_own_aggregation(f, k, p);
      // the factory of the DOF <-> node translation
      const std::string amalgamation = (leader ? "Aggregates" : "Amalgamation") + s;
      // Coarse DOF ids: block k's follow block k-1's (Xpetra numbering on every level).
      List& coarse_map = factory(f, "CoarseMap" + s, k == 0 ? "CoarseMapFactory" : "BlockedCoarseMapFactory");
      coarse_map.set("Aggregates", "Aggregates" + s);
      if (k > 0)
        coarse_map.set("CoarseMap", "CoarseMap" + std::to_string(k - 1));
      List& ptent = factory(f, "Ptent" + s, "TentativePFactory");
      ptent.set("A", "A" + s);
      ptent.set("Aggregates", "Aggregates" + s);
      ptent.set("CoarseMap", "CoarseMap" + s);
      ptent.set("UnAmalgamationInfo", amalgamation);
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
      field.set("UnAmalgamationInfo", amalgamation);
      if (leader)
        field.set("DualNodeID2PrimalNodeID", "LeaderMapping" + s);
    }

    /// "repartition/enable" is set and true.
    bool rebalanced(const List& p)
    {
      return p.isSublist("repartition") && p.sublist("repartition").isType<bool>("enable") &&
             p.sublist("repartition").get<bool>("enable");
    }

    /// "prolongator: smoothing": false for "per field" (the default: each field's SA step with its
    /// own diagonal block, P block-diagonal), true for "across fields" (one Jacobi step of the
    /// whole operator on the tentative P, coupled_prolongator.h).
    bool smoothing_across_fields(const List& p, const std::string& preset)
    {
      if (!p.isParameter("prolongator: smoothing"))
        return false;
      const auto value = p.get<std::string>("prolongator: smoothing");
      if (value != "per field" && value != "across fields")
        throw InputError("preset '" + preset + "': 'prolongator: smoothing' is '" + value +
                         "', expected 'per field' or 'across fields'");
      return value == "across fields";
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
    for (std::size_t k = 0; k < system.n_blocks(); ++k)
      if (const auto leader = leader_of(p, system, k, preset.name))
        {
          const auto& b = system.block(k);
          for (const auto* block : {&b, &system.block(*leader)})
            if (block->coordinates.is_null())
              throw InputError("preset '" + preset.name + "': block '" + b.name +
                               "' takes the aggregates of '" + system.block(*leader).name +
                               "' at the same node positions, and block '" + block->name +
                               "' has no coordinates");
          if (b.coordinates->getNumVectors() != system.block(*leader).coordinates->getNumVectors())
            throw InputError("preset '" + preset.name + "': blocks '" + b.name + "' and '" +
                             system.block(*leader).name + "' have coordinates of different dimensions");
          // The coarse-level rebalancing (block_rebalancing.h) moves the node mapping of the
          // contact lists' two blocks only.
          if (rebalanced(p))
            throw InputError("preset '" + preset.name + "': block '" + b.name +
                             "' takes the aggregates of '" + system.block(*leader).name +
                             "', which the coarse-level rebalancing does not support yet; set "
                             "'repartition/enable' to false or 'block aggregates/" +
                             b.name + "' to own");
          // The copied aggregates keep DOFs per node on every level; the coarse levels have one
          // DOF per near-nullspace vector.
          const auto modes = system.nullspace_or_translations(k)->getNumVectors();
          if (modes != static_cast<std::size_t>(b.dofs_per_node))
            throw InputError("preset '" + preset.name + "': block '" + b.name + "' takes another block's " +
                             "aggregates, which needs as many near-nullspace vectors (" +
                             std::to_string(modes) + ") as DOFs per node (" +
                             std::to_string(b.dofs_per_node) + ")");
        }
    // The rebalancing moves block-diagonal prolongators (RebalanceBlockInterpolationFactory
    // rebalances each block group's P).
    if (smoothing_across_fields(p, preset.name) && rebalanced(p))
      throw InputError("preset '" + preset.name +
                       "': 'prolongator: smoothing = across fields' makes P non-block-diagonal, which the "
                       "coarse-level rebalancing does not support; set 'repartition/enable' to false or "
                       "'prolongator: smoothing' to 'per field'");
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
    const bool  across = smoothing_across_fields(p, preset.name);
    std::string tentative_blocks;
    for (std::size_t k = 0; k < n; ++k)
      {
        const bool smoothed = prolongator_of(p, system.block(k).name) == "smoothed";
        if (!smoothed)
          tentative_blocks += std::to_string(k) + " ";
        add_field_transfer(f, k, p, smoothed && !across, leader_of(p, system, k, preset.name),
                           system.block(k).dofs_per_node);
      }
    // 3. block-diagonal P (or the tentative one smoothed across the fields), R = P^T, Galerkin
    //    product of the whole n x n operator.
    name_block_groups(factory(f, "BlockedP", "BlockedPFactory"), "Field", n);
    std::string prolongator = "BlockedP";
    if (across)
      {
        prolongator   = "CoupledP";
        List& coupled = factory(f, prolongator, "CoupledSaPFactory");
        coupled.set("P", "BlockedP");
        coupled.set("sa: damping factor", p.get<double>("sa: damping factor"));
        coupled.set("tentative blocks", tentative_blocks);
        factory(f, "BlockedR", "BlockedTransposeFactory").set("P", prolongator);
      }
    else
      factory(f, "BlockedR", "GenericRFactory").set("P", prolongator);
    // the project's Galerkin product: MueLu 13.2's BlockedRAPFactory fails on a third product
    // in one block (a coupled P) and always forms A P first (coupled_prolongator.h)
    List& rap = factory(f, "BlockedRAP", "BlockedGalerkinFactory");
    rap.set("P", prolongator);
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
    all.set("P", prolongator);
    all.set("R", std::string("BlockedR"));
    all.set("A", std::string("BlockedRAP"));
    return muelu;
  }

  LeaderNodeMaps follower_node_maps(const Preset& preset, const BlockSystem& system,
                                    std::vector<std::string>& notes)
  {
    LeaderNodeMaps maps;
    for (std::size_t k = 0; k < system.n_blocks(); ++k)
      if (const auto leader = leader_of(preset.parameters, system, k, preset.name))
        {
          const auto& follower = system.block(k);
          const auto& lead     = system.block(*leader);
          const int   dim      = static_cast<int>(follower.coordinates->getNumVectors());
          // positions equal to 1e-9 of the leader's extent on this rank
          const auto   leader_xyz = local_positions(lead);
          const double extent     = largest_extent(leader_xyz, dim);
          const auto   match =
              same_positions(local_positions(follower), leader_xyz, dim, extent > 0 ? 1e-9 * extent : 1e-12);
          auto& map             = maps[leader_map_name(k)];
          GO    local_unmatched = 0;
          for (std::size_t i = 0; i < match.size(); ++i)
            {
              map[static_cast<LO>(i)] = match[i] < 0 ? no_primal_node : static_cast<LO>(match[i]);
              local_unmatched += match[i] < 0;
            }
          GO unmatched = 0;
          Teuchos::reduceAll(*system.comm(), Teuchos::REDUCE_SUM, local_unmatched,
                             Teuchos::outArg(unmatched));
          const GO nodes = follower.global_size / follower.dofs_per_node;
          if (unmatched == nodes)
            throw InputError("preset '" + preset.name + "': block '" + follower.name +
                             "' takes the aggregates of '" + lead.name +
                             "' at the same node positions, and none of its nodes has a '" + lead.name +
                             "' node at its position on its rank");
          notes.push_back("block '" + follower.name + "' takes the aggregates of '" + lead.name +
                          "': " + std::to_string(nodes - unmatched) + " of " + std::to_string(nodes) +
                          " nodes matched" +
                          (unmatched > 0 ? " (the others aggregated on its own graph)" : ""));
        }
    return maps;
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
