#include "spai_factories.h"

#include "hierarchy_utils.h"
#include "inverse_approximation.h"
#include "schur_complement.h"

#include <MueLu_Level.hpp>
#include <MueLu_Monitor.hpp>
#include <MueLu_NoFactory.hpp>
#include <MueLu_SingleLevelFactoryBase.hpp>
#include <MueLu_SmootherFactory.hpp>
#include <MueLu_SmootherPrototype.hpp>

#include <Xpetra_BlockedCrsMatrix.hpp>
#include <Xpetra_TpetraMultiVector.hpp>

namespace multigrid
{
  namespace
  {
    using MueLu::Level;
    using FactoryPointer = RCP<const MueLu::FactoryBase>;

    /// "Ainv" = Â ≈ A^-1 of the level's "A" (usually the A00 block): diagonal, row-sum,
    /// absolute-row-sum (lumping) or spai.
    class InverseApproximationFactory : public MueLu::SingleLevelFactoryBase
    {
    public:
      explicit InverseApproximationFactory(const Teuchos::ParameterList& list)
          : options_(inverse_approximation_options(list, "inverse: approximation type", "spai"))
      {
      }

      RCP<const Teuchos::ParameterList> GetValidParameterList() const override
      {
        auto list = Teuchos::rcp(new Teuchos::ParameterList());
        list->set<FactoryPointer>("A", Teuchos::null, "Generating factory of the matrix to approximate the inverse of");
        return list;
      }
      void DeclareInput(Level& level) const override { Input(level, "A"); }

      void Build(Level& level) const override
      {
        MueLu::FactoryMonitor monitor(*this, "Inverse approximation (" + options_.type + ")", level);
        Set(level, "Ainv", approximate_inverse(*Get<RCP<Matrix>>(level, "A"), options_));
      }

    private:
      InverseApproximationOptions options_;
    };

    /// S = A11 - (1/omega) A10 Â A01 with Â = "Ainv" of an InverseApproximationFactory.
    class SpaiSchurComplementFactory : public MueLu::SingleLevelFactoryBase
    {
    public:
      explicit SpaiSchurComplementFactory(const Teuchos::ParameterList& list)
          : omega_(value_or<double>(list, "omega", 1.0))
      {
      }

      RCP<const Teuchos::ParameterList> GetValidParameterList() const override
      {
        auto list = Teuchos::rcp(new Teuchos::ParameterList());
        // as MueLu's SchurComplementFactory: the level's blocked operator, not the factory
        // manager's "A" (which is this factory's own output in the corrector group)
        list->set<FactoryPointer>("A", MueLu::NoFactory::getRCP(), "Generating factory of the 2 x 2 blocked matrix");
        list->set<FactoryPointer>("Ainv", Teuchos::null, "InverseApproximationFactory of the A00 block");
        return list;
      }
      void DeclareInput(Level& level) const override
      {
        Input(level, "A");
        Input(level, "Ainv");
      }

      void Build(Level& level) const override
      {
        MueLu::FactoryMonitor monitor(*this, "Schur complement with an inverse approximation", level);
        auto bA = Teuchos::rcp_dynamic_cast<BlockedCrsMatrix>(Get<RCP<Matrix>>(level, "A"));
        if (bA.is_null() || bA->Rows() != 2 || bA->Cols() != 2)
          throw InputError("SpaiSchurComplementFactory: expected a 2 x 2 blocked matrix");
        RCP<Matrix> A01 = bA->getMatrix(0, 1), A10 = bA->getMatrix(1, 0), A11 = bA->getMatrix(1, 1);
        if (A01.is_null() || A10.is_null())
          {
            // No coupling stored on this level (contact: no active node, the coarse B blocks are
            // all zero and Xpetra does not store them): S = C.
            if (A11.is_null())
              throw InputError("SpaiSchurComplementFactory: a level without coupling blocks and without C "
                               "block: the multiplier block is singular");
            Set(level, "A", A11);
            return;
          }
        RCP<Matrix> inverse = Get<RCP<Matrix>>(level, "Ainv");
        Set(level, "A", explicit_schur_complement(A11, *A10, *inverse, *A01, 1.0 / omega_));
      }

    private:
      double omega_;
    };

    /// x <- x + damping Â (b - A x), Â = "Ainv" of an InverseApproximationFactory.
    class SpaiSmoother : public MueLu::SmootherPrototype<double, int, long long, ::multigrid::NO>
    {
    public:
      explicit SpaiSmoother(const Teuchos::ParameterList& list)
          : sweeps_(value_or<int>(list, "relaxation: sweeps", 1))
          , damping_(value_or<double>(list, "relaxation: damping factor", 1.0))
      {
      }

      RCP<const Teuchos::ParameterList> GetValidParameterList() const override
      {
        auto list = Teuchos::rcp(new Teuchos::ParameterList());
        list->set<FactoryPointer>("A", Teuchos::null, "Generating factory of the matrix");
        list->set<FactoryPointer>("Ainv", Teuchos::null, "InverseApproximationFactory of the same matrix");
        return list;
      }
      void DeclareInput(MueLu::Level& level) const override
      {
        this->Input(level, "A");
        this->Input(level, "Ainv");
      }

      void Setup(MueLu::Level& level) override
      {
        MueLu::FactoryMonitor monitor(*this, "SPAI smoother", level);
        A_       = this->template Get<RCP<::multigrid::Matrix>>(level, "A");
        inverse_ = this->template Get<RCP<::multigrid::Matrix>>(level, "Ainv");
        this->IsSetup(true);
      }

      /// The sweeps of spai_smooth() (inverse_approximation.h) on the Tpetra objects underneath.
      void Apply(::multigrid::MultiVector& X, const ::multigrid::MultiVector& B, bool /*initial_guess_is_zero*/) const override
      {
        using Helpers = Xpetra::Helpers<double, int, long long, ::multigrid::NO>;
        spai_smooth(Helpers::Op2TpetraCrs(*A_), Helpers::Op2TpetraCrs(*inverse_), Xpetra::toTpetra(B),
                    Xpetra::toTpetra(X), sweeps_, damping_);
      }

      RCP<MueLu::SmootherPrototype<double, int, long long, ::multigrid::NO>> Copy() const override
      {
        return Teuchos::rcp(new SpaiSmoother(*this));
      }
      std::string description() const override { return "SPAI smoother"; }
      size_t      getNodeSmootherComplexity() const override
      {
        return inverse_.is_null() ? 0 : static_cast<size_t>(inverse_->getNodeNumEntries());
      }

    private:
      int                      sweeps_;
      double                   damping_;
      RCP<::multigrid::Matrix> A_, inverse_;
    };

    /// The factory `list` names for `input` (e.g. "Ainv" -> "BeamInverse"), if any.
    FactoryPointer named_input(const Teuchos::ParameterList& list, const std::string& input, const std::string& owner,
                               const std::map<std::string, FactoryPointer>& factories)
    {
      if (!list.isParameter(input))
        return Teuchos::null;
      const auto name = list.get<std::string>(input);
      const auto it   = factories.find(name);
      if (it == factories.end())
        throw InputError(owner + ": '" + input + "' names factory '" + name + "', which is not defined before it");
      return it->second;
    }
  } // namespace

  RCP<const MueLu::FactoryBase> build_spai_factory(const std::string& name, const Teuchos::ParameterList& list,
                                                   const std::map<std::string, FactoryPointer>& factories)
  {
    RCP<MueLu::SingleLevelFactoryBase> factory;
    if (name == "InverseApproximationFactory")
      factory = Teuchos::rcp(new InverseApproximationFactory(list));
    else if (name == "SpaiSchurComplementFactory")
      factory = Teuchos::rcp(new SpaiSchurComplementFactory(list));
    else if (name == "SpaiSmoother")
      {
        auto smoother = Teuchos::rcp(new SpaiSmoother(list));
        for (const std::string input : {"A", "Ainv"})
          if (auto f = named_input(list, input, name, factories); !f.is_null())
            smoother->SetFactory(input, f);
        return Teuchos::rcp(new MueLu::SmootherFactory<SC, LO, GO, NO>(smoother, Teuchos::null));
      }
    else
      return Teuchos::null;
    for (const std::string input : {"A", "Ainv"})
      if (auto f = named_input(list, input, name, factories); !f.is_null())
        factory->SetFactory(input, f);
    return factory;
  }
} // namespace multigrid
