#include "block_system_io.h"

#include "temporary_files.h"

#include <Xpetra_IO.hpp>
#include <Xpetra_MapFactory.hpp>
#include <Xpetra_StridedMap.hpp>
#include <Xpetra_MultiVector.hpp>

#include <Teuchos_CommHelpers.hpp>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <functional>
#include <sstream>

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
        std::string nullspace; ///< file or empty
      };
      std::string        source; ///< for messages
      std::string        matrix, rhs;
      std::vector<Block> blocks;
      bool               has_interface = false;
      std::vector<GO>    dual_to_primal;   ///< primal node of every dual node (global)
      std::vector<GO>    segregation_gids; ///< DOFs of the slave body (global), may be empty
    };

    void require_file(const std::string& file, const std::string& what)
    {
      if (!fs::is_regular_file(file))
        throw InputError(file + ": " + what + " file not found");
    }

    /// Runs `f` on rank 0; an InputError there is rethrown on every rank with the same message.
    template <typename F>
    void on_root(const Comm& comm, F&& f)
    {
      std::string message;
      if (comm.getRank() == 0)
        {
          try
            {
              f();
            }
          catch (const InputError& e)
            {
              message = e.what();
            }
        }
      int length = static_cast<int>(message.size());
      Teuchos::broadcast(comm, 0, Teuchos::outArg(length));
      message.resize(length);
      if (length > 0)
        {
          Teuchos::broadcast(comm, 0, length, message.data());
          throw InputError(message);
        }
    }

    std::vector<GO> read_integer_array(const std::string& file, long long& rows, long long& cols)
    {
      const auto header = scan_matrix_market(file);
      if (header.coordinate || header.field != "integer")
        throw InputError(file + ": expected a Matrix Market 'array integer' file");
      rows = header.rows;
      cols = header.cols;
      std::ifstream   in(file);
      std::string     line;
      bool            seen_size = false;
      std::vector<GO> values;
      while (std::getline(in, line))
        {
          if (line.empty() || line[0] == '%')
            continue;
          if (!seen_size)
            {
              seen_size = true;
              continue;
            }
          values.push_back(std::strtoll(line.c_str(), nullptr, 10));
        }
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
      std::string   dual_to_primal_file, segregation_file;
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
              std::string        nsp;
              if (!(s >> b.name >> b.size >> b.dofs_per_node))
                bad("expected 'block <name> <size> <dofs per node> [nullspace]'");
              if (b.size <= 0 || b.dofs_per_node <= 0)
                bad("block '" + b.name + "': size and DOFs per node must be positive");
              if (s >> nsp && nsp != "-")
                b.nullspace = (fs::path(dir) / nsp).string();
              d.blocks.push_back(b);
            }
          else if (key == "interface")
            {
              if (!(s >> dual_to_primal_file))
                bad("expected 'interface <dual-to-primal file> [segregation file]'");
              s >> segregation_file;
              d.has_interface = true;
            }
          else
            bad("unknown key '" + key + "' (expected format, matrix, rhs, block, interface)");
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
      d.blocks.push_back({"displacement", n_primal, dpn, nullspace});
      d.blocks.push_back({"lagrange multiplier", n_dual, dpn, ""});

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

    /// The same local values on another map with the same local length.
    RCP<MultiVector> with_map(const MultiVector& v, const RCP<const Map>& map)
    {
      auto copy = Xpetra::MultiVectorFactory<SC, LO, GO, NO>::Build(map, v.getNumVectors());
      for (std::size_t j = 0; j < v.getNumVectors(); ++j)
        {
          const auto src = v.getData(j);
          auto       dst = copy->getDataNonConst(j);
          std::copy(src.begin(), src.end(), dst.begin());
        }
      return copy;
    }

    /// Contiguous chunk of `n` items owned by `rank` out of `size`.
    std::pair<GO, GO> chunk(GO n, int rank, int size)
    {
      return {n * rank / size, n * (rank + 1) / size};
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
        const auto h = scan_matrix_market(d.matrix);
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
          if (!b.nullspace.empty())
            {
              const auto n = scan_matrix_market(b.nullspace);
              if (n.coordinate || n.rows != b.size)
                throw InputError(b.nullspace + ": nullspace has " + std::to_string(n.rows) +
                                 " rows, expected " + std::to_string(b.size) + " (block '" + b.name + "')");
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

      // Owned DOFs: primal nodes in contiguous chunks; multiplier nodes follow their primal node.
      const int                    rank = comm->getRank(), size = comm->getSize();
      std::vector<BlockInfo>       blocks;
      std::vector<std::vector<GO>> owned(d.blocks.size());
      std::vector<GO>              first_node(d.blocks.size(), 0);
      GO                           offset = 0;
      const auto primal_nodes             = chunk(d.blocks[0].size / d.blocks[0].dofs_per_node, rank, size);
      for (std::size_t k = 0; k < d.blocks.size(); ++k)
        {
          const auto& b = d.blocks[k];
          const GO    n = b.size / b.dofs_per_node;
          if (k == 1 && d.has_interface)
            {
              for (GO j = 0; j < n; ++j)
                {
                  const GO p = d.dual_to_primal[j];
                  if (p >= primal_nodes.first && p < primal_nodes.second)
                    for (int c = 0; c < b.dofs_per_node; ++c)
                      owned[k].push_back(offset + j * b.dofs_per_node + c);
                }
            }
          else
            {
              const auto [lo, hi] = chunk(n, rank, size);
              first_node[k]       = lo;
              for (GO i = lo * b.dofs_per_node; i < hi * b.dofs_per_node; ++i)
                owned[k].push_back(offset + i);
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

      using IO                = Xpetra::IO<SC, LO, GO, NO>;
      RCP<Matrix>      A      = IO::Read(d.matrix, row_map);
      RCP<MultiVector> rhs    = d.rhs.empty() ? Teuchos::null : IO::ReadMultiVector(d.rhs, row_map);
      BlockSystem      system = BlockSystem::from_merged(comm, blocks, owned, A, rhs);

      for (std::size_t k = 0; k < d.blocks.size(); ++k)
        if (!d.blocks[k].nullspace.empty())
          {
            // Nullspace files are numbered within their block.
            const auto nsp =
                IO::ReadMultiVector(d.blocks[k].nullspace, block_local_map(system.block(k), comm));
            system.block(k).nullspace = with_map(*nsp, system.block(k).map);
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
                  static_cast<LO>(primal_node - primal_nodes.first);
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
          system.set_interface(std::move(info));
        }
      system.validate(d.source);
      return system;
    }
  } // namespace

  MatrixMarketHeader scan_matrix_market(const std::string& file, bool check_entries)
  {
    std::ifstream in(file);
    if (!in)
      throw InputError(file + ": cannot open Matrix Market file");
    MatrixMarketHeader h;
    std::string        line;
    long long          line_no = 0;
    if (!std::getline(in, line) || line.rfind("%%MatrixMarket", 0) != 0)
      throw InputError(file + ":1: missing '%%MatrixMarket' banner");
    ++line_no;
    {
      std::istringstream s(line);
      std::string        banner, object, format, symmetry;
      s >> banner >> object >> format >> h.field >> symmetry;
      if (object != "matrix" || (format != "coordinate" && format != "array"))
        throw InputError(file + ":1: expected 'matrix coordinate' or 'matrix array'");
      h.coordinate = (format == "coordinate");
      if (symmetry != "general")
        throw InputError(file + ":1: symmetry '" + symmetry + "', only 'general' is supported");
    }
    bool      have_size = false;
    long long count     = 0;
    while (std::getline(in, line))
      {
        ++line_no;
        if (line.empty() || line[0] == '%')
          continue;
        std::istringstream s(line);
        const std::string  where = file + ":" + std::to_string(line_no) + ": ";
        if (!have_size)
          {
            if (!(s >> h.rows >> h.cols) || (h.coordinate && !(s >> h.entries)))
              throw InputError(where + "expected the size line");
            if (!h.coordinate)
              h.entries = h.rows * h.cols;
            have_size = true;
            if (!check_entries)
              return h;
            continue;
          }
        ++count;
        if (count > h.entries)
          throw InputError(where + "more entries than the " + std::to_string(h.entries) + " announced");
        std::string value;
        if (h.coordinate)
          {
            long long i = 0, j = 0;
            if (!(s >> i >> j >> value))
              throw InputError(where + "expected 'row column value'");
            if (i < 1 || i > h.rows || j < 1 || j > h.cols)
              throw InputError(where + "index (" + std::to_string(i) + ", " + std::to_string(j) +
                               ") outside the " + std::to_string(h.rows) + " x " + std::to_string(h.cols) +
                               " matrix");
          }
        else if (!(s >> value))
          throw InputError(where + "expected a value");
        char*        end = nullptr;
        const double v   = std::strtod(value.c_str(), &end);
        if (end == value.c_str() || *end != '\0' || !std::isfinite(v))
          throw InputError(where + "value '" + value + "' is not a finite number");
      }
    if (!have_size)
      throw InputError(file + ": no size line");
    if (count != h.entries)
      throw InputError(file + ": " + std::to_string(count) + " entries, the header announces " +
                       std::to_string(h.entries));
    return h;
  }

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
    IO::Write(partial + "/matrix.mm", *system.merged_matrix());
    IO::Write(partial + "/rhs.mm", *system.rhs());
    for (std::size_t k = 0; k < system.n_blocks(); ++k)
      {
        const auto& b        = system.block(k);
        std::string nsp_name = "-";
        if (!b.nullspace.is_null())
          {
            const auto copy = with_map(*b.nullspace, block_local_map(b, system.comm()));
            nsp_name        = "nullspace_" + std::to_string(k) + ".mm";
            IO::Write(partial + "/" + nsp_name, *copy);
          }
        std::string name = b.name;
        std::replace(name.begin(), name.end(), ' ', '_');
        manifest << "block " << name << " " << b.global_size << " " << b.dofs_per_node << " " << nsp_name
                 << "\n";
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
        manifest << "interface dual_to_primal.mm " << segregation << "\n";
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
