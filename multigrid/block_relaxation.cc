#include "block_relaxation.h"

#include "superlu_direct.h"

#include <MueLu_Hierarchy.hpp>
#include <MueLu_Level.hpp>

#include <Xpetra_BlockedCrsMatrix.hpp>
#include <Xpetra_MapExtractor.hpp>
#include <Xpetra_MapFactory.hpp>
#include <Xpetra_MatrixFactory.hpp>
#include <Xpetra_MultiVectorFactory.hpp>

namespace multigrid
{
  namespace
  {
    /// `map` with every global id shifted by -offset.
    RCP<const ::multigrid::Map> shifted(const ::multigrid::Map& map, GO offset)
    {
      std::vector<GO> ids;
      for (GO g : map.getNodeElementList())
        ids.push_back(g - offset);
      return Xpetra::MapFactory<LO, GO, NO>::Build(map.lib(), map.getGlobalNumElements(),
                                                   Teuchos::ArrayView<const GO>(ids), 0, map.getComm());
    }

    /// A_kk renumbered from 0. MueLu's simple parameter lists find nodes as (DOF id) / (DOFs per
    /// node) ("DOF offset" 0, which only factory-style lists can change): for a block starting at
    /// an id that is no multiple of its DOFs per node (the ALE block after structure and fluid)
    /// the DOFs of one node would fall into two nodes, and CoalesceDropFactory reads past its
    /// arrays.
    RCP<Matrix> zero_based(const Matrix& A, GO offset)
    {
      const auto  rows = shifted(*A.getRowMap(), offset), cols = shifted(*A.getColMap(), offset);
      RCP<Matrix> B = Xpetra::MatrixFactory<SC, LO, GO, NO>::Build(rows, cols, A.getNodeMaxNumRowEntries());
      for (std::size_t i = 0; i < A.getNodeNumRows(); ++i)
        {
          Teuchos::ArrayView<const LO> c;
          Teuchos::ArrayView<const SC> v;
          A.getLocalRowView(static_cast<LO>(i), c, v);
          B->insertLocalValues(static_cast<LO>(i), c, v);
        }
      B->fillComplete(shifted(*A.getDomainMap(), offset), shifted(*A.getRangeMap(), offset));
      return B;
    }
  } // namespace

  /// M_k^-1 of one diagonal block: one V-cycle of its AMG hierarchy (on A_kk renumbered from 0)
  /// or a direct solve.
  struct BlockRelaxationOperator::BlockSolver
  {
    RCP<Hierarchy>                 amg;
    RCP<Matrix>                    A_zero_based; ///< the operator of `amg`
    std::unique_ptr<SuperLUDirect> direct;
    RCP<Matrix>                    A;

    /// dx = M_k^-1 r.
    void solve(const ::multigrid::MultiVector& r, ::multigrid::MultiVector& dx) const
    {
      if (direct)
        {
          direct->solve(r, dx);
          return;
        }
      const auto map = A_zero_based->getRangeMap();
      auto       r0  = ::multigrid::with_map(r, map),
           dx0       = Xpetra::MultiVectorFactory<SC, LO, GO, NO>::Build(map, r.getNumVectors(), true);
      amg->Iterate(*r0, *dx0, 1, true);
      for (std::size_t j = 0; j < dx.getNumVectors(); ++j)
        {
          const auto src = dx0->getData(j);
          auto       dst = dx.getDataNonConst(j);
          std::copy(src.begin(), src.end(), dst.begin());
        }
    }
  };

  namespace
  {
    /// The solver parameters of block `name`: its own sublist of "block solvers", else "default".
    Teuchos::ParameterList block_solver_parameters(const Teuchos::ParameterList& p, const std::string& name)
    {
      const auto& all = p.sublist("block solvers");
      if (all.isSublist(name))
        return all.sublist(name);
      if (all.isSublist("default"))
        return all.sublist("default");
      throw InputError("preset parameter 'block solvers' has no sublist '" + name + "' nor 'default'");
    }
  } // namespace

  BlockRelaxationOperator::BlockRelaxationOperator(const BlockSystem& system, const Teuchos::ParameterList& p)
      : full_map_(system.full_map())
      , extractor_(system.map_extractor())
      , A_(system.blocked_matrix())
  {
    const std::string method = p.get<std::string>("method");
    if (method != "gauss-seidel" && method != "jacobi")
      throw InputError("preset parameter 'method' is '" + method + "', expected gauss-seidel or jacobi");
    gauss_seidel_ = method == "gauss-seidel";
    sweeps_       = p.get<int>("sweeps");
    damping_      = p.get<double>("damping");
    if (sweeps_ < 1 || !(damping_ > 0 && damping_ <= 2))
      throw InputError("preset parameters 'sweeps' = " + std::to_string(sweeps_) + ", 'damping' = " +
                       std::to_string(damping_) + ": expected sweeps >= 1 and 0 < damping <= 2");
    for (std::size_t k = 0; k < system.n_blocks(); ++k)
      {
        const auto& block = system.block(k);
        names_.push_back(block.name);
        auto list              = block_solver_parameters(p, block.name);
        auto solver            = std::make_unique<BlockSolver>();
        solver->A              = A_->getMatrix(k, k);
        const std::string kind = list.get<std::string>("solver", "amg");
        list.remove("solver", false);
        if (kind == "direct")
          solver->direct = std::make_unique<SuperLUDirect>(solver->A);
        else if (kind == "amg")
          {
            // A placeholder MueLu sets up cheaply; SuperLU replaces it (see the header).
            list.set("coarse: type", std::string("RELAXATION"));
            solver->A_zero_based = zero_based(*solver->A, block.offset);
            solver->amg =
                build_single_field_hierarchy(solver->A_zero_based, block.dofs_per_node,
                                             ::multigrid::with_map(*system.nullspace_or_translations(k),
                                                                   solver->A_zero_based->getRowMap()),
                                             list, block.coordinates);
            use_superlu_coarse_solver(*solver->amg);
          }
        else
          throw InputError("preset parameter 'block solvers/" + block.name + "/solver' is '" + kind +
                           "', expected amg or direct");
        solvers_.push_back(std::move(solver));
      }
  }

  BlockRelaxationOperator::~BlockRelaxationOperator() = default;

  void BlockRelaxationOperator::apply(const ::multigrid::MultiVector& X, ::multigrid::MultiVector& Y,
                                      Teuchos::ETransp mode, SC alpha, SC beta) const
  {
    if (mode != Teuchos::NO_TRANS)
      throw std::logic_error("BlockRelaxationOperator: transposed apply is not supported");
    const std::size_t                          n    = solvers_.size();
    const auto                                 nvec = X.getNumVectors();
    RCP<const ::multigrid::MultiVector>        full = Teuchos::rcpFromRef(X);
    std::vector<RCP<::multigrid::MultiVector>> b(n), x(n), x_old(n);
    std::vector<bool>                          nonzero(n, false); // x_j = 0 needs no product
    for (std::size_t k = 0; k < n; ++k)
      {
        b[k] = extractor_->ExtractVector(full, k);
        x[k] = extractor_->getVector(k, nvec, false, true);
      }
    auto dx = std::vector<RCP<::multigrid::MultiVector>>(n);
    for (std::size_t k = 0; k < n; ++k)
      dx[k] = extractor_->getVector(k, nvec, false, true);

    for (int sweep = 0; sweep < sweeps_; ++sweep)
      {
        const std::vector<bool> nonzero_old = nonzero;
        if (!gauss_seidel_)
          for (std::size_t k = 0; k < n; ++k)
            {
              x_old[k] = Xpetra::MultiVectorFactory<SC, LO, GO, NO>::Build(x[k]->getMap(), nvec, false);
              x_old[k]->update(1.0, *x[k], 0.0);
            }
        for (std::size_t k = 0; k < n; ++k)
          {
            // r_k = b_k - sum_j A_kj x_j (Gauss-Seidel: the newest x_j; Jacobi: the sweep's start)
            auto r = Xpetra::MultiVectorFactory<SC, LO, GO, NO>::Build(b[k]->getMap(), nvec, false);
            r->update(1.0, *b[k], 0.0);
            for (std::size_t j = 0; j < n; ++j)
              {
                const bool used = gauss_seidel_ ? nonzero[j] : nonzero_old[j];
                auto       Akj  = A_->getMatrix(k, j);
                if (used && !Akj.is_null() && Akj->getGlobalNumEntries() > 0)
                  Akj->apply(gauss_seidel_ ? *x[j] : *x_old[j], *r, Teuchos::NO_TRANS, -1.0, 1.0);
              }
            solvers_[k]->solve(*r, *dx[k]);
            x[k]->update(damping_, *dx[k], 1.0);
            nonzero[k] = true;
          }
      }
    auto result = Xpetra::MultiVectorFactory<SC, LO, GO, NO>::Build(full_map_, nvec, true);
    for (std::size_t k = 0; k < n; ++k)
      extractor_->InsertVector(*x[k], k, *result);
    Y.update(alpha, *result, beta);
  }

  void BlockRelaxationOperator::residual(const ::multigrid::MultiVector&, const ::multigrid::MultiVector&,
                                         ::multigrid::MultiVector&) const
  {
    throw std::logic_error("BlockRelaxationOperator: residual() is not defined for a preconditioner");
  }

  void BlockRelaxationOperator::describe(PreconditionerInfo& info) const
  {
    std::vector<std::vector<std::pair<long long, long long>>> sizes;
    std::size_t                                               depth = 1;
    long long                                                 fine = 0, total = 0;
    for (std::size_t k = 0; k < solvers_.size(); ++k)
      {
        const auto& s = *solvers_[k];
        sizes.push_back(s.amg.is_null()
                            ? std::vector<std::pair<long long, long long>>{{static_cast<long long>(
                                                                                s.A->getGlobalNumRows()),
                                                                            static_cast<long long>(
                                                                                s.A->getGlobalNumEntries())}}
                            : level_sizes(*s.amg));
        depth = std::max(depth, sizes.back().size());
        fine += sizes.back()[0].second;
        for (const auto& level : sizes.back())
          total += level.second;
        std::string note = "block '" + names_[k] + "': ";
        if (s.amg.is_null())
          note += "direct (SuperLU), L+U nonzeros " + std::to_string(s.direct->factor_nonzeros());
        else
          note += "SA-AMG, " + std::to_string(sizes.back().size()) + " levels";
        info.notes.push_back(note);
      }
    for (std::size_t l = 0; l < depth; ++l)
      {
        LevelInfo level;
        for (const auto& block : sizes)
          {
            const auto [rows, nnz] = l < block.size() ? block[l] : std::pair<long long, long long>{0, 0};
            level.rows += rows;
            level.nonzeros += nnz;
            level.block_rows.push_back(rows);
          }
        info.levels.push_back(level);
      }
    info.operator_complexity = fine > 0 ? static_cast<double>(total) / fine : 1.0;
    info.notes.push_back(std::string(gauss_seidel_ ? "block Gauss-Seidel" : "block Jacobi") + ", " +
                         std::to_string(sweeps_) + " sweep(s), damping " + std::to_string(damping_) +
                         "; levels and operator complexity are those of the diagonal blocks' hierarchies");
    info.coarse_solver = "SuperLU per block (project adaptor)";
  }
} // namespace multigrid
