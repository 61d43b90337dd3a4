// The bridge from deal.II assembly to the block-AMG module's Tpetra objects.
//
// deal.II 9.4 (Debian) wraps Epetra only, and MueLu here is Tpetra-only (PLATFORM.md). Assembly
// therefore goes through deal.II's distributed TrilinosWrappers matrices, where
// AffineConstraints::distribute_local_to_global, ghosted assembly and compress() work as in the
// tutorials, and the finished rows are copied into an Xpetra/Tpetra matrix with the same row
// distribution (global ids widened from int to long long). The copy costs one extra matrix in
// memory during the hand-over; it keeps every deal.II idiom intact.
#pragma once

#include "types.h"

#include <deal.II/lac/trilinos_index_access.h>
#include <deal.II/lac/trilinos_sparse_matrix.h>
#include <deal.II/lac/trilinos_vector.h>

#include <mpi.h>

#include <map>
#include <utility>
#include <vector>

namespace physics
{
  /// Teuchos communicator over the same MPI communicator deal.II uses.
  multigrid::RCP<const multigrid::Comm> teuchos_comm(MPI_Comm comm);

  /// Row map of a deal.II-distributed object: this rank's locally owned global ids.
  multigrid::RCP<const multigrid::Map> to_xpetra_map(const dealii::IndexSet& locally_owned, MPI_Comm comm);

  /// Copy of a compressed (assembled) TrilinosWrappers matrix; rows distributed as in deal.II.
  multigrid::RCP<multigrid::Matrix> to_xpetra(const dealii::TrilinosWrappers::SparseMatrix& A);

  /// Copy of a TrilinosWrappers vector (non-ghosted) as a one-column multivector on `map`.
  multigrid::RCP<multigrid::MultiVector> to_xpetra(const dealii::TrilinosWrappers::MPI::Vector& v,
                                                   const multigrid::RCP<const multigrid::Map>&  map);

  /// Adds the locally owned row `row` of a deal.II matrix to `entries`, columns renamed by
  /// `column_gid` (from deal.II's numbering to the one of the merged system).
  template <typename ColumnMap>
  void add_row(const dealii::TrilinosWrappers::SparseMatrix& A, dealii::types::global_dof_index row,
               const ColumnMap& column_gid, std::map<multigrid::GO, double>& entries)
  {
    // A view of the Epetra row: deal.II's row iterators copy the row on construction, and an
    // end(row) in the loop condition makes that quadratic in the row length.
    const Epetra_CrsMatrix& m     = A.trilinos_matrix();
    const int               local = m.LRID(static_cast<dealii::TrilinosWrappers::types::int_type>(row));
    int                     n     = 0;
    double*                 values  = nullptr;
    int*                    columns = nullptr;
    m.ExtractMyRowView(local, n, values, columns);
    for (int k = 0; k < n; ++k)
      entries[column_gid(static_cast<dealii::types::global_dof_index>(
          dealii::TrilinosWrappers::global_column_index(m, columns[k])))] += values[k];
  }

  /// One finished matrix row: (global column, value), columns ascending and distinct. A row is
  /// summed in a std::map and kept in this form (16 bytes per entry against a map node's ~64, and
  /// one allocation per row instead of one per entry).
  using FlatRow = std::vector<std::pair<multigrid::GO, double>>;

  /// The merged matrix of a coupled system from rows in global ids: rows[i] is row gids[i]
  /// (this rank's rows; together a one-to-one distribution of n_total ids). Returns the
  /// fill-complete matrix (row map = range = domain map).
  multigrid::RCP<multigrid::Matrix> matrix_from_rows(MPI_Comm comm, multigrid::GO n_total,
                                                     const std::vector<multigrid::GO>& gids,
                                                     const std::vector<FlatRow>&       rows);

  /// The same from rows keyed by their global ids (this rank's rows, in ascending order), so
  /// that a caller holding its rows in a map need not copy them into a vector first.
  multigrid::RCP<multigrid::Matrix>
  matrix_from_rows(MPI_Comm comm, multigrid::GO n_total,
                   const std::map<dealii::types::global_dof_index,
                                  std::map<dealii::types::global_dof_index, double>>& rows);

  /// Writes the locally owned entries of x (one column, same global ids) into v.
  void copy_to_dealii(const multigrid::MultiVector& x, dealii::TrilinosWrappers::MPI::Vector& v);
} // namespace physics
