#include "schur_complement.h"

#include <MueLu_Utilities.hpp>

#include <Teuchos_FancyOStream.hpp>
#include <Tpetra_CrsMatrix.hpp>
#include <Tpetra_Details_makeColMap.hpp>
#include <Xpetra_MatrixMatrix.hpp>

#include <algorithm>
#include <sstream>
#include <stdexcept>
#include <utility>
#include <vector>

namespace multigrid
{
  namespace
  {
    using TpetraCrs = Tpetra::CrsMatrix<SC, LO, GO, NO>;
    using TpetraMap = Tpetra::Map<LO, GO, NO>;

    /// The column map of a sum of C and P: Tpetra's own construction (the columns owned by this
    /// rank in domain-map order, then the remote ones grouped by owner) over the ids of both
    /// column maps, which are far fewer than the entries.
    Teuchos::RCP<const TpetraMap> union_column_map(const TpetraCrs& C, const TpetraCrs& P)
    {
      const TpetraMap&                             a   = *C.getColMap();
      const TpetraMap&                             b   = *P.getColMap();
      const auto                                   n_a = static_cast<LO>(a.getNodeNumElements());
      const auto                                   n_b = static_cast<LO>(b.getNodeNumElements());
      Kokkos::View<GO*, typename NO::memory_space> ids(Kokkos::ViewAllocateWithoutInitializing("column ids"),
                                                       static_cast<std::size_t>(n_a + n_b));
      for (LO j = 0; j < n_a; ++j)
        ids(j) = a.getGlobalElement(j);
      for (LO j = 0; j < n_b; ++j)
        ids(n_a + j) = b.getGlobalElement(j);
      Teuchos::RCP<const TpetraMap> columns;
      std::ostringstream            errors;
      if (Tpetra::Details::makeColMap<LO, GO, NO>(columns, C.getDomainMap(), ids, &errors) != 0)
        throw std::runtime_error("sum of two matrices: no column map (" + errors.str() + ")");
      return columns;
    }

    /// For each local column of `from`, its local id in `to` (which holds all of them).
    std::vector<LO> translated_columns(const TpetraMap& from, const TpetraMap& to)
    {
      std::vector<LO> local(from.getNodeNumElements());
      for (std::size_t j = 0; j < local.size(); ++j)
        local[j] = to.getLocalElement(from.getGlobalElement(static_cast<LO>(j)));
      return local;
    }

    /// Appends the entries of local row i of M, in the new column numbering, times `factor`.
    void append_row(const TpetraCrs& M, LO i, const std::vector<LO>& new_column, double factor,
                    std::vector<std::pair<LO, SC>>& row)
    {
      typename TpetraCrs::local_inds_host_view_type columns;
      typename TpetraCrs::values_host_view_type     values;
      M.getLocalRowView(i, columns, values);
      for (std::size_t k = 0; k < columns.extent(0); ++k)
        row.emplace_back(new_column[static_cast<std::size_t>(columns(k))], factor * values(k));
    }

    /// Sorts a row by column and sums the entries of equal columns. The row is the entries of
    /// two fill-complete rows, each sorted by its own local ids; the union column map keeps the
    /// order of both column maps (owned ids in domain-map order, then the remote ones grouped by
    /// owner, ascending), so each part stays sorted and one merge sorts the row. A part that is
    /// not sorted (a product left unsorted) is sorted instead.
    void sort_and_merge(std::vector<std::pair<LO, SC>>& row, std::size_t first_part)
    {
      const auto by_column = [](const auto& x, const auto& y) { return x.first < y.first; };
      const auto middle    = row.begin() + static_cast<std::ptrdiff_t>(first_part);
      if (std::is_sorted(row.begin(), middle, by_column) && std::is_sorted(middle, row.end(), by_column))
        std::inplace_merge(row.begin(), middle, row.end(), by_column);
      else
        std::sort(row.begin(), row.end(), by_column);
      std::size_t n = 0;
      for (std::size_t k = 0; k < row.size(); ++k)
        if (n > 0 && row[n - 1].first == row[k].first)
          row[n - 1].second += row[k].second;
        else
          row[n++] = row[k];
      row.resize(n);
    }
  } // namespace

  RCP<Matrix> add_matrices(const Matrix& C_matrix, double beta, const Matrix& P_matrix)
  {
    const TpetraCrs& C = Xpetra::Helpers<SC, LO, GO, NO>::Op2TpetraCrs(C_matrix);
    const TpetraCrs& P = Xpetra::Helpers<SC, LO, GO, NO>::Op2TpetraCrs(P_matrix);
    if (!C.getRowMap()->isSameAs(*P.getRowMap()) || !C.getDomainMap()->isSameAs(*P.getDomainMap()))
      throw std::logic_error("sum of two matrices: their row or domain maps differ");
    const auto columns = union_column_map(C, P);
    const auto from_C  = translated_columns(*C.getColMap(), *columns);
    const auto from_P  = translated_columns(*P.getColMap(), *columns);
    const auto n_rows  = static_cast<LO>(C.getNodeNumRows());

    // Row i of the sum, in the new column ids. Formed twice: the first pass counts, so that the
    // arrays are allocated once and exactly (as S is the largest matrix of the preconditioner).
    std::vector<std::pair<LO, SC>> row;
    const auto                     form_row = [&](LO i) {
      row.clear();
      append_row(C, i, from_C, 1.0, row);
      const std::size_t first_part = row.size();
      append_row(P, i, from_P, beta, row);
      sort_and_merge(row, first_part);
    };
    typename TpetraCrs::local_graph_device_type::row_map_type::non_const_type offsets(
        "row offsets", static_cast<std::size_t>(n_rows) + 1);
    for (LO i = 0; i < n_rows; ++i)
      {
        form_row(i);
        offsets(i + 1) = offsets(i) + row.size();
      }
    const std::size_t                                                         n_entries = offsets(n_rows);
    typename TpetraCrs::local_graph_device_type::entries_type::non_const_type indices(
        Kokkos::ViewAllocateWithoutInitializing("column indices"), n_entries);
    typename TpetraCrs::local_matrix_device_type::values_type values(
        Kokkos::ViewAllocateWithoutInitializing("values"), n_entries);
    for (LO i = 0; i < n_rows; ++i)
      {
        form_row(i);
        std::size_t k = offsets(i);
        for (const auto& [column, value] : row)
          {
            indices(k) = column;
            values(k)  = value;
            ++k;
          }
      }
    auto sum = Teuchos::rcp(new TpetraCrs(C.getRowMap(), columns, offsets, indices, values));
    sum->expertStaticFillComplete(C.getDomainMap(), C.getRangeMap());
    return MueLu::TpetraCrs_To_XpetraMatrix(sum);
  }

  RCP<Matrix> explicit_schur_complement(const RCP<Matrix>& C, const Matrix& B2, const Matrix& A_inverse,
                                        const Matrix& B1t, double scale)
  {
    using MM        = Xpetra::MatrixMatrix<SC, LO, GO, NO>;
    auto        out = Teuchos::fancyOStream(Teuchos::rcpFromRef(std::cerr));
    RCP<Matrix> product =
        MM::Multiply(*MM::Multiply(B2, false, A_inverse, false, *out), false, B1t, false, *out);
    if (C.is_null())
      {
        const auto domain = product->getDomainMap(), range = product->getRangeMap();
        product->resumeFill();
        product->scale(-scale);
        product->fillComplete(domain, range);
        return product;
      }
    RCP<Matrix> S = add_matrices(*C, -scale, *product);
    S->SetFixedBlockSize(C->GetFixedBlockSize()); // the block's striding, for smoothers and an AMG on S
    return S;
  }
} // namespace multigrid
