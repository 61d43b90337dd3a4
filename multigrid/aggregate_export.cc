#include "aggregate_export.h"

#include "hierarchy_utils.h"
#include "temporary_files.h"

#include <MueLu_Aggregates.hpp>
#include <MueLu_Hierarchy.hpp>
#include <MueLu_Level.hpp>
#include <MueLu_Monitor.hpp>
#include <MueLu_TwoLevelFactoryBase.hpp>

#include <Teuchos_CommHelpers.hpp>

#include <filesystem>
#include <fstream>
#include <map>
#include <set>
#include <sstream>

namespace multigrid
{
  namespace
  {
    using MueLu::Level;
    using MueLu::NoFactory;

    /// What the recorder leaves on a level: the local aggregate of each owned node of one field.
    struct LevelAggregates
    {
      std::vector<LO> node_to_aggregate; ///< -1: in no aggregate of this rank
      LO              n_aggregates = 0;
    };

    std::string record_name(int block)
    {
      return "project: aggregates of block " + std::to_string(block);
    }

    /// Stores the finer level's aggregates of one field as user data (kept after the set-up).
    class AggregateRecordFactory : public MueLu::TwoLevelFactoryBase
    {
    public:
      RCP<const Teuchos::ParameterList> GetValidParameterList() const override
      {
        auto list = Teuchos::rcp(new Teuchos::ParameterList());
        list->set<RCP<const FactoryBase>>("Aggregates", Teuchos::null, "The field's aggregation factory");
        list->set<int>("block", 0, "The field (block index) whose aggregates these are");
        return list;
      }

      void DeclareInput(Level& fine, Level&) const override { Input(fine, "Aggregates"); }

      void Build(Level& fine, Level& coarse) const override
      {
        MueLu::FactoryMonitor monitor(*this, "Record the aggregates (project)", coarse);
        const auto            aggregates = Get<RCP<MueLu::Aggregates<LO, GO, NO>>>(fine, "Aggregates");
        const auto            vertex     = aggregates->GetVertex2AggId()->getData(0);
        const auto            winner     = aggregates->GetProcWinner()->getData(0);
        const int             rank       = aggregates->GetMap()->getComm()->getRank();
        // Entries of the overlapping node map: the owned nodes first (in the order of the rows),
        // then ghosts. recorded_aggregates reads the owned ones only; a node aggregated by
        // another rank (none in uncoupled aggregation) counts as in no aggregate here.
        auto record          = Teuchos::rcp(new LevelAggregates());
        record->n_aggregates = aggregates->GetNumAggregates();
        record->node_to_aggregate.assign(vertex.size(), -1);
        for (LO i = 0; i < vertex.size(); ++i)
          if (winner[i] == rank)
            record->node_to_aggregate[i] = vertex[i];
        fine.Set(record_name(GetParameterList().get<int>("block")), record, NoFactory::get());
      }
    };

    /// A named group's "Aggregates" factory, in the order of the blocks of the BlockedPFactory.
    std::vector<std::string> aggregation_factories(const Teuchos::ParameterList& factories,
                                                   const Teuchos::ParameterList& blocked_p)
    {
      std::vector<std::string> names;
      for (auto it = blocked_p.begin(); it != blocked_p.end(); ++it)
        {
          if (!blocked_p.isSublist(blocked_p.name(it)))
            continue;
          const auto& block = blocked_p.sublist(blocked_p.name(it));
          const auto  group = value_or<std::string>(block, "group", "");
          if (group.empty() || !factories.isSublist(group) ||
              !factories.sublist(group).isParameter("Aggregates"))
            throw InputError("the MueLu list's BlockedPFactory block '" + blocked_p.name(it) +
                             "' names no group with 'Aggregates' (needed to export the aggregates)");
          names.push_back(value_or<std::string>(factories.sublist(group), "Aggregates", ""));
        }
      return names;
    }

    std::string factory_kind(const Teuchos::ParameterList& list, const std::string& name)
    {
      return list.isSublist(name) ? value_or<std::string>(list.sublist(name), "factory", "") : "";
    }

    /// Global id of the first aggregate of this rank (exclusive scan of the local counts).
    GO first_global_aggregate(const Comm& comm, LO local)
    {
      GO mine = local, inclusive = 0;
      Teuchos::scan(comm, Teuchos::REDUCE_SUM, 1, &mine, &inclusive);
      return inclusive - mine;
    }

    // ---- VTK XML output (ASCII: small point sets, read by ParaView and python3-vtk9) ----

    struct Points
    {
      std::vector<double>                           xyz; // 3 per point
      std::map<std::string, std::vector<long long>> arrays;
    };

    void write_vtu(const Points& points, const std::string& file)
    {
      const std::size_t  n = points.xyz.size() / 3;
      std::ostringstream s;
      s << "<?xml version=\"1.0\"?>\n<VTKFile type=\"UnstructuredGrid\" "
           "version=\"0.1\">\n<UnstructuredGrid>\n"
        << "<Piece NumberOfPoints=\"" << n << "\" NumberOfCells=\"" << n << "\">\n<PointData>\n";
      for (const auto& [name, values] : points.arrays)
        {
          s << "<DataArray type=\"Int64\" Name=\"" << name << "\" format=\"ascii\">\n";
          for (const auto v : values)
            s << v << ' ';
          s << "\n</DataArray>\n";
        }
      s << "</PointData>\n<Points>\n<DataArray type=\"Float64\" NumberOfComponents=\"3\" format=\"ascii\">\n";
      s.precision(12);
      for (const double x : points.xyz)
        s << x << ' ';
      s << "\n</DataArray>\n</Points>\n<Cells>\n"
        << "<DataArray type=\"Int64\" Name=\"connectivity\" format=\"ascii\">\n";
      for (std::size_t i = 0; i < n; ++i)
        s << i << ' ';
      s << "\n</DataArray>\n<DataArray type=\"Int64\" Name=\"offsets\" format=\"ascii\">\n";
      for (std::size_t i = 0; i < n; ++i)
        s << i + 1 << ' ';
      s << "\n</DataArray>\n<DataArray type=\"UInt8\" Name=\"types\" format=\"ascii\">\n";
      for (std::size_t i = 0; i < n; ++i)
        s << "1 "; // VTK_VERTEX
      s << "\n</DataArray>\n</Cells>\n</Piece>\n</UnstructuredGrid>\n</VTKFile>\n";
      write_file_atomically(file, s.str());
    }

    void write_pvtu(const std::vector<std::string>& arrays, const std::vector<std::string>& pieces,
                    const std::string& file)
    {
      std::ostringstream s;
      s << "<?xml version=\"1.0\"?>\n<VTKFile type=\"PUnstructuredGrid\" version=\"0.1\">\n"
        << "<PUnstructuredGrid GhostLevel=\"0\">\n<PPointData>\n";
      for (const auto& name : arrays)
        s << "<PDataArray type=\"Int64\" Name=\"" << name << "\"/>\n";
      s << "</PPointData>\n<PPoints>\n<PDataArray type=\"Float64\" NumberOfComponents=\"3\"/>\n</PPoints>\n";
      for (const auto& piece : pieces)
        s << "<Piece Source=\"" << piece << "\"/>\n";
      s << "</PUnstructuredGrid>\n</VTKFile>\n";
      write_file_atomically(file, s.str());
    }

    /// Node positions of block k on this rank (3 per owned node), or empty when it has none.
    std::vector<double> node_positions(const BlockSystem& system, std::size_t k)
    {
      const auto& b       = system.block(k);
      const auto  n_nodes = b.map->getNodeNumElements() / b.dofs_per_node;
      auto        from    = [&](const MultiVector& c, auto node_of) {
        std::vector<double> xyz(3 * n_nodes, 0.0);
        for (std::size_t d = 0; d < c.getNumVectors() && d < 3; ++d)
          {
            const auto data = c.getData(d);
            for (std::size_t i = 0; i < n_nodes; ++i)
              xyz[3 * i + d] = data[node_of(i)];
          }
        return xyz;
      };
      if (!b.coordinates.is_null() && b.coordinates->getLocalLength() == n_nodes)
        return from(*b.coordinates, [](std::size_t i) { return i; });
      // Contact multipliers: at their slave nodes.
      const auto& primal = system.block(0).coordinates;
      if (k == 1 && system.has_interface() && !primal.is_null() &&
          system.interface().dual_to_primal_node.size() == n_nodes)
        return from(*primal, [&](std::size_t i) { return system.interface().dual_to_primal_node.at(i); });
      return {};
    }
  } // namespace

  void record_aggregates(Teuchos::ParameterList& muelu)
  {
    if (!muelu.isSublist("Factories"))
      throw InputError(
          "exporting aggregates needs a factory-style blocked MueLu list (this preset has none)");
    auto&                    factories = muelu.sublist("Factories");
    std::vector<std::string> fields;
    std::vector<std::string> raps;
    for (auto it = factories.begin(); it != factories.end(); ++it)
      {
        const auto& name = factories.name(it);
        const auto  kind = factory_kind(factories, name);
        if (kind == "BlockedPFactory")
          fields = aggregation_factories(factories, factories.sublist(name));
        else if (kind == "BlockedRAPFactory" || kind == "BlockedGalerkinFactory")
          raps.push_back(name);
      }
    if (fields.empty() || raps.size() != 1)
      throw InputError("exporting aggregates needs a MueLu list with one BlockedPFactory and one "
                       "BlockedRAPFactory or BlockedGalerkinFactory");
    auto& transfers = factories.sublist(raps.front()).sublist("TransferFactories");
    for (std::size_t k = 0; k < fields.size(); ++k)
      {
        auto& recorder = transfers.sublist("RecordAggregates" + std::to_string(k));
        recorder.set("factory", std::string("AggregateRecordFactory"));
        recorder.set("Aggregates", fields[k]);
        recorder.set("block", static_cast<int>(k));
      }
  }

  RCP<const MueLu::FactoryBase>
  build_aggregate_record_factory(const Teuchos::ParameterList&        list,
                                 const RCP<const MueLu::FactoryBase>& aggregates)
  {
    auto factory = Teuchos::rcp(new AggregateRecordFactory());
    factory->SetParameter("block", Teuchos::ParameterEntry(list.get<int>("block")));
    factory->SetFactory("Aggregates", aggregates);
    return factory;
  }

  std::vector<FieldAggregates> recorded_aggregates(MueLu::Hierarchy<SC, LO, GO, NO>& H,
                                                   const BlockSystem&                system)
  {
    const auto&                  comm = *system.comm();
    std::vector<FieldAggregates> result;
    for (std::size_t k = 0; k < system.n_blocks(); ++k)
      {
        FieldAggregates field;
        field.block = k;
        // current[i]: the local node of the level being composed that holds fine node i.
        const auto&     b = system.block(k);
        std::vector<LO> current(b.map->getNodeNumElements() / b.dofs_per_node);
        for (std::size_t i = 0; i < current.size(); ++i)
          current[i] = static_cast<LO>(i);
        for (int l = 0; l + 1 < H.GetNumLevels(); ++l)
          {
            auto level = H.GetLevel(l);
            if (!level->IsAvailable(record_name(static_cast<int>(k)), NoFactory::get()))
              throw InputError("no aggregates were recorded for block " + std::to_string(k) + " on level " +
                               std::to_string(l) + " (the list was not passed through record_aggregates)");
            const auto record =
                level->Get<RCP<LevelAggregates>>(record_name(static_cast<int>(k)), NoFactory::get());
            const GO        first = first_global_aggregate(comm, record->n_aggregates);
            std::vector<GO> global(current.size(), -1);
            for (std::size_t i = 0; i < current.size(); ++i)
              {
                const LO node = current[i];
                const LO a    = node >= 0 && static_cast<std::size_t>(node) < record->node_to_aggregate.size()
                                    ? record->node_to_aggregate[node]
                                    : -1;
                current[i]    = a;
                global[i]     = a >= 0 ? first + a : -1;
              }
            field.levels.push_back(std::move(global));
          }
        result.push_back(std::move(field));
      }
    return result;
  }

  void write_aggregates(const BlockSystem& system, const std::vector<FieldAggregates>& aggregates,
                        const std::string& path)
  {
    const auto& comm     = *system.comm();
    const int   rank     = comm.getRank();
    std::size_t n_levels = 0;
    for (const auto& f : aggregates)
      n_levels = std::max(n_levels, f.levels.size());

    Points     points;
    const auto labels = system.has_interface() ? system.segregation_labels() : Teuchos::null;
    const auto label  = labels.is_null() ? Teuchos::ArrayRCP<const double>() : labels->getData(0);
    auto&      field  = points.arrays["field"];
    auto&      ranks  = points.arrays["rank"];
    auto&      body   = points.arrays["body"];
    std::vector<std::vector<long long>*> level_ids;
    for (std::size_t l = 0; l < n_levels; ++l)
      level_ids.push_back(&points.arrays["aggregate_level_" + std::to_string(l + 1)]);
    for (const auto& f : aggregates)
      {
        const auto xyz = node_positions(system, f.block);
        if (xyz.empty())
          continue;
        const std::size_t n   = xyz.size() / 3;
        const int         dpn = system.block(f.block).dofs_per_node;
        points.xyz.insert(points.xyz.end(), xyz.begin(), xyz.end());
        for (std::size_t i = 0; i < n; ++i)
          {
            field.push_back(static_cast<long long>(f.block));
            ranks.push_back(rank);
            body.push_back(f.block == 0 && !label.is_null() ? static_cast<long long>(label[i * dpn]) : -1);
            for (std::size_t l = 0; l < n_levels; ++l)
              level_ids[l]->push_back(l < f.levels.size() ? f.levels[l][i] : -1);
          }
      }
    namespace fs = std::filesystem;
    const fs::path    target(path);
    const std::string stem = target.filename().string();
    if (rank == 0 && target.has_parent_path())
      fs::create_directories(target.parent_path());
    comm.barrier();
    write_vtu(points, (target.parent_path() / (stem + "_rank" + std::to_string(rank) + ".vtu")).string());
    comm.barrier();
    if (rank == 0)
      {
        std::vector<std::string> arrays{"field", "rank", "body"}, pieces;
        for (std::size_t l = 0; l < n_levels; ++l)
          arrays.push_back("aggregate_level_" + std::to_string(l + 1));
        for (int r = 0; r < comm.getSize(); ++r)
          pieces.push_back(stem + "_rank" + std::to_string(r) + ".vtu");
        write_pvtu(arrays, pieces, path + ".pvtu");
      }
    comm.barrier();
  }

  long long aggregates_crossing_bodies(const BlockSystem& system, const FieldAggregates& primal, int level)
  {
    const auto& comm = *system.comm();
    if (level < 1 || static_cast<std::size_t>(level) > primal.levels.size())
      throw InputError("aggregates_crossing_bodies: no level " + std::to_string(level));
    const auto label_vector = system.segregation_labels(); // keeps the data of `labels` alive
    const auto labels       = label_vector->getData(0);
    const int  dpn    = system.block(primal.block).dofs_per_node;
    // Aggregates never span ranks (uncoupled aggregation), so the check is local.
    std::map<GO, std::set<long long>> bodies;
    const auto&                       ids = primal.levels[level - 1];
    for (std::size_t i = 0; i < ids.size(); ++i)
      if (ids[i] >= 0)
        bodies[ids[i]].insert(static_cast<long long>(labels[i * dpn]));
    long long crossing = 0, total = 0;
    for (const auto& [id, set] : bodies)
      crossing += set.size() > 1;
    Teuchos::reduceAll(comm, Teuchos::REDUCE_SUM, 1, &crossing, &total);
    return total;
  }
} // namespace multigrid
