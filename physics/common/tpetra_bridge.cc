#include "tpetra_bridge.h"

#include <Teuchos_DefaultMpiComm.hpp>
#include <Xpetra_MapFactory.hpp>
#include <Xpetra_MatrixFactory.hpp>
#include <Xpetra_MultiVectorFactory.hpp>

#include <Epetra_CrsMatrix.h>

#include <algorithm>
#include <vector>

namespace physics
{
  using namespace multigrid;

  RCP<const Comm> teuchos_comm(MPI_Comm comm)
  {
    return Teuchos::rcp(new Teuchos::MpiComm<int>(comm));
  }

  RCP<const Map> to_xpetra_map(const dealii::IndexSet& locally_owned, MPI_Comm comm)
  {
    std::vector<GO> gids;
    gids.reserve(locally_owned.n_elements());
    for (const auto i : locally_owned)
      gids.push_back(static_cast<GO>(i));
    return Xpetra::MapFactory<LO, GO, NO>::Build(Xpetra::UseTpetra, locally_owned.size(),
                                                 Teuchos::ArrayView<const GO>(gids), 0, teuchos_comm(comm));
  }

  RCP<Matrix> to_xpetra(const dealii::TrilinosWrappers::SparseMatrix& A)
  {
    const Epetra_CrsMatrix& E       = A.trilinos_matrix();
    const MPI_Comm          comm    = A.get_mpi_communicator();
    const auto              row_map = to_xpetra_map(A.locally_owned_range_indices(), comm);
    const auto              domain  = to_xpetra_map(A.locally_owned_domain_indices(), comm);

    // Each row allocated to its own length (as in build_matrix below), not rows x the longest.
    Teuchos::ArrayRCP<std::size_t> lengths(E.NumMyRows());
    for (int local_row = 0; local_row < E.NumMyRows(); ++local_row)
      lengths[local_row] = std::max(E.NumMyEntries(local_row), 1);
    RCP<Matrix>         B = Xpetra::MatrixFactory<SC, LO, GO, NO>::Build(row_map, lengths.getConst());
    std::vector<double> values(E.MaxNumEntries());
    std::vector<int>    columns(E.MaxNumEntries());
    std::vector<GO>     wide(E.MaxNumEntries());
    for (int local_row = 0; local_row < E.NumMyRows(); ++local_row)
      {
        int n = 0;
        E.ExtractMyRowCopy(local_row, static_cast<int>(values.size()), n, values.data(), columns.data());
        for (int k = 0; k < n; ++k)
          wide[k] = static_cast<GO>(E.ColMap().GID(columns[k]));
        B->insertGlobalValues(static_cast<GO>(E.RowMap().GID(local_row)),
                              Teuchos::ArrayView<const GO>(wide.data(), n),
                              Teuchos::ArrayView<const SC>(values.data(), n));
      }
    B->fillComplete(domain, row_map);
    return B;
  }

  namespace
  {
    /// The fill-complete matrix of this rank's rows: `rows` in the order of `gids`, each row's
    /// (column, value) pairs given by entries_of(row). Every row is allocated to its exact length:
    /// one common maximum would reserve rows x longest entries, and the longest row (a structure
    /// row that collects fluid interface columns, a contact row) is several times the average.
    template <typename Rows, typename EntriesOf>
    RCP<Matrix> build_matrix(MPI_Comm comm, GO n_total, const std::vector<GO>& gids, const Rows& rows,
                             const EntriesOf& entries_of)
    {
      auto row_map = Xpetra::MapFactory<LO, GO, NO>::Build(
          Xpetra::UseTpetra, n_total, Teuchos::ArrayView<const GO>(gids), 0, teuchos_comm(comm));
      Teuchos::ArrayRCP<std::size_t> lengths(gids.size());
      std::size_t                    i = 0;
      for (const auto& row : rows)
        lengths[i++] = std::max<std::size_t>(entries_of(row).size(), 1);
      RCP<Matrix>     A = Xpetra::MatrixFactory<SC, LO, GO, NO>::Build(row_map, lengths.getConst());
      std::vector<GO> columns;
      std::vector<SC> values;
      i = 0;
      for (const auto& row : rows)
        {
          columns.clear();
          values.clear();
          for (const auto& [c, v] : entries_of(row))
            {
              columns.push_back(static_cast<GO>(c));
              values.push_back(v);
            }
          A->insertGlobalValues(gids[i++], columns, values);
        }
      A->fillComplete();
      return A;
    }
  } // namespace

  RCP<Matrix> matrix_from_rows(MPI_Comm comm, GO n_total, const std::vector<GO>& gids,
                               const std::vector<FlatRow>& rows)
  {
    return build_matrix(
        comm, n_total, gids, rows, [](const FlatRow& row) -> const auto& { return row; });
  }

  RCP<Matrix> matrix_from_rows(MPI_Comm comm, GO n_total,
                               const std::map<dealii::types::global_dof_index,
                                              std::map<dealii::types::global_dof_index, double>>& rows)
  {
    std::vector<GO> gids;
    gids.reserve(rows.size());
    for (const auto& row : rows)
      gids.push_back(static_cast<GO>(row.first));
    return build_matrix(
        comm, n_total, gids, rows, [](const auto& row) -> const auto& { return row.second; });
  }

  RCP<MultiVector> to_xpetra(const dealii::TrilinosWrappers::MPI::Vector& v, const RCP<const Map>& map)
  {
    auto x    = Xpetra::MultiVectorFactory<SC, LO, GO, NO>::Build(map, 1);
    auto data = x->getDataNonConst(0);
    for (std::size_t i = 0; i < map->getNodeNumElements(); ++i)
      data[i] = v[static_cast<dealii::types::global_dof_index>(map->getGlobalElement(i))];
    return x;
  }

  void copy_to_dealii(const MultiVector& x, dealii::TrilinosWrappers::MPI::Vector& v)
  {
    const auto data = x.getData(0);
    const auto map  = x.getMap();
    for (std::size_t i = 0; i < map->getNodeNumElements(); ++i)
      v[static_cast<dealii::types::global_dof_index>(map->getGlobalElement(i))] = data[i];
    v.compress(dealii::VectorOperation::insert);
  }
} // namespace physics
