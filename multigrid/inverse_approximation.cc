#include "inverse_approximation.h"

#include "hierarchy_utils.h"

#include <MueLu_Utilities.hpp>

#include <Teuchos_LAPACK.hpp>
#include <TpetraExt_MatrixMatrix.hpp>
#include <Tpetra_CrsMatrix.hpp>
#include <Tpetra_Import.hpp>
#include <Tpetra_MultiVector.hpp>
#include <Tpetra_RowMatrixTransposer.hpp>
#include <Xpetra_CrsMatrixWrap.hpp>
#include <Xpetra_MatrixMatrix.hpp>
#include <Xpetra_TpetraCrsMatrix.hpp>

#include <algorithm>
#include <cmath>
#include <vector>

namespace multigrid
{
  namespace
  {
    using Teuchos::rcp;

    /// One locally owned or imported row as (global column, value) pairs.
    void global_row(const TpetraMatrix& A, LO local_row, std::vector<GO>& cols, std::vector<SC>& vals)
    {
      typename TpetraMatrix::local_inds_host_view_type inds;
      typename TpetraMatrix::values_host_view_type     values;
      A.getLocalRowView(local_row, inds, values);
      cols.resize(inds.extent(0));
      vals.resize(inds.extent(0));
      for (std::size_t k = 0; k < inds.extent(0); ++k)
        {
          cols[k] = A.getColMap()->getGlobalElement(inds(k));
          vals[k] = values(k);
        }
    }

    RCP<TpetraMatrix> transpose(const TpetraMatrix& A)
    {
      Tpetra::RowMatrixTransposer<SC, LO, GO, NO> transposer(Teuchos::rcpFromRef(A));
      return transposer.createTranspose();
    }

    /// diag(A)^-1 or one of the lumped inverses (see the header): `type` is diagonal, row-sum or
    /// absolute-row-sum.
    RCP<TpetraMatrix> diagonal_inverse(const TpetraMatrix& A, const std::string& type)
    {
      auto               D = rcp(new TpetraMatrix(A.getRowMap(), 1));
      std::vector<GO>    cols;
      std::vector<SC>    vals;
      for (LO i = 0; i < static_cast<LO>(A.getNodeNumRows()); ++i)
        {
          const GO row = A.getRowMap()->getGlobalElement(i);
          global_row(A, i, cols, vals);
          double diagonal = 0, row_sum = 0, absolute_row_sum = 0;
          for (std::size_t k = 0; k < cols.size(); ++k)
            {
              if (cols[k] == row)
                diagonal = vals[k];
              row_sum += vals[k];
              absolute_row_sum += std::abs(vals[k]);
            }
          // A stiffness matrix's rows of nodes without a Dirichlet condition sum to zero (a rigid
          // translation is in its kernel): the signed row sum is then (round-off of) zero.
          if (type == "row-sum" && std::abs(row_sum) <= 1e-12 * absolute_row_sum)
            throw InputError("inverse approximation 'row-sum': zero row sum (" + std::to_string(row_sum) +
                             " of absolute row sum " + std::to_string(absolute_row_sum) + ") in row " +
                             std::to_string(row));
          if (type != "row-sum" && diagonal == 0)
            throw InputError("inverse approximation '" + type + "': zero diagonal in row " + std::to_string(row));
          const double value = type == "diagonal" ? 1.0 / diagonal
                               : type == "row-sum" ? 1.0 / row_sum
                                                   : (diagonal > 0 ? 1.0 : -1.0) / absolute_row_sum;
          D->insertGlobalValues(row, Teuchos::tuple<GO>(row), Teuchos::tuple<SC>(value));
        }
      D->fillComplete(A.getDomainMap(), A.getRangeMap());
      return D;
    }

    /// Rows `rows` (global ids) of A, imported from their owners, fill-complete.
    RCP<TpetraMatrix> import_rows(const TpetraMatrix& A, const RCP<const Tpetra::Map<LO, GO, NO>>& rows)
    {
      Tpetra::Import<LO, GO, NO> importer(A.getRowMap(), rows);
      size_t                     longest = 0;
      Teuchos::reduceAll(*A.getComm(), Teuchos::REDUCE_MAX, A.getNodeMaxNumRowEntries(), Teuchos::outArg(longest));
      auto imported = rcp(new TpetraMatrix(rows, longest));
      imported->doImport(A, importer, Tpetra::INSERT);
      imported->fillComplete(A.getDomainMap(), A.getRangeMap());
      return imported;
    }

    /// min ||C x - rhs||_2 for the m x n matrix C (column-major, m >= n expected, full column
    /// rank), by Householder QR: C = Q R, x = R^-1 (Q^T rhs)(1..n), left in rhs(1..n). C and
    /// rhs are overwritten. LAPACK's GELS does the same after scaling C where its largest entry
    /// is near over- or underflow, which a stiffness block never is; its max-norm scan, with a
    /// NaN test by function call for every entry, was a third of the SPAI set-up's LAPACK time
    /// (beam/solid, 20 k DOFs). m < n, possible only where columns of the pattern lack their
    /// diagonal entry, goes to GELS's minimum-norm solution. false: rank deficient.
    bool least_squares(int m, int n, std::vector<SC>& C, std::vector<SC>& rhs,
                       const Teuchos::LAPACK<int, double>& lapack, std::vector<SC>& tau,
                       std::vector<SC>& work)
    {
      constexpr int block = 64; // work per column: LAPACK's blocked QR needs n x its block size
      work.resize(static_cast<std::size_t>(block) * std::max(n, 1));
      const int lwork = static_cast<int>(work.size());
      int       info  = 0;
      if (m < n)
        {
          lapack.GELS('N', m, n, 1, C.data(), m, rhs.data(), std::max(m, n), work.data(), lwork, &info);
          return info == 0;
        }
      tau.resize(n);
      lapack.GEQRF(m, n, C.data(), m, tau.data(), work.data(), lwork, &info);
      if (info != 0)
        return false;
      // Q^T rhs with the minimal workspace (one entry for one right-hand side): ORMQR then
      // applies the reflectors one by one, O(m n), instead of forming the blocked
      // representation's triangular factors, O(m n^2), which a single vector does not repay.
      lapack.ORMQR('L', 'T', m, 1, n, C.data(), m, tau.data(), rhs.data(), m, work.data(), 1, &info);
      if (info != 0)
        return false;
      lapack.TRTRS('U', 'N', 'N', n, 1, C.data(), m, rhs.data(), m, &info); // info > 0: R(i,i) = 0
      return info == 0;
    }

    /// Least-squares SPAI, row by row on A^T (see the header).
    RCP<TpetraMatrix> spai(const TpetraMatrix& A, const InverseApproximationOptions& options)
    {
      const RCP<TpetraMatrix> At = transpose(A);
      RCP<TpetraMatrix>       pattern = At; // the pattern of (A^T)^k = (A^k)^T
      for (int k = 1; k < options.pattern_power; ++k)
        {
          auto product = rcp(new TpetraMatrix(At->getRowMap(), 0));
          Tpetra::MatrixMatrix::Multiply(*pattern, false, *At, false, *product);
          pattern = product;
        }
      // The rows of A^T that any local pattern row needs: the pattern's column map.
      const RCP<TpetraMatrix> columns = import_rows(*At, pattern->getColMap());

      // Tpetra 13.2 allocates rows statically: room for the longest pattern row (+ diagonal).
      auto At_inverse = rcp(new TpetraMatrix(At->getRowMap(), pattern->getNodeMaxNumRowEntries() + 1));
      Teuchos::LAPACK<int, double> lapack;
      std::vector<GO>                             J, I, cols;
      std::vector<SC>                             vals, C, rhs, tau, work;
      std::vector<std::vector<std::pair<GO, SC>>> rows_of_J;
      for (LO k = 0; k < static_cast<LO>(pattern->getNodeNumRows()); ++k)
        {
          const GO row = pattern->getRowMap()->getGlobalElement(k);
          // J_k: the pattern row after dropping small entries (the diagonal always stays).
          global_row(*pattern, k, cols, vals);
          double largest = 0;
          for (const double v : vals)
            largest = std::max(largest, std::abs(v));
          J.clear();
          for (std::size_t q = 0; q < cols.size(); ++q)
            if (cols[q] == row || std::abs(vals[q]) >= options.drop_tolerance * largest)
              J.push_back(cols[q]);
          if (std::find(J.begin(), J.end(), row) == J.end())
            J.push_back(row);
          // I_k, the rows that J_k's columns reach, as a sorted list (sorting the gathered ids
          // once is cheaper than inserting them one by one into a search tree: the SPAI set-up's
          // samples 715 -> 638 on the beam/solid case above), and the dense block
          // C = A(I_k, J_k) (column-major, leading dimension |I_k|).
          I.clear();
          rows_of_J.resize(J.size());
          for (std::size_t j = 0; j < J.size(); ++j)
            {
              global_row(*columns, columns->getRowMap()->getLocalElement(J[j]), cols, vals);
              rows_of_J[j].clear();
              for (std::size_t q = 0; q < cols.size(); ++q)
                rows_of_J[j].emplace_back(cols[q], vals[q]);
              I.insert(I.end(), cols.begin(), cols.end());
            }
          std::sort(I.begin(), I.end());
          I.erase(std::unique(I.begin(), I.end()), I.end());
          const auto position = [&I](GO gid) {
            return std::lower_bound(I.begin(), I.end(), gid) - I.begin();
          };
          const int m = static_cast<int>(I.size()), n = static_cast<int>(J.size());
          C.assign(static_cast<std::size_t>(m) * n, 0.0);
          for (int j = 0; j < n; ++j)
            for (const auto& [gid, value] : rows_of_J[j])
              C[static_cast<std::size_t>(j) * m + position(gid)] = value;
          rhs.assign(std::max(m, n), 0.0);
          if (std::binary_search(I.begin(), I.end(), row))
            rhs[position(row)] = 1.0;
          if (!least_squares(m, n, C, rhs, lapack, tau, work))
            throw std::runtime_error("SPAI: least-squares problem of row " + std::to_string(row) +
                                     " is rank deficient");
          At_inverse->insertGlobalValues(row, Teuchos::ArrayView<const GO>(J.data(), n),
                                         Teuchos::ArrayView<const SC>(rhs.data(), n));
        }
      At_inverse->fillComplete(At->getDomainMap(), At->getRangeMap());
      return transpose(*At_inverse);
    }
  } // namespace

  RCP<TpetraMatrix> approximate_inverse(const TpetraMatrix& A, const InverseApproximationOptions& options)
  {
    if (options.drop_tolerance < 0)
      throw InputError("inverse approximation: drop tolerance must be >= 0, got " +
                       std::to_string(options.drop_tolerance));
    if (options.type == "diagonal" || options.type == "row-sum" || options.type == "absolute-row-sum")
      return diagonal_inverse(A, options.type);
    if (options.type == "lumping") // MueLu's name for the absolute row sum
      return diagonal_inverse(A, "absolute-row-sum");
    if (options.type == "spai")
      {
        if (options.pattern_power < 1 || options.pattern_power > 4)
          throw InputError("inverse approximation 'spai': pattern power must be 1 to 4 (pattern of A^k), got " +
                           std::to_string(options.pattern_power));
        return spai(A, options);
      }
    throw InputError("unknown inverse approximation '" + options.type + "' (expected diagonal, row-sum, absolute-row-sum (alias lumping) or spai)");
  }

  InverseApproximationOptions inverse_approximation_options(const Teuchos::ParameterList& list,
                                                            const std::string& type_key,
                                                            const std::string& default_type)
  {
    InverseApproximationOptions options;
    options.type           = value_or<std::string>(list, type_key, default_type);
    options.pattern_power  = value_or<int>(list, "spai: pattern power", options.pattern_power);
    options.drop_tolerance = value_or<double>(list, "spai: drop tolerance", options.drop_tolerance);
    return options;
  }

  RCP<Matrix> approximate_inverse(const Matrix& A, const InverseApproximationOptions& options)
  {
    const TpetraMatrix& tA      = Xpetra::Helpers<SC, LO, GO, NO>::Op2TpetraCrs(A);
    RCP<TpetraMatrix>   inverse = approximate_inverse(tA, options);
    return MueLu::TpetraCrs_To_XpetraMatrix(inverse);
  }

  double inverse_residual_norm(const TpetraMatrix& A, const TpetraMatrix& A_inverse)
  {
    TpetraMatrix product(A.getRowMap(), 0);
    Tpetra::MatrixMatrix::Multiply(A, false, A_inverse, false, product);
    std::vector<GO> cols;
    std::vector<SC> vals;
    double          sum = 0;
    for (LO i = 0; i < static_cast<LO>(product.getNodeNumRows()); ++i)
      {
        const GO row = product.getRowMap()->getGlobalElement(i);
        global_row(product, i, cols, vals);
        bool has_diagonal = false;
        for (std::size_t k = 0; k < cols.size(); ++k)
          {
            const double e = vals[k] - (cols[k] == row ? 1.0 : 0.0);
            has_diagonal |= cols[k] == row;
            sum += e * e;
          }
        if (!has_diagonal)
          sum += 1.0;
      }
    double total = 0;
    Teuchos::reduceAll(*A.getComm(), Teuchos::REDUCE_SUM, sum, Teuchos::outArg(total));
    return std::sqrt(total);
  }

  void spai_smooth(const TpetraMatrix& A, const TpetraMatrix& A_inverse, const TpetraMultiVector& b,
                   TpetraMultiVector& x, int sweeps, double damping)
  {
    TpetraMultiVector r(b.getMap(), b.getNumVectors());
    for (int s = 0; s < sweeps; ++s)
      {
        A.apply(x, r);
        r.update(1.0, b, -1.0); // r = b - A x
        A_inverse.apply(r, x, Teuchos::NO_TRANS, damping, 1.0);
      }
  }
} // namespace multigrid
