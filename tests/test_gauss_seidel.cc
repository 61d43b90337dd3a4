// The project's symmetric Gauss-Seidel (multigrid/gauss_seidel_smoother.h), which replaces
// Ifpack2's "Symmetric Gauss-Seidel" in the contact presets:
//  - its sweeps are Ifpack2 Relaxation's to round-off on the tied blocks' displacement block, from
//    a zero start and from a given x, for one and three sweeps with and without damping; on two
//    ranks this checks the import of the other rank's x before every sweep but a zero-start one;
//  - a zero diagonal and wrong settings give one-line errors;
//  - in the presets: "SGS" in an easy-style list (CheapSIMPLE's SA-AMG levels, cheapsimplec(sgs)'s
//    one-level solve, SGS as the coarse solve below two levels) and the factory
//    "GaussSeidelSmoother" in the saddle-point template (SIMPLE's predictor and corrector) give
//    the preconditioner of the Ifpack2 type to round-off.
#include "block_preconditioner.h"
#include "gauss_seidel_smoother.h"
#include "model_problems.h"
#include "presets.h"

#include <Ifpack2_Factory.hpp>
#include <MueLu_Utilities.hpp>
#include <Teuchos_ParameterList.hpp>
#include <Tpetra_CrsMatrix.hpp>
#include <Xpetra_BlockedCrsMatrix.hpp>
#include <Xpetra_MultiVectorFactory.hpp>
#include <gtest/gtest.h>

#include "test_helpers.h"

#include <filesystem>
#include <fstream>
#include <regex>

using namespace multigrid;
using test_helpers::comm;
using test_helpers::error_of;

namespace
{
  using MVF = Xpetra::MultiVectorFactory<SC, LO, GO, NO>;

  double norm(const MultiVector& v)
  {
    Teuchos::Array<double> n(1);
    v.norm2(n);
    return n[0];
  }

  RCP<const Matrix> displacement_block()
  {
    return tied_blocks_2d(comm(), {1, true, 1.0, 0.3}).blocked_matrix()->getMatrix(0, 0);
  }

  /// ||x_project - x_ifpack2|| / ||x_ifpack2|| after `sweeps` symmetric sweeps with `damping` on
  /// A x = b, b random, from x = 0 or from a random x.
  double against_ifpack2(const RCP<const Matrix>& A, int sweeps, double damping, bool zero_start)
  {
    Teuchos::ParameterList params;
    params.set("relaxation: type", std::string("Symmetric Gauss-Seidel"));
    params.set("relaxation: sweeps", sweeps);
    params.set("relaxation: damping factor", damping);
    params.set("relaxation: zero starting solution", zero_start);
    auto tA = MueLu::Utilities<SC, LO, GO, NO>::Op2NonConstTpetraCrs(Teuchos::rcp_const_cast<Matrix>(A));
    auto relaxation = Ifpack2::Factory::create<Tpetra::RowMatrix<SC, LO, GO, NO>>("RELAXATION", tA);
    relaxation->setParameters(params);
    relaxation->initialize();
    relaxation->compute();

    auto b = MVF::Build(A->getRowMap(), 1), x0 = MVF::Build(A->getRowMap(), 1);
    b->randomize();
    x0->randomize();
    auto x_ifpack2 = MVF::Build(A->getRowMap(), 1), x_project = MVF::Build(A->getRowMap(), 1);
    x_ifpack2->update(1.0, *x0, 0.0);
    x_project->update(1.0, *x0, 0.0);
    relaxation->apply(Xpetra::toTpetra(*b), Xpetra::toTpetra(*x_ifpack2));
    const SymmetricGaussSeidel sgs(A, {sweeps, damping});
    sgs.apply(*x_project, *b, zero_start);

    const double reference = norm(*x_ifpack2);
    x_project->update(-1.0, *x_ifpack2, 1.0);
    return norm(*x_project) / reference;
  }

  /// ||y1 - y2|| / ||y2|| for y = M b of the two presets on the tied blocks (level 2).
  double difference_of_applications(const Preset& project, const Preset& ifpack2)
  {
    const auto                    system = tied_blocks_2d(comm(), {2, true, 1.0, 0.3});
    std::vector<RCP<MultiVector>> y;
    for (const Preset* preset : {&project, &ifpack2})
      {
        BlockPreconditioner M(system, *preset);
        y.push_back(MVF::Build(system.full_map(), 1, true));
        M.op()->apply(*system.rhs(), *y.back());
      }
    const double reference = norm(*y[1]);
    EXPECT_GT(reference, 0.0);
    y[0]->update(-1.0, *y[1], 1.0);
    return norm(*y[0]) / reference;
  }
} // namespace

TEST(GaussSeidel, SweepsAreIfpack2sToRoundOff)
{
  const auto A = displacement_block();
  for (const bool zero_start : {true, false})
    for (const int sweeps : {1, 3})
      for (const double damping : {1.0, 0.8})
        EXPECT_LT(against_ifpack2(A, sweeps, damping, zero_start), 1e-13)
            << sweeps << " sweeps, damping " << damping << (zero_start ? ", zero start" : ", random start");
}

TEST(GaussSeidel, NamesAZeroDiagonalAndWrongSettings)
{
  // A diagonal matrix with a zero in the first row of every rank.
  auto map =
      Tpetra::createContigMap<LO, GO>(Teuchos::OrdinalTraits<Tpetra::global_size_t>::invalid(), 10, comm());
  auto tA = Teuchos::rcp(new Tpetra::CrsMatrix<SC, LO, GO, NO>(map, 1));
  for (LO i = 0; i < 10; ++i)
    {
      const GO g = map->getGlobalElement(i);
      tA->insertGlobalValues(g, Teuchos::tuple<GO>(g), Teuchos::tuple<SC>(i == 0 ? 0.0 : 2.0));
    }
  tA->fillComplete();
  const auto        A = MueLu::TpetraCrs_To_XpetraMatrix(tA);
  const std::string e = error_of([&] { SymmetricGaussSeidel sgs(A, {}); });
  EXPECT_NE(e.find("SGS: diagonal entry 0.000000 in local row 0 of 10"), std::string::npos) << e;

  const auto settings_error = [](const std::string& name, const Teuchos::ParameterEntry& value) {
    Teuchos::ParameterList list;
    list.sublist("smoother: params").setEntry(name, value);
    return error_of([&] { gauss_seidel_settings(list, "smoother: params", "primal solver"); });
  };
  EXPECT_NE(settings_error("relaxation: sweeps", Teuchos::ParameterEntry(0))
                .find("primal solver: SGS's 'relaxation: sweeps' must be an integer >= 1"),
            std::string::npos);
  EXPECT_NE(settings_error("relaxation: type", Teuchos::ParameterEntry(std::string("Jacobi")))
                .find("must be 'Symmetric Gauss-Seidel'"),
            std::string::npos);
  EXPECT_NE(settings_error("relaxation: damping factor", Teuchos::ParameterEntry(0.0)).find("other than 0"),
            std::string::npos);
  EXPECT_NE(settings_error("relaxation: use l1", Teuchos::ParameterEntry(true))
                .find("primal solver: SGS has no parameter 'relaxation: use l1'"),
            std::string::npos);
  Teuchos::ParameterList list;
  list.sublist("p").set("relaxation: sweeps", 2).set("relaxation: damping factor", 0.8);
  const auto s = gauss_seidel_settings(list, "p", "test");
  EXPECT_EQ(s.sweeps, 2);
  EXPECT_EQ(s.damping, 0.8);
}

TEST(GaussSeidel, InEasyListsIsTheIfpack2Type)
{
  // CheapSIMPLE's SA-AMG levels, cheapsimplec(sgs)'s one-level solve, and SGS as the coarse
  // solve below two levels.
  struct Case
  {
    std::string name, which;
    bool        coarse_below_levels;
  };
  for (const auto& c :
       {Case{"cheapsimple(sa-amg)", "smoother", false}, Case{"cheapsimplec(sgs)", "coarse", false},
        Case{"cheapsimple(sa-amg)", "coarse", true}})
    {
      Preset      project = load_preset(c.name);
      auto&       primal  = project.parameters.sublist("primal solver");
      const auto& type    = c.which + ": type";
      if (c.coarse_below_levels)
        {
          primal.set(type, std::string("SGS"));
          primal.set("coarse: max size", 100);
          primal.sublist("coarse: params") = primal.sublist("smoother: params");
        }
      ASSERT_EQ(primal.get<std::string>(type), "SGS") << c.name;
      Preset ifpack2 = project;
      ifpack2.parameters.sublist("primal solver").set(type, std::string("RELAXATION"));
      EXPECT_LT(difference_of_applications(project, ifpack2), 1e-12) << c.name << ", " << type;
    }
}

TEST(GaussSeidel, InTheSaddlePointTemplateIsTheIfpack2Type)
{
  // fully-coupled-sa-amg(simple)'s MueLu XML with the project's smoother, and the same XML with
  // Ifpack2's RELAXATION in each of its places.
  const Preset preset = load_preset("fully-coupled-sa-amg(simple)");
  const auto   xml    = expand_template(preset, 2, 2);
  const auto   own = std::regex(R"(<Parameter name="factory" type="string" value="GaussSeidelSmoother"/>)");
  const auto   ifpack2 =
      std::regex_replace(xml, own,
                         R"(<Parameter name="factory" type="string" value="TrilinosSmoother"/>)"
                         R"(<Parameter name="type" type="string" value="RELAXATION"/>)");
  ASSERT_NE(ifpack2, xml);
  const auto file = [&](const std::string& suffix, const std::string& text) {
    const auto path = std::filesystem::temp_directory_path() /
                      ("test_gauss_seidel_" + std::to_string(comm()->getRank()) + "_" + suffix + ".xml");
    std::ofstream(path) << text;
    return path.string();
  };
  const auto project_file = file("project", xml), ifpack2_file = file("ifpack2", ifpack2);
  EXPECT_LT(difference_of_applications(load_preset_file(project_file), load_preset_file(ifpack2_file)),
            1e-12);
  std::filesystem::remove(project_file);
  std::filesystem::remove(ifpack2_file);
}
