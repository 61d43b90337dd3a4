#include "block_system.h"

#include <MueLu_Utilities.hpp>
#include <Tpetra_CrsMatrix.hpp>

#include <Xpetra_BlockedCrsMatrix.hpp>
#include <Xpetra_CrsMatrixWrap.hpp>
#include <Xpetra_ImportFactory.hpp>
#include <Xpetra_MapExtractorFactory.hpp>
#include <Xpetra_MapFactory.hpp>
#include <Xpetra_MapUtils.hpp>
#include <Xpetra_MatrixFactory.hpp>
#include <Xpetra_MatrixUtils.hpp>
#include <Xpetra_MultiVectorFactory.hpp>
#include <Xpetra_StridedMap.hpp>

#include <Teuchos_CommHelpers.hpp>

#include <algorithm>
#include <cmath>
#include <sstream>

namespace multigrid
{
  namespace
  {
    /// True on every rank iff the local element lists of both maps coincide on every rank.
    bool same_distribution(const Map& a, const Map& b)
    {
      int local_same = 1;
      if (a.getNodeNumElements() != b.getNodeNumElements())
        local_same = 0;
      else
        {
          const auto ea = a.getNodeElementList(), eb = b.getNodeElementList();
          for (decltype(ea.size()) i = 0; i < ea.size() && local_same; ++i)
            local_same = (ea[i] == eb[i]);
        }
      int global_same = 0;
      Teuchos::reduceAll(*a.getComm(), Teuchos::REDUCE_MIN, local_same, Teuchos::outArg(global_same));
      return global_same == 1;
    }

    /// Block (r, c) of the merged matrix for every pair of blocks, as MueLu's blocked matrix.
    /// Xpetra's MatrixUtils::SplitMatrix does the same by inserting every row's entries by global
    /// id into n x n matrices that each reserve (and zero) the merged matrix's longest row for
    /// every row, and then lets fillComplete find every block's column owners again: on the FSI
    /// tube that split was 18 % of each Newton assembly. Here the entries of each block are
    /// counted, then copied once into exactly sized compressed-row arrays in the block's own
    /// column ids. The blocks own contiguous id ranges [offsets[k], offsets[k + 1]); a block's
    /// column map is the merged column map's ids it uses, in the merged map's order, which is
    /// the order Tpetra's fillComplete gives (the domain map's own ids first, then the others by
    /// owning rank and id), so the blocks are Xpetra's to the last bit (test
    /// BlockSystem.SplitGivesXpetrasBlocks).
    RCP<BlockedCrsMatrix> split_blocks(const Matrix& merged, const RCP<const MapExtractor>& extractor,
                                       const std::vector<GO>& offsets)
    {
      using TpetraCrs                 = Tpetra::CrsMatrix<SC, LO, GO, NO>;
      using TpetraMap                 = Tpetra::Map<LO, GO, NO>;
      const TpetraCrs&         A      = Xpetra::Helpers<SC, LO, GO, NO>::Op2TpetraCrs(merged);
      const auto               local  = A.getLocalMatrixHost();
      const auto&              rows   = *A.getRowMap();
      const auto&              cols   = *A.getColMap();
      const std::size_t        n      = offsets.size() - 1;
      const auto               n_cols = static_cast<LO>(cols.getNodeNumElements());
      std::vector<std::size_t> column_block(n_cols);
      for (LO j = 0; j < n_cols; ++j)
        column_block[j] =
            std::upper_bound(offsets.begin(), offsets.end(), cols.getGlobalElement(j)) - offsets.begin() - 1;

      RCP<const MapExtractor> range  = extractor,
                              domain = extractor; // Xpetra takes them by non-const reference
      auto              blocked      = Teuchos::rcp(new BlockedCrsMatrix(range, domain, 10));
      std::vector<LO>   block_column(n_cols);
      std::vector<char> used(n_cols);
      for (std::size_t r = 0; r < n; ++r)
        {
          const RCP<const TpetraMap> row_map = Xpetra::toTpetra(extractor->getMap(r));
          const auto                 m       = static_cast<LO>(row_map->getNodeNumElements());
          std::vector<LO>            merged_row(m); // the merged matrix's local row of each block row
          for (LO i = 0; i < m; ++i)
            merged_row[i] = rows.getLocalElement(row_map->getGlobalElement(i));
          for (std::size_t c = 0; c < n; ++c)
            {
              // the columns block (r, c) uses, numbered in the merged column map's order
              std::fill(used.begin(), used.end(), 0);
              typename TpetraCrs::local_graph_device_type::row_map_type::non_const_type offsets_rc(
                  "row offsets", m + 1);
              for (LO i = 0; i < m; ++i)
                {
                  std::size_t count = 0;
                  for (auto k = local.graph.row_map(merged_row[i]);
                       k < local.graph.row_map(merged_row[i] + 1); ++k)
                    if (column_block[local.graph.entries(k)] == c)
                      {
                        used[local.graph.entries(k)] = 1;
                        ++count;
                      }
                  offsets_rc(i + 1) = offsets_rc(i) + count;
                }
              std::vector<GO> column_ids;
              for (LO j = 0; j < n_cols; ++j)
                if (used[j])
                  {
                    block_column[j] = static_cast<LO>(column_ids.size());
                    column_ids.push_back(cols.getGlobalElement(j));
                  }
              // On one rank a block that uses every column of its domain map takes that map as its
              // column map, as Tpetra's fillComplete does (MueLu's products then find the two maps
              // identical by address; a copy made the emin set-up 10-18 % slower).
              const RCP<const TpetraMap> domain_map = Xpetra::toTpetra(extractor->getMap(c));
              const RCP<const TpetraMap> col_map =
                  cols.getComm()->getSize() == 1 && column_ids.size() == domain_map->getNodeNumElements()
                      ? domain_map
                      : Teuchos::rcp<const TpetraMap>(
                            new TpetraMap(Teuchos::OrdinalTraits<Tpetra::global_size_t>::invalid(),
                                          Teuchos::ArrayView<const GO>(column_ids), 0, cols.getComm()));
              typename TpetraCrs::local_graph_device_type::entries_type::non_const_type columns(
                  Kokkos::ViewAllocateWithoutInitializing("column indices"), offsets_rc(m));
              typename TpetraCrs::local_matrix_device_type::values_type values(
                  Kokkos::ViewAllocateWithoutInitializing("values"), offsets_rc(m));
              for (LO i = 0; i < m; ++i)
                {
                  std::size_t q = offsets_rc(i);
                  for (auto k = local.graph.row_map(merged_row[i]);
                       k < local.graph.row_map(merged_row[i] + 1); ++k)
                    if (column_block[local.graph.entries(k)] == c)
                      {
                        columns(q) = block_column[local.graph.entries(k)];
                        values(q)  = local.values(k);
                        ++q;
                      }
                }
              auto block = Teuchos::rcp(new TpetraCrs(row_map, col_map, offsets_rc, columns, values));
              block->expertStaticFillComplete(domain_map, row_map);
              blocked->setMatrix(r, c, MueLu::TpetraCrs_To_XpetraMatrix(block));
            }
        }
      return blocked;
    }
  } // namespace

  BlockSystem BlockSystem::from_merged(RCP<const Comm> comm, std::vector<BlockInfo> blocks,
                                       const std::vector<std::vector<GO>>& owned_block_gids,
                                       RCP<Matrix> merged_matrix, RCP<MultiVector> rhs)
  {
    if (blocks.empty() || blocks.size() != owned_block_gids.size())
      throw InputError("BlockSystem: expected one list of owned DOFs per block, got " +
                       std::to_string(owned_block_gids.size()) + " for " + std::to_string(blocks.size()) +
                       " blocks");
    BlockSystem system;
    system.comm_ = comm;

    // Block k owns the global ids [offset_k, offset_k + n_k): strided maps with the block's DOFs
    // per node, so that MueLu's SubBlockAFactory can recover the striding on every block.
    GO                          offset = 0;
    std::vector<GO>             offsets{0};
    std::vector<RCP<const Map>> sub_maps;
    for (std::size_t k = 0; k < blocks.size(); ++k)
      {
        BlockInfo& b = blocks[k];
        if (b.dofs_per_node < 1 || b.global_size % b.dofs_per_node != 0)
          throw InputError("BlockSystem: block '" + b.name + "' has " + std::to_string(b.global_size) +
                           " DOFs, not a multiple of " + std::to_string(b.dofs_per_node) + " DOFs per node");
        b.offset         = offset;
        const auto& gids = owned_block_gids[k];
        if (gids.size() % b.dofs_per_node != 0)
          throw InputError("BlockSystem: block '" + b.name + "': owned DOFs on rank " +
                           std::to_string(comm->getRank()) + " do not form whole nodes");
        for (GO g : gids)
          if (g < offset || g >= offset + b.global_size)
            throw InputError("BlockSystem: block '" + b.name + "': DOF " + std::to_string(g) +
                             " outside its range [" + std::to_string(offset) + ", " +
                             std::to_string(offset + b.global_size) + ")");
        std::vector<std::size_t> striding{static_cast<std::size_t>(b.dofs_per_node)};
        b.map = Teuchos::rcp(new StridedMap(Xpetra::UseTpetra, b.global_size,
                                            Teuchos::ArrayView<const GO>(gids), 0, striding, comm));
        sub_maps.push_back(b.map);
        offset += b.global_size;
        offsets.push_back(offset);
      }
    RCP<const Map> full_map = Xpetra::MapUtils<LO, GO, NO>::concatenateMaps(sub_maps);

    if (merged_matrix->getGlobalNumRows() != static_cast<Xpetra::global_size_t>(offset) ||
        merged_matrix->getGlobalNumCols() != static_cast<Xpetra::global_size_t>(offset))
      throw InputError("BlockSystem: matrix is " + std::to_string(merged_matrix->getGlobalNumRows()) + " x " +
                       std::to_string(merged_matrix->getGlobalNumCols()) + ", but the blocks add up to " +
                       std::to_string(offset));

    // Bring the matrix and the right-hand side into the block distribution if necessary.
    if (!same_distribution(*merged_matrix->getRowMap(), *full_map))
      {
        auto importer = Xpetra::ImportFactory<LO, GO, NO>::Build(merged_matrix->getRowMap(), full_map);
        merged_matrix =
            Xpetra::MatrixFactory<SC, LO, GO, NO>::Build(merged_matrix, *importer, full_map, full_map);
        if (!rhs.is_null())
          {
            auto moved = Xpetra::MultiVectorFactory<SC, LO, GO, NO>::Build(full_map, rhs->getNumVectors());
            moved->doImport(*rhs, *importer, Xpetra::INSERT);
            rhs = moved;
          }
      }
    if (rhs.is_null())
      rhs = Xpetra::MultiVectorFactory<SC, LO, GO, NO>::Build(full_map, 1, true);
    if (rhs->getGlobalLength() != static_cast<Xpetra::global_size_t>(offset))
      throw InputError("BlockSystem: right-hand side has length " + std::to_string(rhs->getGlobalLength()) +
                       ", expected " + std::to_string(offset));

    system.extractor_ = Xpetra::MapExtractorFactory<SC, LO, GO, NO>::Build(full_map, sub_maps, false);
    system.blocked_   = split_blocks(*merged_matrix, system.extractor_, offsets);
    system.merged_    = merged_matrix;
    system.rhs_       = rhs;
    system.blocks_    = std::move(blocks);
    return system;
  }

  GO BlockSystem::global_size() const
  {
    GO n = 0;
    for (const auto& b : blocks_)
      n += b.global_size;
    return n;
  }

  RCP<const Map> BlockSystem::full_map() const
  {
    return extractor_->getFullMap();
  }

  const InterfaceInfo& BlockSystem::interface() const
  {
    if (!interface_)
      throw InputError("BlockSystem: no interface data (primal interface DOF map, dual-to-primal "
                       "node mapping) attached, but the preset needs it");
    return *interface_;
  }

  void BlockSystem::set_interface(InterfaceInfo info)
  {
    interface_ = std::move(info);
  }

  RCP<MultiVector> BlockSystem::nullspace_or_translations(std::size_t k) const
  {
    const BlockInfo& b = block(k);
    if (!b.nullspace.is_null())
      return b.nullspace;
    return translation_modes(b.map, b.dofs_per_node);
  }

  void BlockSystem::validate(const std::string& source) const
  {
    const std::string where = source.empty() ? std::string("system") : source;
    // Finite entries, on every rank.
    int bad_local = 0;
    GO  bad_row   = -1;
    for (std::size_t i = 0; i < merged_->getNodeNumRows() && !bad_local; ++i)
      {
        Teuchos::ArrayView<const LO> cols;
        Teuchos::ArrayView<const SC> vals;
        merged_->getLocalRowView(i, cols, vals);
        for (const SC v : vals)
          if (!std::isfinite(v))
            {
              bad_local = 1;
              bad_row   = merged_->getRowMap()->getGlobalElement(i);
              break;
            }
      }
    GO bad_row_global = -1;
    Teuchos::reduceAll(*comm_, Teuchos::REDUCE_MAX, bad_row, Teuchos::outArg(bad_row_global));
    if (bad_row_global >= 0)
      throw InputError(where + ": matrix has a NaN or infinite entry in row " +
                       std::to_string(bad_row_global + 1) + " (1-based); expected finite values");
    {
      const auto data = rhs_->getData(0);
      int        bad  = 0;
      for (const SC v : data)
        bad |= !std::isfinite(v);
      int bad_global = 0;
      Teuchos::reduceAll(*comm_, Teuchos::REDUCE_MAX, bad, Teuchos::outArg(bad_global));
      if (bad_global)
        throw InputError(where + ": right-hand side has a NaN or infinite entry; expected finite values");
    }
    for (const auto& b : blocks_)
      {
        if (!b.nullspace.is_null() && b.nullspace->getLocalLength() != b.map->getNodeNumElements())
          throw InputError(where + ": nullspace of block '" + b.name + "' has length " +
                           std::to_string(b.nullspace->getGlobalLength()) + ", expected " +
                           std::to_string(b.global_size));
      }
    if (interface_)
      {
        if (blocks_.size() != 2)
          throw InputError(where + ": interface data needs exactly 2 blocks (primal, dual), got " +
                           std::to_string(blocks_.size()));
        const auto& dual           = blocks_[1];
        const auto& primal         = blocks_[0];
        const LO    n_dual_nodes   = dual.map->getNodeNumElements() / dual.dofs_per_node;
        const LO    n_primal_nodes = primal.map->getNodeNumElements() / primal.dofs_per_node;
        if (static_cast<LO>(interface_->dual_to_primal_node.size()) != n_dual_nodes)
          throw InputError(where + ": dual-to-primal node mapping has " +
                           std::to_string(interface_->dual_to_primal_node.size()) + " entries on rank " +
                           std::to_string(comm_->getRank()) + ", expected " + std::to_string(n_dual_nodes) +
                           " (one per local multiplier node)");
        for (const auto& [d, p] : interface_->dual_to_primal_node)
          if (d < 0 || d >= n_dual_nodes || p < 0 || p >= n_primal_nodes)
            throw InputError(where + ": dual-to-primal node mapping entry " + std::to_string(d) + " -> " +
                             std::to_string(p) + " is out of range on rank " +
                             std::to_string(comm_->getRank()));
        if (!interface_->body_labels.is_null() &&
            interface_->body_labels->getLocalLength() != primal.map->getNodeNumElements())
          throw InputError(where + ": body labels have " +
                           std::to_string(interface_->body_labels->getLocalLength()) + " entries on rank " +
                           std::to_string(comm_->getRank()) + ", expected one per local primal DOF (" +
                           std::to_string(primal.map->getNodeNumElements()) + ")");
      }
  }

  RCP<MultiVector> BlockSystem::segregation_labels() const
  {
    const auto& info = interface();
    if (!info.body_labels.is_null())
      return info.body_labels;
    auto labels = Xpetra::MultiVectorFactory<SC, LO, GO, NO>::Build(blocks_.at(0).map, 1, true);
    if (!info.segregation_dofs.is_null())
      {
        auto       data = labels->getDataNonConst(0);
        const auto& map = *blocks_.at(0).map;
        for (std::size_t i = 0; i < map.getNodeNumElements(); ++i)
          data[i] = info.segregation_dofs->isNodeGlobalElement(map.getGlobalElement(i)) ? 1.0 : 0.0;
      }
    return labels;
  }

  std::vector<double> BlockSystem::block_norms(const MultiVector& v) const
  {
    std::vector<double>    norms;
    RCP<const MultiVector> vp = Teuchos::rcpFromRef(v);
    for (std::size_t k = 0; k < blocks_.size(); ++k)
      {
        auto                   part = extractor_->ExtractVector(vp, k);
        Teuchos::Array<double> n(1);
        part->norm2(n);
        norms.push_back(n[0]);
      }
    return norms;
  }

  std::vector<double> BlockSystem::block_residual_norms(const MultiVector& x, const MultiVector& b) const
  {
    auto r = Xpetra::MultiVectorFactory<SC, LO, GO, NO>::Build(full_map(), 1);
    merged_->apply(x, *r);
    r->update(1.0, b, -1.0);
    return block_norms(*r);
  }

  void set_node_coordinates(BlockInfo& block, int dim, const std::vector<double>& x)
  {
    const int         dpn   = block.dofs_per_node;
    const auto        dofs  = block.map->getNodeElementList();
    const std::size_t nodes = dofs.size() / dpn;
    if (x.size() != nodes * dim)
      throw InputError("block '" + block.name + "': " + std::to_string(x.size() / std::max(dim, 1)) +
                       " node positions for " + std::to_string(nodes) + " local nodes");
    std::vector<GO> node_gids(nodes);
    for (std::size_t i = 0; i < nodes; ++i)
      node_gids[i] = (dofs[i * dpn] - block.offset) / dpn;
    auto node_map     = Xpetra::MapFactory<LO, GO, NO>::Build(block.map->lib(), block.global_size / dpn,
                                                              Teuchos::ArrayView<const GO>(node_gids), 0,
                                                              block.map->getComm());
    block.coordinates = Xpetra::MultiVectorFactory<SC, LO, GO, NO>::Build(node_map, dim);
    for (int d = 0; d < dim; ++d)
      {
        auto data = block.coordinates->getDataNonConst(d);
        for (std::size_t i = 0; i < nodes; ++i)
          data[i] = x[i * dim + d];
      }
  }

  RCP<MultiVector> translation_modes(const RCP<const Map>& dof_map, int dofs_per_node)
  {
    auto modes = Xpetra::MultiVectorFactory<SC, LO, GO, NO>::Build(dof_map, dofs_per_node, true);
    for (int d = 0; d < dofs_per_node; ++d)
      {
        auto data = modes->getDataNonConst(d);
        for (std::size_t i = d; i < dof_map->getNodeNumElements(); i += dofs_per_node)
          data[i] = 1.0;
      }
    return modes;
  }

  RCP<MultiVector> rigid_body_modes(const RCP<const Map>& dof_map, int dim, const std::vector<double>& x)
  {
    const std::size_t n_nodes = dof_map->getNodeNumElements() / dim;
    if (x.size() != n_nodes * dim)
      throw InputError("rigid_body_modes: " + std::to_string(x.size() / std::max(dim, 1)) +
                       " coordinates for " + std::to_string(n_nodes) + " local nodes");
    const int n_modes = (dim == 2) ? 3 : 6;
    auto      modes   = Xpetra::MultiVectorFactory<SC, LO, GO, NO>::Build(dof_map, n_modes, true);
    std::vector<Teuchos::ArrayRCP<SC>> m;
    for (int j = 0; j < n_modes; ++j)
      m.push_back(modes->getDataNonConst(j));
    for (std::size_t i = 0; i < n_nodes; ++i)
      {
        const double* p = &x[i * dim];
        for (int d = 0; d < dim; ++d)
          m[d][i * dim + d] = 1.0;
        if (dim == 2)
          { // infinitesimal rotation about the z axis: (-y, x)
            m[2][i * 2 + 0] = -p[1];
            m[2][i * 2 + 1] = p[0];
          }
        else
          { // rotations about x, y, z: omega x p
            m[3][i * 3 + 1] = -p[2];
            m[3][i * 3 + 2] = p[1];
            m[4][i * 3 + 0] = p[2];
            m[4][i * 3 + 2] = -p[0];
            m[5][i * 3 + 0] = -p[1];
            m[5][i * 3 + 1] = p[0];
          }
      }
    return modes;
  }

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
} // namespace multigrid
