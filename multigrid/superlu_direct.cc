#include "superlu_direct.h"

#include <Xpetra_ExportFactory.hpp>
#include <Xpetra_ImportFactory.hpp>
#include <Xpetra_MapFactory.hpp>
#include <Xpetra_MatrixFactory.hpp>
#include <Xpetra_MultiVectorFactory.hpp>

#include <Teuchos_CommHelpers.hpp>

#include <Xpetra_IO.hpp>

#include <metis.h>
#include <slu_ddefs.h>

#include <algorithm>
#include <stdexcept>
#include <cstdlib>
#include <iterator>
#include <numeric>

namespace multigrid
{
  namespace
  {
    /// SuperLU's yes_no_t NO (0): the name NO is a macro of another header included before this one.
    constexpr yes_no_t superlu_no = static_cast<yes_no_t>(0);

    /// A square sparse matrix in compressed-column form (SuperLU's SLU_NC), 0-based.
    struct CompressedColumns
    {
      int                 n = 0;
      std::vector<int>    pointers, rows;
      std::vector<double> values;
    };

    /// The gathered matrix (all rows on this rank, rows and columns numbered by `map`) in
    /// compressed columns, built in two passes over its rows (count per column, then fill) so that
    /// no row-wise copy exists beside it: on a coarse level gathered to rank 0 every copy of the
    /// matrix adds to that one rank's memory. Stored zeros are left out; an empty row gets a one on
    /// its diagonal if `unit_diagonal_on_empty_rows`. Rows come in increasing order in each column.
    CompressedColumns gathered_columns(const Matrix& root, const ::multigrid::Map& map,
                                       bool unit_diagonal_on_empty_rows)
    {
      const int        n       = static_cast<int>(root.getNodeNumRows());
      const auto       col_map = root.getColMap();
      std::vector<int> column_of(col_map->getNodeNumElements()); // column map LID -> column of A
      for (std::size_t c = 0; c < column_of.size(); ++c)
        column_of[c] = map.getLocalElement(col_map->getGlobalElement(c));
      CompressedColumns A;
      A.n = n;
      A.pointers.assign(n + 1, 0);
      // visit(i, column, value) for every entry the factorization gets, row by row.
      const auto for_each_entry = [&](auto&& visit) {
        for (int i = 0; i < n; ++i)
          {
            Teuchos::ArrayView<const LO> cols;
            Teuchos::ArrayView<const SC> vals;
            root.getLocalRowView(i, cols, vals);
            bool empty = true;
            for (LO k = 0; k < cols.size(); ++k)
              if (vals[k] != 0.0)
                {
                  visit(i, column_of[cols[k]], vals[k]);
                  empty = false;
                }
            if (empty && unit_diagonal_on_empty_rows)
              visit(i, i, 1.0);
          }
      };
      for_each_entry([&](int, int column, double) { ++A.pointers[column + 1]; });
      std::partial_sum(A.pointers.begin(), A.pointers.end(), A.pointers.begin());
      A.rows.resize(A.pointers.back());
      A.values.resize(A.pointers.back());
      std::vector<int> next(A.pointers.begin(), A.pointers.end() - 1);
      for_each_entry([&](int i, int column, double value) {
        const int at = next[column]++;
        A.rows[at]   = i;
        A.values[at] = value;
      });
      return A;
    }

    /// Fill-reducing symmetric ordering: METIS nested dissection of the graph of A + A^T
    /// (diagonal left out). Returns SuperLU's perm_c: column j of A is column perm_c[j] of A Pc.
    std::vector<int> nested_dissection(const CompressedColumns& A)
    {
      // The pattern of A^T (rows of A as lists of columns, sorted), then each vertex's neighbours:
      // the union of column j and row j of A without the diagonal, written straight into the
      // METIS arrays (no list per vertex).
      std::vector<int> t_pointers(A.n + 1, 0), t_columns(A.rows.size());
      for (int r : A.rows)
        ++t_pointers[r + 1];
      std::partial_sum(t_pointers.begin(), t_pointers.end(), t_pointers.begin());
      {
        std::vector<int> next(t_pointers.begin(), t_pointers.end() - 1);
        for (int j = 0; j < A.n; ++j)
          for (int k = A.pointers[j]; k < A.pointers[j + 1]; ++k)
            t_columns[next[A.rows[k]]++] = j;
      }
      std::vector<idx_t> xadj(1, 0), adjncy;
      adjncy.reserve(2 * A.rows.size());
      for (int j = 0; j < A.n; ++j)
        {
          const auto column = A.rows.begin() + A.pointers[j], column_end = A.rows.begin() + A.pointers[j + 1];
          const auto row = t_columns.begin() + t_pointers[j], row_end = t_columns.begin() + t_pointers[j + 1];
          const auto from = adjncy.size();
          std::set_union(column, column_end, row, row_end, std::back_inserter(adjncy));
          adjncy.erase(std::remove(adjncy.begin() + from, adjncy.end(), static_cast<idx_t>(j)), adjncy.end());
          xadj.push_back(static_cast<idx_t>(adjncy.size()));
        }
      std::vector<int>().swap(t_columns);
      std::vector<int> perm_c(A.n);
      if (adjncy.empty()) // no couplings (e.g. a diagonal coarse matrix): any order is fill-free
        {
          std::iota(perm_c.begin(), perm_c.end(), 0);
          return perm_c;
        }
      idx_t              n = A.n;
      std::vector<idx_t> perm(A.n), iperm(A.n);
      idx_t              options[METIS_NOPTIONS];
      METIS_SetDefaultOptions(options);
      if (METIS_NodeND(&n, xadj.data(), adjncy.data(), nullptr, options, perm.data(), iperm.data()) !=
          METIS_OK)
        throw std::runtime_error("SuperLU: METIS_NodeND failed on a graph of " + std::to_string(A.n) +
                                 " vertices");
      // METIS: row i of the reordered matrix is row perm[i] of A, i.e. A's row j goes to iperm[j].
      std::copy(iperm.begin(), iperm.end(), perm_c.begin());
      return perm_c;
    }
  } // namespace

  /// The factorization on rank 0, by SuperLU's expert driver dgssvx, of A itself (compressed
  /// columns) with
  ///  1. equilibration (dgsequ/dlaqgs: A <- diag(R) A diag(C), rows and columns scaled to max 1);
  ///  2. a fill-reducing ordering: METIS nested dissection of the graph of A + A^T;
  ///  3. partial pivoting (threshold 1; the multiplier rows' zero diagonals are pivoted away);
  ///  4. iterative refinement in double precision on every solve, when asked for (componentwise
  ///     backward error to machine precision; each step one residual and one more solve).
  /// Why: the contact systems mix ~1e6 displacement rows and columns with ~1e-3 constraint rows and
  /// multiplier columns. The adaptor before this one factored A^T (the gathered rows as columns)
  /// unscaled, so its pivot search compared entries of differently scaled columns of A: relative
  /// residual 2e-9 / 8e-9 / 5e-8 on the 3D benchmark's last Newton systems at 3.3 k / 21 k / 66 k
  /// DOFs; with equilibration alone 1e-15 (3.3 k). The METIS ordering needs 0.64x the factor
  /// nonzeros of COLAMD at 66 k. (Debian's SuperLU 5.3 and SuperLU_DIST 8.1 stub out MC64's large-
  /// diagonal row matching, non-free code: dldperm aborts the program, so it is not used.)
  struct SuperLUDirect::Factors
  {
    CompressedColumns   B; ///< A, then equilibrated in place by dgssvx
    std::vector<int>    perm_r, perm_c, etree;
    std::vector<double> R, C; ///< dgssvx's equilibration
    char                equed = 'N';
    superlu_options_t   options{};
    SuperMatrix         A{}, L{}, U{};
    GlobalLU_t          glu{};
    bool                factored = false;

    ~Factors()
    {
      if (factored)
        {
          Destroy_SuperNode_Matrix(&L);
          Destroy_CompCol_Matrix(&U);
        }
      if (B.n > 0)
        Destroy_SuperMatrix_Store(&A);
    }

    int n() const { return B.n; }

    /// Returns dgssvx's info: 0 on success, i in 1..n if U(i,i) is exactly zero.
    int factorize(bool refine)
    {
      const int n = B.n;
      set_default_options(&options);
      options.Equil           = YES;
      options.ColPerm         = MY_PERMC;
      options.DiagPivotThresh = 1.0; // partial pivoting: the multiplier rows' zero diagonals
      options.IterRefine      = refine ? SLU_DOUBLE : NOREFINE;
      options.ConditionNumber = superlu_no;
      options.PivotGrowth     = superlu_no;
      options.PrintStat       = superlu_no;
      dCreate_CompCol_Matrix(&A, n, n, static_cast<int>(B.values.size()), B.values.data(), B.rows.data(),
                             B.pointers.data(), SLU_NC, SLU_D, SLU_GE);
      perm_c = nested_dissection(B);
      perm_r.resize(n);
      etree.resize(n);
      R.resize(n);
      C.resize(n);
      std::vector<double> none(n);
      SuperMatrix         Bx, Xx;
      dCreate_Dense_Matrix(&Bx, n, 1, none.data(), n, SLU_DN, SLU_D, SLU_GE);
      dCreate_Dense_Matrix(&Xx, n, 1, none.data(), n, SLU_DN, SLU_D, SLU_GE);
      Bx.ncol              = 0; // factorize only (dgssvx's convention)
      double        growth = 0, rcond = 0, ferr = 0, berr = 0;
      mem_usage_t   memory;
      SuperLUStat_t stat;
      StatInit(&stat);
      int info = 0;
      dgssvx(&options, &A, perm_c.data(), perm_r.data(), etree.data(), &equed, R.data(), C.data(), &L, &U,
             nullptr, 0, &Bx, &Xx, &growth, &rcond, &ferr, &berr, &glu, &memory, &stat, &info);
      StatFree(&stat);
      Destroy_SuperMatrix_Store(&Bx);
      Destroy_SuperMatrix_Store(&Xx);
      factored = (info == 0);
      if (!factored && info > 0 && info <= n)
        { // L and U were allocated before the zero pivot was met
          Destroy_SuperNode_Matrix(&L);
          Destroy_CompCol_Matrix(&U);
        }
      return info;
    }

    long long nonzeros() const
    {
      const auto* l = static_cast<const SCformat*>(L.Store);
      const auto* u = static_cast<const NCformat*>(U.Store);
      return static_cast<long long>(l->nnz) + u->nnz;
    }

    /// rhs (n x n_rhs, column-major) is overwritten with A^-1 rhs.
    void solve(std::vector<double>& rhs, int n_rhs)
    {
      const int           n = B.n;
      std::vector<double> x(rhs.size());
      SuperMatrix         Bx, Xx;
      dCreate_Dense_Matrix(&Bx, n, n_rhs, rhs.data(), n, SLU_DN, SLU_D, SLU_GE);
      dCreate_Dense_Matrix(&Xx, n, n_rhs, x.data(), n, SLU_DN, SLU_D, SLU_GE);
      superlu_options_t solve_options = options;
      solve_options.Fact              = FACTORED;
      std::vector<double> ferr(n_rhs), berr(n_rhs);
      double              growth = 0, rcond = 0;
      mem_usage_t         memory;
      SuperLUStat_t       stat;
      StatInit(&stat);
      int info = 0;
      dgssvx(&solve_options, &A, perm_c.data(), perm_r.data(), etree.data(), &equed, R.data(), C.data(), &L,
             &U, nullptr, 0, &Bx, &Xx, &growth, &rcond, ferr.data(), berr.data(), &glu, &memory, &stat,
             &info);
      StatFree(&stat);
      Destroy_SuperMatrix_Store(&Bx);
      Destroy_SuperMatrix_Store(&Xx);
      rhs.swap(x);
    }
  };

  SuperLUDirect::SuperLUDirect(const RCP<const Matrix>& A, const SuperLUOptions& options)
  {
    const auto comm  = A->getRowMap()->getComm();
    distributed_map_ = A->getRangeMap();
    if (A->getGlobalNumRows() != A->getGlobalNumCols())
      throw InputError("SuperLU: matrix is " + std::to_string(A->getGlobalNumRows()) + " x " +
                       std::to_string(A->getGlobalNumCols()) + ", expected square");

    // All rows on rank 0, in the order of the range map's global ids.
    const auto       gids = distributed_map_->getNodeElementList();
    std::vector<GO>  mine(gids.begin(), gids.end());
    int              n_local = static_cast<int>(mine.size());
    std::vector<int> counts(comm->getSize());
    Teuchos::gatherAll(*comm, 1, &n_local, comm->getSize(), counts.data());
    std::vector<GO> all;
    if (comm->getRank() == 0)
      all.resize(std::accumulate(counts.begin(), counts.end(), 0LL));
    {
      // gather of variable-size blocks through a padded all-reduce would cost O(N P); N here is
      // coarse-level or test sized, so a simple reduce of a zero-padded array is adequate.
      const long long n_global = static_cast<long long>(A->getGlobalNumRows());
      std::vector<GO> padded(n_global, 0), summed(n_global, 0);
      long long       start = 0;
      for (int r = 0; r < comm->getRank(); ++r)
        start += counts[r];
      for (int i = 0; i < n_local; ++i)
        padded[start + i] = mine[i];
      Teuchos::reduceAll(*comm, Teuchos::REDUCE_SUM, static_cast<int>(n_global), padded.data(),
                         summed.data());
      if (comm->getRank() == 0)
        all = summed;
    }
    root_map_ = Xpetra::MapFactory<LO, GO, NO>::Build(distributed_map_->lib(), A->getGlobalNumRows(),
                                                      Teuchos::ArrayView<const GO>(all),
                                                      distributed_map_->getIndexBase(), comm);
    gather_   = Xpetra::ImportFactory<LO, GO, NO>::Build(distributed_map_, root_map_);
    RCP<const Xpetra::Import<LO, GO, NO>> importer = gather_;
    if (!A->getRowMap()->isSameAs(*distributed_map_))
      importer = Xpetra::ImportFactory<LO, GO, NO>::Build(A->getRowMap(), root_map_);
    RCP<Matrix> root = Xpetra::MatrixFactory<SC, LO, GO, NO>::Build(A, *importer, root_map_, root_map_);

    // Rank 0 keeps one copy of the matrix, in compressed columns; the gathered Tpetra matrix goes
    // before the factorization (on a coarse level of many ranks this one rank holds the whole
    // coarse operator, its copies and its factors).
    if (comm->getRank() == 0)
      {
        factors_    = std::make_unique<Factors>();
        factors_->B = gathered_columns(*root, *root_map_, options.unit_diagonal_on_empty_rows);
      }
    root     = Teuchos::null;
    int info = 0;
    if (factors_ && factors_->n() > 0)
      {
        info = factors_->factorize(options.iterative_refinement);
        if (info == 0)
          factor_nnz_ = factors_->nonzeros();
      }
    Teuchos::broadcast(*comm, 0, Teuchos::outArg(info));
    Teuchos::broadcast(*comm, 0, Teuchos::outArg(factor_nnz_));
    if (info != 0 && std::getenv("SUPERLU_DUMP_SINGULAR"))
      Xpetra::IO<SC, LO, GO, NO>::Write(std::getenv("SUPERLU_DUMP_SINGULAR"), *A);
    if (info != 0)
      throw InputError("SuperLU: matrix of size " + std::to_string(A->getGlobalNumRows()) + " is " +
                       "singular (zero pivot in column " + std::to_string(info) +
                       "); expected a nonsingular system");
  }

  SuperLUDirect::~SuperLUDirect() = default;

  void SuperLUDirect::solve(const MultiVector& B, MultiVector& X) const
  {
    // The cached gather serves every vector distributed like the matrix (the usual case); a vector
    // on another map gets its own importer.
    auto importer_for = [this](const RCP<const Map>& map) -> RCP<const Xpetra::Import<LO, GO, NO>> {
      if (map.get() == distributed_map_.get() || map->isSameAs(*distributed_map_))
        return gather_;
      return Xpetra::ImportFactory<LO, GO, NO>::Build(map, root_map_);
    };
    const std::size_t n_rhs  = B.getNumVectors();
    auto              root_b = Xpetra::MultiVectorFactory<SC, LO, GO, NO>::Build(root_map_, n_rhs);
    root_b->doImport(B, *importer_for(B.getMap()), Xpetra::INSERT);
    if (factors_ && factors_->n() > 0)
      {
        const int           n = factors_->n();
        std::vector<double> rhs(static_cast<std::size_t>(n) * n_rhs);
        for (std::size_t j = 0; j < n_rhs; ++j)
          {
            const auto data = root_b->getData(j);
            std::copy(data.begin(), data.end(), rhs.begin() + j * n);
          }
        factors_->solve(rhs, static_cast<int>(n_rhs));
        for (std::size_t j = 0; j < n_rhs; ++j)
          {
            auto data = root_b->getDataNonConst(j);
            std::copy(rhs.begin() + j * n, rhs.begin() + (j + 1) * n, data.begin());
          }
      }
    X.doExport(*root_b, *importer_for(X.getMap()), Xpetra::INSERT); // reverse of the gather
  }

  DirectSolverOperator::DirectSolverOperator(const RCP<const Matrix>& A)
      : A_(A)
      , solver_(std::make_unique<SuperLUDirect>(A))
  {
  }

  void DirectSolverOperator::apply(const ::multigrid::MultiVector& X, ::multigrid::MultiVector& Y,
                                   Teuchos::ETransp mode, SC alpha, SC beta) const
  {
    if (mode != Teuchos::NO_TRANS)
      throw std::logic_error("DirectSolverOperator: transposed apply is not supported");
    auto Z = Xpetra::MultiVectorFactory<SC, LO, GO, NO>::Build(Y.getMap(), Y.getNumVectors());
    solver_->solve(X, *Z);
    Y.update(alpha, *Z, beta);
  }

  void DirectSolverOperator::residual(const ::multigrid::MultiVector& X, const ::multigrid::MultiVector& B,
                                      ::multigrid::MultiVector& R) const
  {
    A_->apply(X, R);
    R.update(1.0, B, -1.0);
  }
} // namespace multigrid
