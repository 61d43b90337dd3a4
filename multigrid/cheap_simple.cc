#include "cheap_simple.h"

#include "hierarchy_utils.h"
#include "inverse_approximation.h"
#include "schur_complement.h"

#include <MueLu_Hierarchy.hpp>

#include <Xpetra_BlockedCrsMatrix.hpp>
#include <Xpetra_MapExtractor.hpp>
#include <Xpetra_MultiVectorFactory.hpp>

#include <algorithm>
#include <string>
#include <vector>

namespace multigrid
{
  namespace
  {
    /// A string parameter with its allowed values, or its default when absent.
    std::string choice(const Teuchos::ParameterList& p, const std::string& name, const std::string& fallback,
                       const std::vector<std::string>& allowed)
    {
      const std::string value = value_or<std::string>(p, name, fallback);
      if (std::find(allowed.begin(), allowed.end(), value) == allowed.end())
        {
          std::string list;
          for (const auto& a : allowed)
            list += (list.empty() ? "" : ", ") + a;
          throw InputError("CheapSIMPLE: '" + name + "' is '" + value + "', expected one of " + list);
        }
      return value;
    }
  } // namespace

  CheapSimpleOperator::CheapSimpleOperator(const BlockSystem& system, const Teuchos::ParameterList& p,
                                           bool keep_transfers)
      : extractor_(system.map_extractor())
      , full_map_(system.full_map())
  {
    if (system.n_blocks() != 2)
      throw InputError("CheapSIMPLE needs a 2 x 2 block system, got " + std::to_string(system.n_blocks()) +
                       " blocks");
    sweeps_  = p.get<int>("sweeps");
    damping_ = p.get<double>("damping");
    if (sweeps_ < 1 || !(damping_ > 0.0))
      throw InputError("CheapSIMPLE: sweeps must be >= 1 and damping > 0 (got " + std::to_string(sweeps_) +
                       ", " + std::to_string(damping_) + ")");
    // Â's type is checked by approximate_inverse().
    inverse_options_ = inverse_approximation_options(p, "inverse approximation", "diagonal");
    // The final update's Â: the Schur complement's unless chosen apart (SIMPLE's diag(A)^-1 with
    // a lumped S, e.g.); the same type is computed once.
    update_options_ = inverse_approximation_options(p, "update inverse approximation", inverse_options_.type);
    const std::string predictor       = choice(p, "predictor", "amg", {"amg", "approximate inverse"});
    const std::string schur_nullspace = choice(p, "schur nullspace", "none", {"none", "block"});

    if (predictor == "amg")
      primal_parameters_ = p.sublist("primal solver");
    schur_parameters_ = p.sublist("schur solver");
    adopt(form_blocks(system));

    if (predictor == "amg")
      primal_ =
          build_single_field_hierarchy(A_, system.block(0).dofs_per_node, system.nullspace_or_translations(0),
                                       primal_parameters_, system.block(0).coordinates, keep_transfers);
    // S of a contact system lives on the multipliers (no near-nullspace); S of beam/solid on the
    // solid, whose rigid-body modes make the inner SA-AMG elasticity-aware.
    if (schur_nullspace == "block")
      schur_ =
          build_single_field_hierarchy(S_, system.block(1).dofs_per_node, system.nullspace_or_translations(1),
                                       schur_parameters_, Teuchos::null, keep_transfers);
    else
      schur_ = build_single_field_hierarchy(S_, 1, Teuchos::null, schur_parameters_, Teuchos::null,
                                            keep_transfers);
  }

  CheapSimpleOperator::Blocks CheapSimpleOperator::form_blocks(const BlockSystem& system) const
  {
    Blocks     b;
    const auto blocked = system.blocked_matrix();
    b.merged           = system.merged_matrix();
    b.A                = blocked->getMatrix(0, 0);
    b.B1t              = blocked->getMatrix(0, 1);
    b.B2               = blocked->getMatrix(1, 0);
    RCP<Matrix> C      = blocked->getMatrix(1, 1);
    b.A_inverse        = approximate_inverse(*b.A, inverse_options_);
    b.update_inverse   = update_options_.type == inverse_options_.type
                             ? b.A_inverse
                             : approximate_inverse(*b.A, update_options_);

    // S = C - B2 Â B1^T, formed explicitly (sparse: Â is diagonal or a SPAI on a fixed pattern).
    b.S = explicit_schur_complement(C, *b.B2, *b.A_inverse, *b.B1t, 1.0);
    return b;
  }

  void CheapSimpleOperator::adopt(Blocks b)
  {
    merged_         = std::move(b.merged);
    A_              = std::move(b.A);
    B1t_            = std::move(b.B1t);
    B2_             = std::move(b.B2);
    S_              = std::move(b.S);
    A_inverse_      = std::move(b.A_inverse);
    update_inverse_ = std::move(b.update_inverse);
  }

  void CheapSimpleOperator::refresh(const BlockSystem& system)
  {
    adopt(form_blocks(system));
    if (!primal_.is_null())
      refresh_single_field_hierarchy(*primal_, A_, primal_parameters_);
    refresh_single_field_hierarchy(*schur_, S_, schur_parameters_);
  }

  void CheapSimpleOperator::apply(const ::multigrid::MultiVector& X, ::multigrid::MultiVector& Y,
                                  Teuchos::ETransp mode, SC alpha, SC beta) const
  {
    if (mode != Teuchos::NO_TRANS)
      throw std::logic_error("CheapSimpleOperator: transposed apply is not supported");
    using MVF        = Xpetra::MultiVectorFactory<SC, LO, GO, NO>;
    const auto& ext  = *extractor_;
    const auto  full = full_map_;
    const auto  n    = X.getNumVectors();
    auto        x    = MVF::Build(full, n, true);
    auto        r    = MVF::Build(full, n);
    auto        dx1  = MVF::Build(A_->getRangeMap(), n);
    auto        dx2  = MVF::Build(S_->getRangeMap(), n);
    auto        tmp1 = MVF::Build(A_->getRangeMap(), n);
    auto        tmp2 = MVF::Build(A_->getRangeMap(), n);
    auto        rhs2 = MVF::Build(S_->getRangeMap(), n);

    for (int sweep = 0; sweep < sweeps_; ++sweep)
      {
        // 1. residual of the current iterate (x = 0 on the first sweep)
        if (sweep == 0)
          r->update(1.0, X, 0.0);
        else
          {
            merged_->apply(*x, *r);
            r->update(1.0, X, -1.0);
          }
        auto r1 = ext.ExtractVector(r, 0);
        auto r2 = ext.ExtractVector(r, 1);
        // 2. prediction: inner AMG, or one sweep of x <- x + Â (b - A x) from zero
        if (primal_.is_null())
          A_inverse_->apply(*r1, *dx1);
        else
          {
            dx1->putScalar(0.0);
            primal_->Iterate(*r1, *dx1, 1, true);
          }
        // 3. approximate Schur complement equation
        B2_->apply(*dx1, *rhs2);
        rhs2->update(1.0, *r2, -1.0);
        dx2->putScalar(0.0);
        schur_->Iterate(*rhs2, *dx2, 1, true);
        // 4. damped update of the second block and its consequence for the first
        dx2->scale(damping_);
        B1t_->apply(*dx2, *tmp1);
        update_inverse_->apply(*tmp1, *tmp2);
        dx1->update(-1.0 / damping_, *tmp2, 1.0);
        // 5. increment
        auto xx1 = ext.ExtractVector(x, 0);
        auto xx2 = ext.ExtractVector(x, 1);
        xx1->update(1.0, *dx1, 1.0);
        xx2->update(1.0, *dx2, 1.0);
        ext.InsertVector(xx1, 0, x);
        ext.InsertVector(xx2, 1, x);
      }
    Y.update(alpha, *x, beta);
  }

  void CheapSimpleOperator::residual(const ::multigrid::MultiVector& X, const ::multigrid::MultiVector& B,
                                     ::multigrid::MultiVector& R) const
  {
    merged_->apply(X, R);
    R.update(1.0, B, -1.0);
  }

  std::vector<std::pair<long long, long long>> CheapSimpleOperator::primal_levels() const
  {
    if (primal_.is_null())
      return {};
    return level_sizes(*primal_);
  }

  std::vector<std::pair<long long, long long>> CheapSimpleOperator::schur_levels() const
  {
    return level_sizes(*schur_);
  }

  long long CheapSimpleOperator::schur_nonzeros() const
  {
    return S_->getGlobalNumEntries();
  }

  long long CheapSimpleOperator::inverse_approximation_nonzeros() const
  {
    return A_inverse_->getGlobalNumEntries();
  }
} // namespace multigrid
