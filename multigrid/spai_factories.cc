#include "spai_factories.h"

#include "inverse_approximation.h"

#include <MueLu_Level.hpp>
#include <MueLu_Monitor.hpp>
#include <MueLu_NoFactory.hpp>
#include <MueLu_SingleLevelFactoryBase.hpp>
#include <MueLu_SmootherFactory.hpp>
#include <MueLu_SmootherPrototype.hpp>

#include <Xpetra_BlockedCrsMatrix.hpp>
#include <Xpetra_MatrixMatrix.hpp>
#include <Xpetra_MultiVectorFactory.hpp>

namespace multigrid
{
  namespace
  {
    using MueLu::Level;

    template <typename T>
    T value_or(const Teuchos::ParameterList& list, const std::string& name, T fallback)
    {
      return list.isParameter(name) ? list.get<T>(name) : fallback;
    }

    InverseApproximationOptions options_from(const Teuchos::ParameterList& list)
    {
      InverseApproximationOptions o;
      o.type           = value_or<std::string>(list, "inverse: approximation type", "spai");
      o.pattern_power  = value_or<int>(list, "spai: pattern power", 1);
      o.drop_tolerance = value_or<double>(list, "spai: drop tolerance", 0.0);
      return o;
    }

    class SpaiSchurComplementFactory : public MueLu::SingleLevelFactoryBase
    {
    public:
      explicit SpaiSchurComplementFactory(const Teuchos::ParameterList& list)
          : options_(options_from(list))
          , omega_(value_or<double>(list, "omega", 1.0))
      {
      }

      RCP<const Teuchos::ParameterList> GetValidParameterList() const override
      {
        auto list = Teuchos::rcp(new Teuchos::ParameterList());
        // as MueLu's SchurComplementFactory: the level's blocked operator, not the factory
        // manager's "A" (which is this factory's own output in the corrector group)
        list->set<RCP<const MueLu::FactoryBase>>("A", MueLu::NoFactory::getRCP(),
                                                 "Generating factory of the 2 x 2 blocked matrix");
        return list;
      }
      void DeclareInput(Level& level) const override { Input(level, "A"); }

      void Build(Level& level) const override
      {
        MueLu::FactoryMonitor monitor(*this, "Schur complement with a sparse approximate inverse", level);
        auto bA = Teuchos::rcp_dynamic_cast<BlockedCrsMatrix>(Get<RCP<Matrix>>(level, "A"));
        if (bA.is_null() || bA->Rows() != 2 || bA->Cols() != 2)
          throw InputError("SpaiSchurComplementFactory: expected a 2 x 2 blocked matrix");
        RCP<Matrix> A00 = bA->getMatrix(0, 0), A01 = bA->getMatrix(0, 1), A10 = bA->getMatrix(1, 0),
                    A11 = bA->getMatrix(1, 1);
        RCP<Matrix> inverse = approximate_inverse(*A00, options_);
        using MM            = Xpetra::MatrixMatrix<SC, LO, GO, NO>;
        Teuchos::FancyOStream& out = GetOStream(MueLu::Statistics2);
        RCP<Matrix> inverse_A01 = MM::Multiply(*inverse, false, *A01, false, out);
        RCP<Matrix> product     = MM::Multiply(*A10, false, *inverse_A01, false, out);
        RCP<Matrix> S;
        MM::TwoMatrixAdd(*A11, false, 1.0, *product, false, -1.0 / omega_, S, out);
        S->fillComplete(A11->getDomainMap(), A11->getRangeMap());
        // the block's striding, for the corrector's smoother and a later AMG on S
        S->SetFixedBlockSize(A11->GetFixedBlockSize());
        Set(level, "A", S);
        Set(level, "Ainv", inverse); // the SPAI smoother of the same level can reuse it
      }

      const InverseApproximationOptions& options() const { return options_; }

    private:
      InverseApproximationOptions options_;
      double                      omega_;
    };

    class SpaiSmoother : public MueLu::SmootherPrototype<double, int, long long, ::multigrid::NO>
    {
    public:
      explicit SpaiSmoother(const Teuchos::ParameterList& list)
          : options_(options_from(list))
          , sweeps_(value_or<int>(list, "relaxation: sweeps", 1))
          , damping_(value_or<double>(list, "relaxation: damping factor", 1.0))
      {
      }

      RCP<const Teuchos::ParameterList> GetValidParameterList() const override
      {
        auto list = Teuchos::rcp(new Teuchos::ParameterList());
        list->set<RCP<const MueLu::FactoryBase>>("A", Teuchos::null, "Generating factory of the matrix");
        list->set<RCP<const MueLu::FactoryBase>>("Ainv", Teuchos::null,
                                                 "Factory that already computed the inverse approximation of A "
                                                 "(e.g. the SPAI Schur complement factory); none: computed here");
        return list;
      }
      void DeclareInput(MueLu::Level& level) const override
      {
        this->Input(level, "A");
        if (reuse_)
          this->Input(level, "Ainv");
      }

      void Setup(MueLu::Level& level) override
      {
        MueLu::FactoryMonitor monitor(*this, "SPAI smoother", level);
        A_       = this->template Get<RCP<::multigrid::Matrix>>(level, "A");
        inverse_ = reuse_ ? this->template Get<RCP<::multigrid::Matrix>>(level, "Ainv")
                          : approximate_inverse(*A_, options_);
        this->IsSetup(true);
      }

      const InverseApproximationOptions& options() const { return options_; }

      /// Take Â from `factory` ("Ainv") instead of computing it.
      void reuse_inverse_of(const RCP<const MueLu::FactoryBase>& factory)
      {
        reuse_ = true;
        this->SetFactory("Ainv", factory);
      }

      void Apply(::multigrid::MultiVector& X, const ::multigrid::MultiVector& B, bool initial_guess_is_zero) const override
      {
        auto r = Xpetra::MultiVectorFactory<double, int, long long, ::multigrid::NO>::Build(B.getMap(), B.getNumVectors());
        for (int s = 0; s < sweeps_; ++s)
          {
            if (s == 0 && initial_guess_is_zero)
              r->update(1.0, B, 0.0);
            else
              {
                A_->apply(X, *r);
                r->update(1.0, B, -1.0); // r = b - A x
              }
            inverse_->apply(*r, X, Teuchos::NO_TRANS, damping_, s == 0 && initial_guess_is_zero ? 0.0 : 1.0);
          }
      }

      RCP<MueLu::SmootherPrototype<double, int, long long, ::multigrid::NO>> Copy() const override { return Teuchos::rcp(new SpaiSmoother(*this)); }
      std::string description() const override { return "SPAI smoother"; }
      size_t getNodeSmootherComplexity() const override
      {
        return inverse_.is_null() ? 0 : static_cast<size_t>(inverse_->getNodeNumEntries());
      }

    private:
      InverseApproximationOptions options_;
      int                         sweeps_;
      double                      damping_;
      bool                        reuse_ = false;
      RCP<::multigrid::Matrix>    A_, inverse_;
    };
  } // namespace

  RCP<const MueLu::FactoryBase> build_spai_factory(const std::string& name, const Teuchos::ParameterList& list,
                                                   const std::map<std::string, RCP<const MueLu::FactoryBase>>& factories)
  {
    if (name == "SpaiSchurComplementFactory")
      return Teuchos::rcp(new SpaiSchurComplementFactory(list));
    if (name == "SpaiSmoother")
      {
        auto smoother = Teuchos::rcp(new SpaiSmoother(list));
        if (list.isParameter("Ainv"))
          {
            const auto source = list.get<std::string>("Ainv");
            const auto it     = factories.find(source);
            if (it == factories.end())
              throw InputError("SpaiSmoother: 'Ainv' names factory '" + source + "', which is not defined before it");
            // Reuse only the same approximation (a baseline may use diag(A)^-1 in the Schur
            // complement but keep the SPAI smoother).
            const auto schur = Teuchos::rcp_dynamic_cast<const SpaiSchurComplementFactory>(it->second);
            const auto& a = smoother->options();
            if (!schur.is_null() && schur->options().type == a.type && schur->options().pattern_power == a.pattern_power &&
                schur->options().drop_tolerance == a.drop_tolerance)
              smoother->reuse_inverse_of(it->second);
          }
        return Teuchos::rcp(new MueLu::SmootherFactory<SC, LO, GO, NO>(smoother, Teuchos::null));
      }
    return Teuchos::null;
  }
} // namespace multigrid
