#include "block_system_io.h"

#include "spatial_order.h"
#include "temporary_files.h"

#include <Xpetra_IO.hpp>
#include <Xpetra_ImportFactory.hpp>
#include <Xpetra_MapFactory.hpp>
#include <Xpetra_StridedMap.hpp>
#include <Xpetra_MultiVector.hpp>

#include <Teuchos_CommHelpers.hpp>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <functional>
#include <limits>
#include <numeric>
#include <sstream>
#include <unordered_map>

namespace fs = std::filesystem;

namespace multigrid
{
  namespace
  {
    /// What a system on disk consists of, independent of the number of ranks.
    struct Description
    {
      struct Block
      {
        std::string name;
        GO          size          = 0;
        int         dofs_per_node = 1;
        std::string nullspace;   ///< file or empty
        std::string coordinates; ///< file of nodal coordinates or empty
      };
      std::string        source; ///< for messages
      std::string        matrix, rhs;
      std::vector<Block> blocks;
      bool               has_interface = false;
      std::vector<GO>    dual_to_primal;   ///< primal node of every dual node (global)
      std::vector<GO>    segregation_gids; ///< DOFs of the slave body (global), may be empty
      std::string        body_labels;      ///< file of the primal DOFs' body labels, or empty
      std::vector<int>   owner;            ///< writer's rank of every global row, or empty
      int                written_ranks = 0; ///< the writer's number of ranks (with `owner`)
    };

    void require_file(const std::string& file, const std::string& what)
    {
      if (!fs::is_regular_file(file))
        throw InputError(file + ": " + what + " file not found");
    }

    /// The value lines of a Matrix Market array file: every line after the comments and the size line.
    std::vector<std::string> array_lines(const std::string& file)
    {
      std::ifstream            in(file);
      std::string              line;
      bool                     seen_size = false;
      std::vector<std::string> lines;
      while (std::getline(in, line))
        {
          if (line.empty() || line[0] == '%')
            continue;
          if (seen_size)
            lines.push_back(line);
          seen_size = true;
        }
      return lines;
    }

    std::vector<GO> read_integer_array(const std::string& file, long long& rows, long long& cols)
    {
      const auto header = scan_matrix_market(file);
      if (header.coordinate || header.field != "integer")
        throw InputError(file + ": expected a Matrix Market 'array integer' file");
      rows = header.rows;
      cols = header.cols;
      std::vector<GO> values;
      for (const auto& line : array_lines(file))
        values.push_back(std::strtoll(line.c_str(), nullptr, 10));
      return values;
    }

    /// The integer values of a one-column Matrix Market array (integer or real field), each
    /// checked to lie in lo .. hi; `what` names the values in messages.
    std::vector<int> read_integer_column(const std::string& file, int lo, int hi, const std::string& what)
    {
      const auto header = scan_matrix_market(file);
      if (header.coordinate || header.cols != 1)
        throw InputError(file + ": expected a one-column Matrix Market array (" + what + ")");
      std::vector<int> values;
      for (const auto& line : array_lines(file))
        {
          const double r = std::strtod(line.c_str(), nullptr);
          if (!(r >= lo && r <= hi) || r != static_cast<int>(r))
            throw InputError(file + ": row " + std::to_string(values.size()) + " has " + what + " '" + line +
                             "', expected an integer " + std::to_string(lo) + ".." + std::to_string(hi));
          values.push_back(static_cast<int>(r));
        }
      if (static_cast<long long>(values.size()) != header.rows)
        throw InputError(file + ": " + std::to_string(values.size()) + " values, the header says " +
                         std::to_string(header.rows));
      return values;
    }

    Description describe_manifest(const std::string& dir)
    {
      const std::string manifest = (fs::path(dir) / "manifest.txt").string();
      require_file(manifest, "manifest");
      Description d;
      d.source = manifest;
      std::ifstream in(manifest);
      std::string   line, format;
      int           line_no = 0;
      std::string   dual_to_primal_file, segregation_file, labels_file, partition_file;
      auto          bad = [&](const std::string& what) {
        throw InputError(manifest + ":" + std::to_string(line_no) + ": " + what);
      };
      while (std::getline(in, line))
        {
          ++line_no;
          if (line.empty() || line[0] == '#')
            continue;
          std::istringstream s(line);
          std::string        key;
          s >> key;
          if (key == "format")
            s >> format;
          else if (key == "matrix")
            s >> d.matrix;
          else if (key == "rhs")
            s >> d.rhs;
          else if (key == "block")
            {
              Description::Block b;
              std::string        nsp, xyz;
              if (!(s >> b.name >> b.size >> b.dofs_per_node))
                bad("expected 'block <name> <size> <dofs per node> [nullspace|-] [coordinates|-]'");
              if (b.size <= 0 || b.dofs_per_node <= 0)
                bad("block '" + b.name + "': size and DOFs per node must be positive");
              if (s >> nsp && nsp != "-")
                b.nullspace = (fs::path(dir) / nsp).string();
              if (s >> xyz && xyz != "-")
                b.coordinates = (fs::path(dir) / xyz).string();
              d.blocks.push_back(b);
            }
          else if (key == "interface")
            {
              if (!(s >> dual_to_primal_file))
                bad("expected 'interface <dual-to-primal file> [segregation file|-] [body labels file]'");
              s >> segregation_file >> labels_file;
              d.has_interface = true;
            }
          else if (key == "partition")
            {
              if (!(s >> partition_file >> d.written_ranks) || d.written_ranks < 1)
                bad("expected 'partition <file> <number of ranks>'");
            }
          else
            bad("unknown key '" + key + "' (expected format, matrix, rhs, block, interface, partition)");
        }
      if (format != "block-system-1")
        throw InputError(manifest + ": format '" + format + "', expected 'block-system-1'");
      if (d.matrix.empty() || d.blocks.empty())
        throw InputError(manifest + ": needs a 'matrix' line and at least one 'block' line");
      d.matrix = (fs::path(dir) / d.matrix).string();
      if (!d.rhs.empty())
        d.rhs = (fs::path(dir) / d.rhs).string();
      if (d.has_interface)
        {
          long long         rows = 0, cols = 0;
          const std::string f = (fs::path(dir) / dual_to_primal_file).string();
          require_file(f, "dual-to-primal mapping");
          const auto v = read_integer_array(f, rows, cols);
          if (cols != 2 || static_cast<long long>(v.size()) != 2 * rows)
            throw InputError(f + ": expected a two-column integer array (dual node, primal node)");
          d.dual_to_primal.assign(rows, -1);
          for (long long i = 0; i < rows; ++i)
            {
              const GO dual = v[i], primal = v[rows + i];
              if (dual < 0 || dual >= rows)
                throw InputError(f + ": dual node " + std::to_string(dual) + " out of range");
              d.dual_to_primal[dual] = primal;
            }
          if (!segregation_file.empty() && segregation_file != "-")
            d.segregation_gids = read_map_gids((fs::path(dir) / segregation_file).string());
          if (!labels_file.empty())
            {
              d.body_labels = (fs::path(dir) / labels_file).string();
              require_file(d.body_labels, "body labels");
            }
        }
      if (!partition_file.empty())
        {
          const std::string f = (fs::path(dir) / partition_file).string();
          require_file(f, "partition");
          d.owner = read_integer_column(f, 0, d.written_ranks - 1, "rank");
        }
      return d;
    }

    Description describe_single_matrix(const std::string& prefix, const ReadOptions& options)
    {
      Description d;
      // PREFIX_block_matrix.mm, where present, is the whole system and PREFIX_matrix.mm its
      // primal block (the segregatedAgg convention); otherwise PREFIX_matrix.mm is the whole system.
      d.source = fs::is_regular_file(prefix + "_block_matrix.mm") ? prefix + "_block_matrix.mm"
                                                                  : prefix + "_matrix.mm";
      d.matrix = d.source;
      require_file(d.matrix, "matrix");
      d.rhs = prefix + "_rhs.mm";
      if (!fs::is_regular_file(d.rhs))
        d.rhs.clear(); // no right-hand side stored: b = 0 (callers set their own)
      std::string nullspace = prefix + "_nullspace1.mm";
      if (!fs::is_regular_file(nullspace))
        nullspace = prefix + "_nullspace.mm";
      require_file(nullspace, "primal nullspace");
      const std::string interface_file = prefix + "_interface_dof_map_MPI1.mm";
      require_file(interface_file, "interface DOF map");

      // Sizes only: the entries are checked once, on rank 0, when the system is loaded.
      const auto matrix = scan_matrix_market(d.matrix, false);
      const auto nsp    = scan_matrix_market(nullspace, false);
      if (matrix.rows != matrix.cols)
        throw InputError(d.matrix + ": matrix is " + std::to_string(matrix.rows) + " x " +
                         std::to_string(matrix.cols) + ", expected a square saddle-point system");
      const GO n_primal = nsp.rows, n_dual = matrix.rows - nsp.rows;
      if (n_dual <= 0)
        throw InputError(nullspace + ": " + std::to_string(n_primal) +
                         " primal rows leave no multipliers in a " + std::to_string(matrix.rows) +
                         "-row matrix");
      const int dpn = options.dofs_per_node;
      d.blocks.push_back({"displacement", n_primal, dpn, nullspace, ""});
      d.blocks.push_back({"lagrange multiplier", n_dual, dpn, "", ""});

      // The k-th multiplier node belongs to the k-th slave node (ascending ids).
      auto slave = read_map_gids(interface_file);
      std::sort(slave.begin(), slave.end());
      if (static_cast<GO>(slave.size()) != n_dual)
        throw InputError(interface_file + ": " + std::to_string(slave.size()) +
                         " interface DOFs, expected one per multiplier DOF (" + std::to_string(n_dual) + ")");
      d.has_interface = true;
      for (std::size_t k = 0; k < slave.size(); k += dpn)
        {
          if (slave[k] % dpn != 0 || slave[k] >= n_primal)
            throw InputError(interface_file + ": interface DOF " + std::to_string(slave[k]) +
                             " does not start a primal node");
          d.dual_to_primal.push_back(slave[k] / dpn);
        }
      return d;
    }

    /// The block's owned DOFs numbered within the block (global id minus the block's offset):
    /// nullspace files are stored in this numbering, independent of the other blocks.
    RCP<const Map> block_local_map(const BlockInfo& b, const RCP<const Comm>& comm)
    {
      std::vector<GO> local;
      for (GO g : b.map->getNodeElementList())
        local.push_back(g - b.offset);
      return Xpetra::MapFactory<LO, GO, NO>::Build(Xpetra::UseTpetra, b.global_size,
                                                   Teuchos::ArrayView<const GO>(local), 0, comm);
    }

    /// The block's owned nodes numbered within the block (coordinates files use this numbering).
    RCP<const Map> block_node_map(const BlockInfo& b, const RCP<const Comm>& comm)
    {
      std::vector<GO> nodes;
      const auto      gids = b.map->getNodeElementList();
      for (decltype(gids.size()) i = 0; i < gids.size(); i += b.dofs_per_node)
        nodes.push_back((gids[i] - b.offset) / b.dofs_per_node);
      return Xpetra::MapFactory<LO, GO, NO>::Build(Xpetra::UseTpetra, b.global_size / b.dofs_per_node,
                                                   Teuchos::ArrayView<const GO>(nodes), 0, comm);
    }

    /// Every id 0..n-1 on rank 0, ascending, none elsewhere. Tpetra's dense Matrix Market reader
    /// and writer stream a vector rank by rank (rank 0's local rows, then rank 1's, ...), not by
    /// global id; on this map the two orders coincide. Rank 0 then holds the whole vector:
    /// acceptable for file I/O (the matrix reader and writer gather on rank 0 as well), not for
    /// the solver's working vectors.
    RCP<const Map> root_map(GO n, const RCP<const Comm>& comm)
    {
      std::vector<GO> all;
      if (comm->getRank() == 0)
        for (GO g = 0; g < n; ++g)
          all.push_back(g);
      return Xpetra::MapFactory<LO, GO, NO>::Build(Xpetra::UseTpetra, n, Teuchos::ArrayView<const GO>(all), 0, comm);
    }

    /// Reads a Matrix Market array whose row i belongs to global id i of `map` (ids 0..n-1),
    /// whatever the distribution of `map`.
    RCP<MultiVector> read_in_global_order(const std::string& file, const RCP<const Map>& map)
    {
      const auto root  = root_map(static_cast<GO>(map->getGlobalNumElements()), map->getComm());
      const auto whole = Xpetra::IO<SC, LO, GO, NO>::ReadMultiVector(file, root);
      auto       v     = Xpetra::MultiVectorFactory<SC, LO, GO, NO>::Build(map, whole->getNumVectors());
      v->doImport(*whole, *Xpetra::ImportFactory<LO, GO, NO>::Build(root, map), Xpetra::INSERT);
      return v;
    }

    /// Contiguous chunk of `n` items owned by `rank` out of `size`.
    std::pair<GO, GO> chunk(GO n, int rank, int size)
    {
      return {n * rank / size, n * (rank + 1) / size};
    }

    /// The Z-order keys (morton_keys) of every block's nodes from its coordinates file (a block
    /// without one: no keys, its nodes keep their id order).
    std::vector<std::vector<std::uint64_t>> spatial_keys(const Description& d)
    {
      std::vector<std::vector<double>> xyz(d.blocks.size());
      std::vector<int>                 dims(d.blocks.size(), 0);
      for (std::size_t k = 0; k < d.blocks.size(); ++k)
        {
          const auto& file = d.blocks[k].coordinates;
          if (file.empty())
            continue;
          // Its entries were checked on rank 0 (load); here the header and the count suffice.
          const auto header = scan_matrix_market(file, false);
          if (header.coordinate || header.cols < 1 || header.cols > 3)
            throw InputError(file + ": expected a Matrix Market array of 1 to 3 columns (coordinates)");
          dims[k] = static_cast<int>(header.cols);
          for (const auto& line : array_lines(file))
            xyz[k].push_back(std::strtod(line.c_str(), nullptr));
          if (static_cast<long long>(xyz[k].size()) != header.rows * header.cols)
            throw InputError(file + ": " + std::to_string(xyz[k].size()) + " values, the header says " +
                             std::to_string(header.rows) + " x " + std::to_string(header.cols));
        }
      return morton_keys(xyz, dims);
    }

    /// This rank's nodes of block k (ascending), whose first DOF has global id `offset`. Without a
    /// partition: contiguous equal chunks of the node ids. With one (written by the app that
    /// exported the system): on the writer's number of ranks exactly the writer's distribution;
    /// on another number the nodes ordered by (writer's rank, body label where the primal block
    /// has them, position along a Z-order curve where the block has coordinates, id) and cut
    /// into equal chunks, so that every rank holds whole pieces of the writer's subdomains,
    /// where it can whole bodies, and a piece of space in every field. A contiguous split of the
    /// ids alone may scatter a subdomain over the ranks (the apps' global numbering need not
    /// follow the mesh partition), and rank-local aggregation then builds aggregates of a few
    /// nodes (measured on the collapsing rings: twice the coarse rows and 2x the GMRES
    /// iterations; on the FSI tube written on 1 rank and read on 2, 38 instead of 12.6 GMRES
    /// iterations for bgs(amg)). `keys`: spatial_keys(d).
    std::vector<GO> owned_nodes(const Description& d, std::size_t k, GO offset, int rank, int size,
                                const std::vector<std::vector<std::uint64_t>>& keys)
    {
      const auto&     b = d.blocks[k];
      const GO        n = b.size / b.dofs_per_node;
      std::vector<GO> nodes;
      if (d.owner.empty())
        {
          const auto [lo, hi] = chunk(n, rank, size);
          for (GO i = lo; i < hi; ++i)
            nodes.push_back(i);
          return nodes;
        }
      auto owner = [&](GO node) { return d.owner[offset + node * b.dofs_per_node]; };
      if (size == d.written_ranks)
        {
          for (GO i = 0; i < n; ++i)
            if (owner(i) == rank)
              nodes.push_back(i);
          return nodes;
        }
      std::vector<int> body(n, 0);
      if (k == 0 && !d.body_labels.empty())
        {
          const auto labels = read_integer_column(d.body_labels, std::numeric_limits<int>::min(),
                                                  std::numeric_limits<int>::max(), "body label");
          if (static_cast<GO>(labels.size()) != b.size)
            throw InputError(d.body_labels + ": " + std::to_string(labels.size()) +
                             " body labels, expected " + std::to_string(b.size) + " (one per primal DOF)");
          for (GO i = 0; i < n; ++i)
            body[i] = labels[i * b.dofs_per_node];
        }
      std::vector<GO> order(n);
      std::iota(order.begin(), order.end(), GO(0));
      const auto& key = keys[k];
      auto        at  = [&](GO node) { return key.empty() ? std::uint64_t(0) : key[node]; };
      std::stable_sort(order.begin(), order.end(), [&](GO a, GO c) {
        return std::make_tuple(owner(a), body[a], at(a)) < std::make_tuple(owner(c), body[c], at(c));
      });
      const auto [lo, hi] = chunk(n, rank, size);
      nodes.assign(order.begin() + lo, order.begin() + hi);
      std::sort(nodes.begin(), nodes.end());
      return nodes;
    }

    BlockSystem load(const Description& d, RCP<const Comm> comm)
    {
      GO total = 0;
      for (const auto& b : d.blocks)
        {
          if (b.size % b.dofs_per_node != 0)
            throw InputError(d.source + ": block '" + b.name + "' size " + std::to_string(b.size) +
                             " is not a multiple of " + std::to_string(b.dofs_per_node) + " DOFs per node");
          total += b.size;
        }
      on_root(*comm, [&] {
        const auto h = scan_matrix_market(d.matrix, false); // its entries: read_sparse_matrix_market
        if (!h.coordinate)
          throw InputError(d.matrix + ": expected a Matrix Market coordinate matrix");
        if (h.rows != h.cols)
          throw InputError(d.matrix + ": matrix is " + std::to_string(h.rows) + " x " +
                           std::to_string(h.cols) + ", expected square");
        if (h.rows != total)
          throw InputError(d.matrix + ": matrix has " + std::to_string(h.rows) +
                           " rows, but the blocks add up to " + std::to_string(total));
        if (!d.rhs.empty())
          {
            const auto r = scan_matrix_market(d.rhs);
            if (r.coordinate || r.rows != total || r.cols != 1)
              throw InputError(d.rhs + ": right-hand side is " + std::to_string(r.rows) + " x " +
                               std::to_string(r.cols) + ", expected a " + std::to_string(total) +
                               " x 1 array");
          }
        for (const auto& b : d.blocks)
          {
            if (!b.nullspace.empty())
              {
                const auto n = scan_matrix_market(b.nullspace);
                if (n.coordinate || n.rows != b.size)
                  throw InputError(b.nullspace + ": nullspace has " + std::to_string(n.rows) +
                                   " rows, expected " + std::to_string(b.size) + " (block '" + b.name + "')");
              }
            if (!b.coordinates.empty())
              {
                const auto n = scan_matrix_market(b.coordinates);
                if (n.coordinate || n.rows != b.size / b.dofs_per_node)
                  throw InputError(b.coordinates + ": coordinates of " + std::to_string(n.rows) +
                                   " nodes, expected " + std::to_string(b.size / b.dofs_per_node) +
                                   " (block '" + b.name + "')");
              }
          }
        if (d.has_interface)
          {
            if (d.blocks.size() != 2)
              throw InputError(d.source + ": interface data needs 2 blocks, found " +
                               std::to_string(d.blocks.size()));
            const GO n_dual_nodes   = d.blocks[1].size / d.blocks[1].dofs_per_node;
            const GO n_primal_nodes = d.blocks[0].size / d.blocks[0].dofs_per_node;
            if (static_cast<GO>(d.dual_to_primal.size()) != n_dual_nodes)
              throw InputError(d.source + ": dual-to-primal mapping has " +
                               std::to_string(d.dual_to_primal.size()) + " entries, expected " +
                               std::to_string(n_dual_nodes) + " multiplier nodes");
            for (GO p : d.dual_to_primal)
              if (p < 0 || p >= n_primal_nodes)
                throw InputError(d.source + ": dual-to-primal mapping names primal node " +
                                 std::to_string(p) + ", expected 0.." + std::to_string(n_primal_nodes - 1));
          }
      });

      // Owned DOFs: every block's nodes as the writer distributed them (see owned_nodes); the
      // multiplier nodes of an interface follow their primal node.
      const int rank = comm->getRank(), size = comm->getSize();
      if (!d.owner.empty() && static_cast<GO>(d.owner.size()) != total)
        throw InputError(d.source + ": the partition has " + std::to_string(d.owner.size()) +
                         " rows, but the blocks add up to " + std::to_string(total));
      std::vector<BlockInfo>       blocks;
      std::vector<std::vector<GO>> owned(d.blocks.size());
      std::unordered_map<GO, LO>   primal_local; // owned primal node -> its local node index
      GO                           offset = 0;
      const auto                   keys   = (!d.owner.empty() && size != d.written_ranks)
                                                ? spatial_keys(d)
                                                : std::vector<std::vector<std::uint64_t>>(d.blocks.size());
      for (std::size_t k = 0; k < d.blocks.size(); ++k)
        {
          const auto& b = d.blocks[k];
          const GO    n = b.size / b.dofs_per_node;
          if (k == 1 && d.has_interface)
            {
              for (GO j = 0; j < n; ++j)
                if (primal_local.count(d.dual_to_primal[j]))
                  for (int c = 0; c < b.dofs_per_node; ++c)
                    owned[k].push_back(offset + j * b.dofs_per_node + c);
            }
          else
            for (const GO node : owned_nodes(d, k, offset, rank, size, keys))
              {
                if (k == 0)
                  primal_local.emplace(node, static_cast<LO>(primal_local.size()));
                for (int c = 0; c < b.dofs_per_node; ++c)
                  owned[k].push_back(offset + node * b.dofs_per_node + c);
              }
          BlockInfo info;
          info.name          = b.name;
          info.dofs_per_node = b.dofs_per_node;
          info.global_size   = b.size;
          blocks.push_back(info);
          offset += b.size;
        }
      std::vector<GO> all;
      for (const auto& o : owned)
        all.insert(all.end(), o.begin(), o.end());
      RCP<const Map> row_map = Xpetra::MapFactory<LO, GO, NO>::Build(
          Xpetra::UseTpetra, total, Teuchos::ArrayView<const GO>(all), 0, comm);

      RCP<Matrix>      A      = read_sparse_matrix_market(d.matrix, row_map);
      RCP<MultiVector> rhs    = d.rhs.empty() ? Teuchos::null : read_in_global_order(d.rhs, row_map);
      BlockSystem      system = BlockSystem::from_merged(comm, blocks, owned, A, rhs);

      // Nullspace and coordinates files are numbered within their block (DOFs, nodes), and row i
      // goes to the owner of id i, so any rank count reads the same vectors.
      for (std::size_t k = 0; k < d.blocks.size(); ++k)
        {
          auto& b = system.block(k);
          if (!d.blocks[k].nullspace.empty())
            b.nullspace = with_map(*read_in_global_order(d.blocks[k].nullspace, block_local_map(b, comm)), b.map);
          if (!d.blocks[k].coordinates.empty())
            b.coordinates = read_in_global_order(d.blocks[k].coordinates, block_node_map(b, comm));
        }

      if (d.has_interface)
        {
          InterfaceInfo   info;
          const auto&     primal = system.block(0);
          const auto&     dual   = system.block(1);
          std::vector<GO> interface_dofs;
          const auto      dual_gids = dual.map->getNodeElementList();
          for (decltype(dual_gids.size()) i = 0; i < dual_gids.size(); i += dual.dofs_per_node)
            {
              const GO dual_node   = (dual_gids[i] - dual.offset) / dual.dofs_per_node;
              const GO primal_node = d.dual_to_primal[dual_node];
              info.dual_to_primal_node[static_cast<LO>(i / dual.dofs_per_node)] =
                  primal_local.at(primal_node);
              for (int c = 0; c < primal.dofs_per_node; ++c)
                interface_dofs.push_back(primal_node * primal.dofs_per_node + c);
            }
          info.primal_interface_dofs = Xpetra::MapFactory<LO, GO, NO>::Build(
              Xpetra::UseTpetra, Teuchos::OrdinalTraits<Xpetra::global_size_t>::invalid(),
              Teuchos::ArrayView<const GO>(interface_dofs), 0, comm);
          if (!d.segregation_gids.empty())
            {
              std::vector<GO> mine;
              for (GO g : d.segregation_gids)
                if (primal.map->isNodeGlobalElement(g))
                  mine.push_back(g);
              info.segregation_dofs = Xpetra::MapFactory<LO, GO, NO>::Build(
                  Xpetra::UseTpetra, Teuchos::OrdinalTraits<Xpetra::global_size_t>::invalid(),
                  Teuchos::ArrayView<const GO>(mine), 0, comm);
            }
          if (!d.body_labels.empty())
            {
              const auto n = scan_matrix_market(d.body_labels);
              if (n.rows != primal.global_size || n.cols != 1)
                throw InputError(d.body_labels + ": body labels have " + std::to_string(n.rows) + " x " +
                                 std::to_string(n.cols) + " entries, expected " +
                                 std::to_string(primal.global_size) + " x 1 (one per primal DOF)");
              info.body_labels =
                  with_map(*read_in_global_order(d.body_labels, block_local_map(primal, comm)), primal.map);
            }
          system.set_interface(std::move(info));
        }
      system.validate(d.source);
      return system;
    }
  } // namespace

  std::vector<GO> read_map_gids(const std::string& file)
  {
    require_file(file, "map");
    long long  rows = 0, cols = 0;
    const auto v = read_integer_array(file, rows, cols);
    if (cols != 1 || v.size() % 2 != 0)
      throw InputError(file + ": expected a Tpetra map file ((GID, PID) pairs in one column)");
    std::vector<GO> gids;
    for (std::size_t i = 0; i < v.size(); i += 2)
      gids.push_back(v[i]);
    return gids;
  }

  void write_in_global_order(const MultiVector& v, const std::string& file)
  {
    // Gathered on root_map (see there): rank 0's rows of a block system belong to every block,
    // so the rank-by-rank order of Tpetra's writer is not the row order of matrix.mm.
    const auto& map = v.getMap();
    const GO    n   = static_cast<GO>(map->getGlobalNumElements());
    if (map->getMinAllGlobalIndex() != 0 || map->getMaxAllGlobalIndex() != n - 1)
      throw InputError(file + ": the vector's global ids are not 0.." + std::to_string(n - 1));
    on_root(*map->getComm(), [&] {
      if (!std::ofstream(file))
        throw InputError(file + ": cannot write the file (does its folder exist?)");
    });
    const auto root     = root_map(n, map->getComm());
    auto       gathered = Xpetra::MultiVectorFactory<SC, LO, GO, NO>::Build(root, v.getNumVectors());
    gathered->doImport(v, *Xpetra::ImportFactory<LO, GO, NO>::Build(map, root), Xpetra::INSERT);
    Xpetra::IO<SC, LO, GO, NO>::Write(file, *gathered);
  }

  BlockSystem read_block_system(const std::string& path, RCP<const Comm> comm, const ReadOptions& options)
  {
    if (fs::is_directory(path))
      return load(describe_manifest(path), comm);
    if (fs::is_regular_file(path + "_matrix.mm") || fs::is_regular_file(path + "_block_matrix.mm"))
      return load(describe_single_matrix(path, options), comm);
    throw InputError(path + ": no block system there (expected a directory with manifest.txt, or "
                            "a prefix P with P_matrix.mm)");
  }

  void write_block_system(const BlockSystem& system, const std::string& dir)
  {
    using IO                  = Xpetra::IO<SC, LO, GO, NO>;
    const auto&       comm    = *system.comm();
    // The root's unique name, known to every rank (they all write into it).
    std::string partial = unique_temporary_name(dir, "partial");
    int         length  = static_cast<int>(partial.size());
    Teuchos::broadcast(comm, 0, &length);
    partial.resize(static_cast<std::size_t>(length));
    Teuchos::broadcast(comm, 0, length, partial.data());
    on_root(comm, [&] {
      std::error_code ec;
      fs::remove_all(partial, ec);
      if (!fs::create_directories(partial, ec))
        throw InputError(partial + ": cannot create directory (" + ec.message() + ")");
    });
    comm.barrier();

    std::ostringstream manifest;
    manifest << "# BlockSystem written by the saddle-point multiphysics mini-app\n"
             << "format block-system-1\nmatrix matrix.mm\nrhs rhs.mm\n";
    // Every entry of matrix.mm carries its global (row, column); vectors are written in the
    // order of their global ids, i.e. in the row order of matrix.mm.
    IO::Write(partial + "/matrix.mm", *system.merged_matrix());
    write_in_global_order(*system.rhs(), partial + "/rhs.mm");
    // The writer's rank of every row: a reader on the same number of ranks distributes the
    // system as the app did (see owned_nodes in the reader).
    {
      auto owner = Xpetra::MultiVectorFactory<SC, LO, GO, NO>::Build(system.rhs()->getMap(), 1);
      owner->putScalar(static_cast<SC>(comm.getRank()));
      write_in_global_order(*owner, partial + "/partition.mm");
      manifest << "partition partition.mm " << comm.getSize() << "\n";
    }
    for (std::size_t k = 0; k < system.n_blocks(); ++k)
      {
        const auto& b        = system.block(k);
        std::string nsp_name = "-", xyz_name = "-";
        if (!b.nullspace.is_null())
          {
            nsp_name = "nullspace_" + std::to_string(k) + ".mm";
            write_in_global_order(*with_map(*b.nullspace, block_local_map(b, system.comm())),
                                  partial + "/" + nsp_name);
          }
        if (!b.coordinates.is_null())
          {
            xyz_name = "coordinates_" + std::to_string(k) + ".mm";
            write_in_global_order(*b.coordinates, partial + "/" + xyz_name);
          }
        std::string name = b.name;
        std::replace(name.begin(), name.end(), ' ', '_');
        manifest << "block " << name << " " << b.global_size << " " << b.dofs_per_node << " " << nsp_name << " "
                 << xyz_name << "\n";
      }
    if (system.has_interface())
      {
        const auto&     info   = system.interface();
        const auto&     primal = system.block(0);
        const auto&     dual   = system.block(1);
        const GO        n_dual = dual.global_size / dual.dofs_per_node;
        std::vector<GO> local(n_dual, -1), global(n_dual, -1);
        const auto      dual_gids   = dual.map->getNodeElementList();
        const auto      primal_gids = primal.map->getNodeElementList();
        for (const auto& [d, p] : info.dual_to_primal_node)
          local[(dual_gids[d * dual.dofs_per_node] - dual.offset) / dual.dofs_per_node] =
              primal_gids[p * primal.dofs_per_node] / primal.dofs_per_node;
        Teuchos::reduceAll(comm, Teuchos::REDUCE_MAX, static_cast<int>(n_dual), local.data(), global.data());
        std::string segregation = "-";
        if (!info.segregation_dofs.is_null())
          {
            segregation = "segregation_dofs.mm";
            IO::Write(partial + "/" + segregation, *info.segregation_dofs);
          }
        manifest << "interface dual_to_primal.mm " << segregation;
        if (!info.body_labels.is_null())
          {
            write_in_global_order(*with_map(*info.body_labels, block_local_map(primal, system.comm())),
                                  partial + "/body_labels.mm");
            manifest << " body_labels.mm";
          }
        manifest << "\n";
        if (comm.getRank() == 0)
          {
            std::ofstream out(partial + "/dual_to_primal.mm");
            out << "%%MatrixMarket matrix array integer general\n"
                << "% column 1: multiplier node (0-based in block 1), column 2: its primal node\n"
                << n_dual << " 2\n";
            for (GO j = 0; j < n_dual; ++j)
              out << j << "\n";
            for (GO j = 0; j < n_dual; ++j)
              out << global[j] << "\n";
          }
      }
    on_root(comm, [&] {
      {
        std::ofstream out(partial + "/manifest.txt");
        out << manifest.str();
        if (!out)
          throw InputError(partial + "/manifest.txt: write failed");
      }
      std::error_code ec;
      fs::remove_all(dir, ec);
      fs::rename(partial, dir, ec);
      if (ec)
        throw InputError(dir + ": cannot move the written system into place (" + ec.message() + ")");
    });
    comm.barrier();
  }
} // namespace multigrid
