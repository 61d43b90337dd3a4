// Reading and writing a BlockSystem.
//
// Two on-disk conventions are understood:
//  1. The project's own: a directory with `manifest.txt` (written by write_block_system) naming the
//     blocks, their sizes and DOFs per node, and which Matrix Market file holds what:
//        format   block-system-1
//        matrix   matrix.mm                    (the whole operator, 1-based coordinate format)
//        rhs      rhs.mm                       (array format)
//        block    <name> <size> <dofs per node> [nullspace file|-] [coordinates file|-]
//        interface <dual-to-primal file> [segregation DOF file|-] [body labels file]
//        partition <file> <ranks>               (optional: the writer's rank of every row)
//     The dual-to-primal file is a Matrix Market integer array with two columns: for every
//     multiplier node (0-based within block 1) the primal node it belongs to (0-based within block 0).
//     The body labels file (a one-column array in block 0's DOF order) gives every primal DOF its
//     body (InterfaceInfo::body_labels, any number of bodies).
//     Every vector file is in global id order: rhs.mm in the row order of matrix.mm, a nullspace
//     in the DOF order of its block, coordinates (one column per direction) in its node order.
//  2. The single-matrix convention of other codes' exports (tests/data/peer): PREFIX_matrix.mm
//     holding primal then dual DOFs (or PREFIX_block_matrix.mm, with PREFIX_matrix.mm then being
//     the primal block alone), PREFIX_rhs.mm (optional), PREFIX_nullspace[1].mm (its row count is the
//     primal size) and PREFIX_interface_dof_map_MPI1.mm (a Tpetra map file of the slave DOFs; the
//     k-th multiplier node belongs to the k-th slave node).
//
// Distribution on read: with a partition line (write_block_system writes one) on the writer's
// number of ranks the writer's distribution, on another number the nodes in the order (writer's
// rank, id) cut into equal chunks; without one, every block's nodes in contiguous equal chunks of
// their ids. Every multiplier node of an interface lives on the rank that owns its primal node
// (what InterfaceAggregationFactory requires).
#pragma once

#include "block_system.h"

#include <functional>
#include <string>
#include <vector>

namespace multigrid
{
  struct ReadOptions
  {
    int dofs_per_node = 2; ///< single-matrix convention only (manifests store it)
  };

  /// PATH: a manifest directory, or the prefix of a single-matrix system. Throws InputError.
  BlockSystem read_block_system(const std::string& path, RCP<const Comm> comm,
                                const ReadOptions& options = {});

  /// Writes the manifest convention into DIR (replacing it atomically: written to DIR.partial,
  /// then renamed, so an interrupted run never leaves a half-written system behind).
  void write_block_system(const BlockSystem& system, const std::string& dir);

  /// Writes V (a Matrix Market array, one column per vector) with row i holding global id i,
  /// whatever the distribution; V's map must number 0..n-1. Gathers V on rank 0.
  void write_in_global_order(const MultiVector& v, const std::string& file);

  /// Global ids stored in a Tpetra map file (Matrix Market integer array of (GID, PID) pairs).
  std::vector<GO> read_map_gids(const std::string& file);

  /// Runs `f` on rank 0 of `comm`; an InputError there is thrown on every rank with the same
  /// message (collective).
  void on_root(const Comm& comm, const std::function<void()>& f);

  /// Header of a Matrix Market file: rows, columns, entries (coordinate) or rows x cols (array).
  struct MatrixMarketHeader
  {
    bool        coordinate = false;
    std::string field; ///< real, integer, ...
    long long   rows = 0, cols = 0, entries = 0;
  };
  /// Reads the header and (with `check_entries`) every entry line: index ranges, count, finite
  /// values. Throws InputError naming the file, the line and what was expected.
  MatrixMarketHeader scan_matrix_market(const std::string& file, bool check_entries = true);

  /// A square coordinate matrix (checked like scan_matrix_market, duplicates summed) distributed
  /// by `row_map`, which also is its domain and range map; rank 0 reads the file. The result is
  /// Tpetra's reader's to the last bit (test BlockSystemIo.ReaderIsTpetras).
  RCP<Matrix> read_sparse_matrix_market(const std::string& file, const RCP<const Map>& row_map);
} // namespace multigrid
