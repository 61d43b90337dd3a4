#include "spai_simple_smoother.h"

#include "sub_smoothers.h"

#include <MueLu_FactoryManagerBase.hpp>
#include <MueLu_HierarchyUtils.hpp>
#include <MueLu_Level.hpp>
#include <MueLu_Monitor.hpp>

#include <Xpetra_BlockedCrsMatrix.hpp>
#include <Xpetra_BlockedMultiVector.hpp>
#include <Xpetra_MultiVectorFactory.hpp>

namespace multigrid
{
  using FactoryPointer = RCP<const MueLu::FactoryBase>;
  using BlockedVectors = Xpetra::BlockedMultiVector<SC, LO, GO, NO>;

  RCP<const Teuchos::ParameterList> SpaiSimpleSmoother::GetValidParameterList() const
  {
    auto list = Teuchos::rcp(new Teuchos::ParameterList());
    list->set<FactoryPointer>("A", Teuchos::null, "Generating factory of the 2 x 2 blocked matrix");
    list->set<FactoryPointer>("Ainv", Teuchos::null, "InverseApproximationFactory of the A00 block");
    list->set<int>("Sweeps", 1, "Number of SIMPLE sweeps");
    list->set<double>("Damping factor", 1.0, "Damping of the Schur complement correction");
    list->set<bool>("Undamped update", false,
                    "Final update with the undamped correction, x1 += dx1 - Â A01 dx2 (seed 000's "
                    "CheapSIMPLE slide), instead of the damped one, x1 += dx1 - Â A01 (omega dx2) (MueLu)");
    return list;
  }

  void SpaiSimpleSmoother::AddFactoryManager(RCP<const MueLu::FactoryManagerBase> manager, int pos)
  {
    if (pos < 0 || pos > 1)
      throw InputError("SpaiSimpleSmoother: block" + std::to_string(pos + 1) + ": expected block1 and block2 only");
    if (managers_.size() <= static_cast<std::size_t>(pos))
      managers_.resize(pos + 1);
    managers_[pos] = manager;
  }

  void SpaiSimpleSmoother::DeclareInput(MueLu::Level& level) const
  {
    if (managers_.size() != 2 || managers_[0].is_null() || managers_[1].is_null())
      throw InputError("SpaiSimpleSmoother: expected two blocks (block1: predictor on A00, block2: corrector on the "
                       "Schur complement)");
    Input(level, "A");
    Input(level, "Ainv");
    declare_sub_smoothers(level, managers_);
  }

  void SpaiSimpleSmoother::Setup(MueLu::Level& level)
  {
    MueLu::FactoryMonitor monitor(*this, "SIMPLE with SPAI update", level);
    A_      = Get<RCP<::multigrid::Matrix>>(level, "A");
    auto bA = Teuchos::rcp_dynamic_cast<::multigrid::BlockedCrsMatrix>(A_);
    if (bA.is_null() || bA->Rows() != 2 || bA->Cols() != 2)
      throw InputError("SpaiSimpleSmoother: expected a 2 x 2 blocked matrix");
    range_   = bA->getRangeMapExtractor();
    domain_  = bA->getDomainMapExtractor();
    A01_     = bA->getMatrix(0, 1);
    A10_     = bA->getMatrix(1, 0);
    inverse_ = Get<RCP<::multigrid::Matrix>>(level, "Ainv");
    predictor_ = sub_smoother(level, managers_[0]);
    corrector_ = sub_smoother(level, managers_[1]);
    IsSetup(true);
  }

  void SpaiSimpleSmoother::Apply(::multigrid::MultiVector& X, const ::multigrid::MultiVector& B, bool initial_guess_is_zero) const
  {
    const auto&  list   = GetParameterList();
    const int    sweeps = list.get<int>("Sweeps");
    const double omega  = list.get<double>("Damping factor");
    const bool   undamped_update = list.get<bool>("Undamped update");
    auto         bA     = Teuchos::rcp_dynamic_cast<::multigrid::BlockedCrsMatrix>(A_);
    const bool   thyra  = range_->getThyraMode();
    const auto   n      = B.getNumVectors();

    const BlockedViews views(*bA, X, B);
    const auto&        bX = views.x;
    const auto&        bB = views.b;

    auto residual = Teuchos::rcp(new BlockedVectors(bA->getBlockedRangeMap(), n));
    auto dX       = Teuchos::rcp(new BlockedVectors(bA->getBlockedDomainMap(), n));
    auto r1 = residual->getMultiVector(0, thyra), r2 = residual->getMultiVector(1, thyra);
    auto dx1 = dX->getMultiVector(0, thyra), dx2 = dX->getMultiVector(1, thyra);
    auto schur_rhs = range_->getVector(1, n, thyra);
    auto coupling  = range_->getVector(0, n, thyra);
    auto update    = domain_->getVector(0, n, thyra);
    for (int sweep = 0; sweep < sweeps; ++sweep)
      {
        // 1. r = b - A x
        residual->update(1.0, *bB, 0.0);
        if (!initial_guess_is_zero || sweep > 0)
          A_->apply(*bX, *residual, Teuchos::NO_TRANS, -1.0, 1.0);
        // 2. predictor on A00
        dX->putScalar(0.0);
        predictor_->Apply(*dx1, *r1, true); // dx1 = 0: no residual of a zero guess
        // 3.-4. corrector on S with r2 - A10 dx1 (a coupling block that is all zero on a coarse
        // level, e.g. contact without active nodes, is not stored: then r2 alone)
        if (A10_.is_null())
          schur_rhs->update(1.0, *r2, 0.0);
        else
          {
            A10_->apply(*dx1, *schur_rhs);
            schur_rhs->update(1.0, *r2, -1.0);
          }
        corrector_->Apply(*dx2, *schur_rhs, true);
        // 5. dx1 -= Â A01 (omega dx2) (or Â A01 dx2, undamped), x2 += omega dx2, then x += dx
        if (!A01_.is_null())
          {
            A01_->apply(*dx2, *coupling);
            inverse_->apply(*coupling, *update);
            dx1->update(undamped_update ? -1.0 : -omega, *update, 1.0);
          }
        dx2->scale(omega);
        bX->update(1.0, *dX, 1.0);
      }
    views.write_back(X);
  }

  RCP<MueLu::SmootherPrototype<double, int, long long, ::multigrid::NO>> SpaiSimpleSmoother::Copy() const
  {
    return Teuchos::rcp(new SpaiSimpleSmoother(*this));
  }

  size_t SpaiSimpleSmoother::getNodeSmootherComplexity() const
  {
    return inverse_.is_null() ? 0 : static_cast<size_t>(inverse_->getNodeNumEntries());
  }
} // namespace multigrid
