#include "block_gauss_seidel_smoother.h"

#include "sub_smoothers.h"

#include <MueLu_FactoryManagerBase.hpp>
#include <MueLu_HierarchyUtils.hpp>
#include <MueLu_Level.hpp>
#include <MueLu_Monitor.hpp>

#include <Teuchos_OrdinalTraits.hpp>
#include <Xpetra_BlockedCrsMatrix.hpp>
#include <Xpetra_BlockedMultiVector.hpp>
#include <Xpetra_MultiVectorFactory.hpp>

namespace multigrid
{
  namespace
  {
    using FactoryPointer = RCP<const MueLu::FactoryBase>;
  } // namespace

  RCP<const Teuchos::ParameterList> BlockGaussSeidelSmoother::GetValidParameterList() const
  {
    auto list = Teuchos::rcp(new Teuchos::ParameterList());
    list->set<FactoryPointer>("A", Teuchos::null, "Generating factory of the n x n blocked matrix");
    list->set<int>("Sweeps", 1, "Number of block Gauss-Seidel sweeps");
    list->set<double>("Damping factor", 1.0, "omega in x_k += omega M_k^-1 r_k");
    return list;
  }

  void BlockGaussSeidelSmoother::AddFactoryManager(RCP<const MueLu::FactoryManagerBase> manager, int pos)
  {
    if (pos < 0)
      throw InputError("BlockGaussSeidelSmoother: negative block position " + std::to_string(pos));
    if (managers_.size() <= static_cast<std::size_t>(pos))
      managers_.resize(pos + 1);
    managers_[pos] = manager;
  }

  void BlockGaussSeidelSmoother::DeclareInput(MueLu::Level& level) const
  {
    for (std::size_t k = 0; k < managers_.size(); ++k)
      if (managers_[k].is_null())
        throw InputError("BlockGaussSeidelSmoother: no sublist block" + std::to_string(k + 1));
    Input(level, "A");
    declare_sub_smoothers(level, managers_);
  }

  void BlockGaussSeidelSmoother::Setup(MueLu::Level& level)
  {
    MueLu::FactoryMonitor monitor(*this, "block Gauss-Seidel (project)", level);
    A_                   = Get<RCP<::multigrid::Matrix>>(level, "A");
    auto              bA = Teuchos::rcp_dynamic_cast<::multigrid::BlockedCrsMatrix>(A_);
    const std::size_t n  = managers_.size();
    if (bA.is_null() || bA->Rows() != n || bA->Cols() != n)
      throw InputError("BlockGaussSeidelSmoother: expected a " + std::to_string(n) + " x " +
                       std::to_string(n) + " blocked matrix (one sublist blockK per block row)");
    blocks_.assign(n, std::vector<RCP<const ::multigrid::Matrix>>(n));
    for (std::size_t k = 0; k < n; ++k)
      for (std::size_t j = 0; j < n; ++j)
        {
          const auto Akj = bA->getMatrix(k, j);
          if (Akj.is_null())
            continue;
          if (!Teuchos::rcp_dynamic_cast<const ::multigrid::BlockedCrsMatrix>(Akj).is_null())
            throw InputError("BlockGaussSeidelSmoother: block (" + std::to_string(k) + ", " +
                             std::to_string(j) + ") is itself blocked; nested blocks are not supported");
          if (Akj->getGlobalNumEntries() > 0) // a block zero on every rank is skipped on every rank
            blocks_[k][j] = Akj;
        }
    inverses_.clear();
    for (const auto& manager : managers_)
      inverses_.push_back(sub_smoother(level, manager));
    IsSetup(true);
  }

  void BlockGaussSeidelSmoother::Apply(::multigrid::MultiVector& X, const ::multigrid::MultiVector& B,
                                       bool initial_guess_is_zero) const
  {
    const auto&  list   = GetParameterList();
    const int    sweeps = list.get<int>("Sweeps");
    const double omega  = list.get<double>("Damping factor");
    auto         bA     = Teuchos::rcp_dynamic_cast<::multigrid::BlockedCrsMatrix>(A_);
    const bool   thyra  = bA->getRangeMapExtractor()->getThyraMode();
    const auto   m      = B.getNumVectors();
    const auto   n      = blocks_.size();

    const BlockedViews views(*bA, X, B);
    const auto&        bX = views.x;
    const auto&        bB = views.b;
    if (initial_guess_is_zero)
      bX->putScalar(0.0);

    std::vector<RCP<::multigrid::MultiVector>> x(n), r(n), dx(n);
    for (std::size_t k = 0; k < n; ++k)
      {
        x[k]  = bX->getMultiVector(k, thyra);
        r[k]  = bA->getRangeMapExtractor()->getVector(k, m, thyra, false);
        dx[k] = bA->getDomainMapExtractor()->getVector(k, m, thyra, false);
      }
    for (int sweep = 0; sweep < sweeps; ++sweep)
      for (std::size_t k = 0; k < n; ++k)
        {
          // r_k = b_k - sum_j A_kj x_j; from a zero start, x_j (j >= k) is still zero in sweep 0
          r[k]->update(1.0, *bB->getMultiVector(k, thyra), 0.0);
          for (std::size_t j = 0; j < n; ++j)
            if (!blocks_[k][j].is_null() && !(initial_guess_is_zero && sweep == 0 && j >= k))
              blocks_[k][j]->apply(*x[j], *r[k], Teuchos::NO_TRANS, -1.0, 1.0);
          // dx_k = M_k^-1 r_k from dx_k = 0, then x_k += omega dx_k
          dx[k]->putScalar(0.0);
          inverses_[k]->Apply(*dx[k], *r[k], true);
          x[k]->update(omega, *dx[k], 1.0);
        }
    views.write_back(X);
  }

  RCP<MueLu::SmootherPrototype<SC, LO, GO, NO>> BlockGaussSeidelSmoother::Copy() const
  {
    return Teuchos::rcp(new BlockGaussSeidelSmoother(*this));
  }

  size_t BlockGaussSeidelSmoother::getNodeSmootherComplexity() const
  {
    size_t total = 0;
    for (const auto& inverse : inverses_)
      {
        const size_t c = inverse->getNodeSmootherComplexity();
        if (c == Teuchos::OrdinalTraits<size_t>::invalid())
          return c;
        total += c;
      }
    return total;
  }
} // namespace multigrid
