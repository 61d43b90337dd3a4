#include "superlu_direct.h"

#include <Xpetra_ExportFactory.hpp>
#include <Xpetra_ImportFactory.hpp>
#include <Xpetra_MapFactory.hpp>
#include <Xpetra_MatrixFactory.hpp>
#include <Xpetra_MultiVectorFactory.hpp>

#include <Teuchos_CommHelpers.hpp>

#include <Xpetra_IO.hpp>

#include <slu_ddefs.h>

#include <cstdlib>

#include <numeric>

namespace multigrid
{
  /// SuperLU's factorization of A^T in compressed-column form, i.e. of A in compressed-row form;
  /// solves use dgstrs with TRANS, as SuperLU's own dgssv does for row-compressed input.
  struct SuperLUDirect::Factors
  {
    int                 n = 0;
    std::vector<double> values;
    std::vector<int>    indices, pointers;
    std::vector<int>    perm_r, perm_c, etree;
    SuperMatrix         A{}, AC{}, L{}, U{};
    GlobalLU_t          glu{};
    bool                factored = false;

    ~Factors()
    {
      if (factored)
        {
          Destroy_CompCol_Permuted(&AC);
          Destroy_SuperNode_Matrix(&L);
          Destroy_CompCol_Matrix(&U);
        }
      if (n > 0)
        Destroy_SuperMatrix_Store(&A);
    }

    /// Returns SuperLU's info: 0 on success, i > 0 if U(i,i) is exactly zero.
    int factorize()
    {
      superlu_options_t options;
      set_default_options(&options);
      options.ColPerm = COLAMD;
      SuperLUStat_t stat;
      StatInit(&stat);
      dCreate_CompCol_Matrix(&A, n, n, static_cast<int>(values.size()), values.data(), indices.data(),
                             pointers.data(), SLU_NC, SLU_D, SLU_GE);
      perm_r.resize(n);
      perm_c.resize(n);
      etree.resize(n);
      get_perm_c(options.ColPerm, &A, perm_c.data());
      sp_preorder(&options, &A, perm_c.data(), etree.data(), &AC);
      const int panel_size = sp_ienv(1), relax = sp_ienv(2);
      int       info = 0;
      dgstrf(&options, &AC, relax, panel_size, etree.data(), nullptr, 0, perm_c.data(), perm_r.data(), &L, &U,
             &glu, &stat, &info);
      StatFree(&stat);
      factored = (info == 0);
      if (!factored && info <= n)
        { // dgstrf allocated L and U before it met the zero pivot
          Destroy_CompCol_Permuted(&AC);
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

    void solve(std::vector<double>& rhs, int n_rhs) const
    {
      SuperMatrix   B;
      SuperLUStat_t stat;
      StatInit(&stat);
      dCreate_Dense_Matrix(&B, n, n_rhs, rhs.data(), n, SLU_DN, SLU_D, SLU_GE);
      int info = 0;
      dgstrs(TRANS, const_cast<SuperMatrix*>(&L), const_cast<SuperMatrix*>(&U),
             const_cast<int*>(perm_c.data()), const_cast<int*>(perm_r.data()), &B, &stat, &info);
      Destroy_SuperMatrix_Store(&B);
      StatFree(&stat);
    }
  };

  SuperLUDirect::SuperLUDirect(const RCP<const Matrix>& A, bool unit_diagonal_on_empty_rows)
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

    int info = 0;
    if (comm->getRank() == 0)
      {
        factors_   = std::make_unique<Factors>();
        Factors& f = *factors_;
        f.n        = static_cast<int>(root->getNodeNumRows());
        f.pointers.assign(1, 0);
        const auto col_map = root->getColMap();
        for (int i = 0; i < f.n; ++i)
          {
            Teuchos::ArrayView<const LO> cols;
            Teuchos::ArrayView<const SC> vals;
            root->getLocalRowView(i, cols, vals);
            bool empty = true;
            for (LO k = 0; k < cols.size(); ++k)
              {
                f.indices.push_back(root_map_->getLocalElement(col_map->getGlobalElement(cols[k])));
                f.values.push_back(vals[k]);
                empty &= (vals[k] == 0.0);
              }
            if (empty && unit_diagonal_on_empty_rows)
              {
                f.indices.push_back(i);
                f.values.push_back(1.0);
              }
            f.pointers.push_back(static_cast<int>(f.indices.size()));
          }
        info = f.n > 0 ? f.factorize() : 0;
        if (info == 0 && f.n > 0)
          factor_nnz_ = f.nonzeros();
      }
    Teuchos::broadcast(*comm, 0, Teuchos::outArg(info));
    Teuchos::broadcast(*comm, 0, Teuchos::outArg(factor_nnz_));
    if (info != 0 && std::getenv("SUPERLU_DUMP_SINGULAR"))
      Xpetra::IO<SC, LO, GO, NO>::Write(std::getenv("SUPERLU_DUMP_SINGULAR"), *A);
    if (info != 0)
      throw InputError("SuperLU: matrix of size " + std::to_string(A->getGlobalNumRows()) +
                       " is singular (zero pivot in column " + std::to_string(info) +
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
    if (factors_ && factors_->n > 0)
      {
        const int           n = factors_->n;
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
