// A MueLu smoother around one of the project's rank-local kernels (ilu0_smoother.h,
// gauss_seidel_smoother.h): the set-up builds Kernel(A, settings) on its level's matrix, Apply
// hands X, B and the zero-guess flag to Kernel::apply. Kernel provides the type Settings, the
// constant `name` (the smoother's description), a constructor (RCP<const Matrix>, Settings),
// apply(X, B, zero_start) and nonzeros().
#pragma once

#include "types.h"

#include <MueLu_Level.hpp>
#include <MueLu_Monitor.hpp>
#include <MueLu_SmootherPrototype.hpp>
#include <Teuchos_ParameterList.hpp>

#include <memory>
#include <string>

namespace multigrid
{
  template <typename Kernel>
  class KernelSmoother
      : public MueLu::SmootherPrototype<::multigrid::SC, ::multigrid::LO, ::multigrid::GO, ::multigrid::NO>
  {
  public:
    using Settings = typename Kernel::Settings;
    using Prototype =
        MueLu::SmootherPrototype<::multigrid::SC, ::multigrid::LO, ::multigrid::GO, ::multigrid::NO>;

    explicit KernelSmoother(const Settings& settings = {})
        : settings_(settings)
    {
    }
    /// Already set up on A (for a hierarchy built from MueLu's easy-style list, where the
    /// project's smoothers take the place of a placeholder after the set-up).
    KernelSmoother(const RCP<const ::multigrid::Matrix>& A, const Settings& settings)
        : settings_(settings)
        , kernel_(std::make_shared<const Kernel>(A, settings))
    {
      this->IsSetup(true);
    }

    RCP<const Teuchos::ParameterList> GetValidParameterList() const override
    {
      auto list = Teuchos::rcp(new Teuchos::ParameterList());
      list->set<RCP<const MueLu::FactoryBase>>("A", Teuchos::null, "Generating factory of the matrix");
      return list;
    }
    void DeclareInput(MueLu::Level& level) const override { this->Input(level, "A"); }
    void Setup(MueLu::Level& level) override
    {
      MueLu::FactoryMonitor monitor(*this, Kernel::name, level);
      kernel_ =
          std::make_shared<const Kernel>(this->template Get<RCP<::multigrid::Matrix>>(level, "A"), settings_);
      this->IsSetup(true);
    }
    void Apply(::multigrid::MultiVector& X, const ::multigrid::MultiVector& B,
               bool initial_guess_is_zero = false) const override
    {
      kernel_->apply(X, B, initial_guess_is_zero);
    }
    RCP<Prototype> Copy() const override { return Teuchos::rcp(new KernelSmoother(*this)); }
    std::string    description() const override { return Kernel::name; }
    /// The kernel's stored entries on this rank.
    size_t getNodeSmootherComplexity() const override { return kernel_ ? kernel_->nonzeros() : 0; }

  private:
    Settings                      settings_;
    std::shared_ptr<const Kernel> kernel_;
  };
} // namespace multigrid
