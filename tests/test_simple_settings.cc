// The SIMPLE level smoother's settings of the saddle-point template are independent and do what
// their names say:
//  - the inverse approximations: the signed row sum is 1 / sum_j a_ij (and refused, naming the
//    row, where a stiffness row sums to zero), the absolute row sum sign(a_ii) / sum_j |a_ij|,
//    "lumping" its alias;
//  - MueLu's own SimpleSmoother is reproduced to rounding by the template with SCHUR_INVERSE =
//    UPDATE_INVERSE = diagonal (SIMPLE), both absolute-row-sum (UseSIMPLEC) and MueLu's mixed
//    combination, SIMPLE with a lumped Schur complement (diagonal update, lumped S): one V-cycle
//    of each applied to the same vector;
//  - changing one setting (the Schur complement's Â, the update's Â, the undamped update, the
//    predictor's sweeps) changes the V-cycle, and the CheapSIMPLE-outside preset's "update
//    inverse approximation" changes its application while naming the Schur complement's own
//    type leaves it as it was.
#include "block_preconditioner.h"
#include "inverse_approximation.h"
#include "krylov_solver.h"
#include "model_problems.h"
#include "presets.h"

#include <Teuchos_XMLParameterListHelpers.hpp>
#include <Tpetra_CrsMatrix.hpp>
#include <Xpetra_BlockedCrsMatrix.hpp>
#include <Xpetra_MultiVectorFactory.hpp>
#include <gtest/gtest.h>

#include "test_helpers.h"

#include <iostream>
#include <regex>

using namespace multigrid;
using test_helpers::comm;

namespace
{
  using MVF = Xpetra::MultiVectorFactory<SC, LO, GO, NO>;

  /// One application of `preset` to a fixed random vector.
  RCP<MultiVector> apply_once(const BlockSystem& system, const Preset& preset)
  {
    BlockPreconditioner M(system, preset);
    auto                x = MVF::Build(system.full_map(), 1), y = MVF::Build(system.full_map(), 1);
    x->setSeed(7);
    x->randomize();
    M.op()->apply(*x, *y);
    return y;
  }

  double relative_difference(const MultiVector& a, const MultiVector& b)
  {
    auto d = MVF::Build(a.getMap(), 1);
    d->update(1.0, a, -1.0, b, 0.0);
    Teuchos::Array<double> nd(1), na(1);
    d->norm2(nd);
    a.norm2(na);
    return nd[0] / na[0];
  }

  /// pa-amg(cheapsimple) (plain aggregation, SIMPLE level smoother) with a coarse size the small
  /// tied-blocks system coarsens under, and the given template parameters.
  Preset simple_preset(const std::vector<std::string>& settings)
  {
    Preset p = load_preset("pa-amg(cheapsimple)");
    std::vector<std::string> overrides = {"template parameters/COARSE_MAX_SIZE=100"};
    for (const auto& s : settings)
      overrides.push_back("template parameters/" + s);
    apply_overrides(p, overrides);
    return p;
  }

  /// The same hierarchy written with MueLu's own SchurComplementFactory and SimpleSmoother.
  Preset muelu_simple(const BlockSystem& system, bool lumped_schur, bool simplec)
  {
    const Preset project = simple_preset({});
    std::string  xml     = expand_template(project, system.block(0).dofs_per_node, system.block(1).dofs_per_node);
    const std::string schur = std::string(R"(<ParameterList name="Schur">)") +
                              R"(<Parameter name="factory" type="string" value="SchurComplementFactory"/>)" +
                              R"(<Parameter name="omega" type="double" value="1.0"/>)" +
                              R"(<Parameter name="lumping" type="bool" value=")" +
                              (lumped_schur ? "true" : "false") + R"("/></ParameterList>)";
    xml = std::regex_replace(xml, std::regex(R"(<ParameterList name="Schur">[\s\S]*?</ParameterList>)"), schur);
    xml = std::regex_replace(xml, std::regex(R"(value="SpaiSimpleSmoother"/>)"),
                             std::string(R"(value="SimpleSmoother"/><Parameter name="UseSIMPLEC" type="bool" value=")") +
                                 (simplec ? "true" : "false") + "\"/>");
    xml = std::regex_replace(xml, std::regex(R"(<Parameter name="Undamped update"[^>]*/>)"), "");
    xml = std::regex_replace(xml, std::regex(R"(<Parameter name="Ainv" type="string" value="Ainv-[a-z-]*"/>)"), "");
    // the comparison is only worth something if MueLu's factories really replaced ours
    if (xml.find("SpaiSimpleSmoother") != std::string::npos || xml.find("SpaiSchurComplementFactory") != std::string::npos ||
        xml.find("\"SimpleSmoother\"") == std::string::npos)
      throw std::logic_error("muelu_simple: the template's SIMPLE or Schur lists were not replaced");
    Preset muelu;
    muelu.name       = "MueLu SimpleSmoother";
    muelu.kind       = "muelu";
    muelu.parameters = *Teuchos::getParametersFromXmlString(xml);
    return muelu;
  }
} // namespace

TEST(InverseApproximation, RowSumsAndAbsoluteRowSums)
{
  // [[4, -1, 0], [-1, 4, -2], [0, -2, 3]] on one rank's rows
  auto map = Tpetra::createUniformContigMap<LO, GO>(3, comm());
  auto A   = Teuchos::rcp(new TpetraMatrix(map, 3));
  const double values[3][3] = {{4, -1, 0}, {-1, 4, -2}, {0, -2, 3}};
  for (LO i = 0; i < static_cast<LO>(map->getNodeNumElements()); ++i)
    {
      const GO row = map->getGlobalElement(i);
      for (GO j = 0; j < 3; ++j)
        if (values[row][j] != 0)
          A->insertGlobalValues(row, Teuchos::tuple<GO>(j), Teuchos::tuple<SC>(values[row][j]));
    }
  A->fillComplete();
  const double row_sum[3] = {3, 1, 1}, absolute[3] = {5, 7, 5};
  for (const std::string type : {"row-sum", "absolute-row-sum", "lumping"})
    {
      InverseApproximationOptions options;
      options.type   = type;
      const auto inv = approximate_inverse(*A, options);
      for (LO i = 0; i < static_cast<LO>(map->getNodeNumElements()); ++i)
        {
          const GO row = map->getGlobalElement(i);
          typename TpetraMatrix::local_inds_host_view_type inds;
          typename TpetraMatrix::values_host_view_type     vals;
          inv->getLocalRowView(i, inds, vals);
          ASSERT_EQ(inds.extent(0), 1u);
          EXPECT_DOUBLE_EQ(vals(0), 1.0 / (type == "row-sum" ? row_sum[row] : absolute[row])) << type << " row " << row;
        }
    }
}

TEST(InverseApproximation, RowSumOfAStiffnessMatrixIsRefused)
{
  // the free rows of an elastic stiffness matrix sum to zero: a rigid translation is in its kernel
  const auto system = tied_blocks_2d(comm(), {});
  const auto A      = system.blocked_matrix()->getMatrix(0, 0);
  InverseApproximationOptions options;
  options.type = "row-sum";
  try
    {
      approximate_inverse(*A, options);
      FAIL() << "the row-sum lumped inverse of a stiffness matrix was accepted";
    }
  catch (const InputError& e)
    {
      EXPECT_NE(std::string(e.what()).find("zero row sum"), std::string::npos) << e.what();
    }
}

TEST(SimpleSettings, ReproduceMueLusSimpleSmoother)
{
  const auto system = tied_blocks_2d(comm(), {});
  struct Case
  {
    std::string schur, update;
    bool        lumped_schur, simplec;
  };
  for (const Case& c : {Case{"diagonal", "diagonal", false, false}, Case{"absolute-row-sum", "absolute-row-sum", true, true},
                        Case{"absolute-row-sum", "diagonal", true, false}})
    {
      const auto ours   = apply_once(system, simple_preset({"SCHUR_INVERSE=" + c.schur, "UPDATE_INVERSE=" + c.update}));
      const auto theirs = apply_once(system, muelu_simple(system, c.lumped_schur, c.simplec));
      EXPECT_LT(relative_difference(*theirs, *ours), 1e-11) << "S with " << c.schur << ", update " << c.update;
    }
}

TEST(SimpleSettings, EachSettingChangesTheCycle)
{
  const auto system    = tied_blocks_2d(comm(), {});
  const auto reference = apply_once(system, simple_preset({}));
  for (const std::string setting : {"SCHUR_INVERSE=absolute-row-sum", "SCHUR_INVERSE=spai", "UPDATE_INVERSE=absolute-row-sum",
                                    "UNDAMPED_UPDATE=true", "PREDICTOR_SWEEPS=3", "SMOOTHER_SWEEPS=3"})
    EXPECT_GT(relative_difference(*reference, *apply_once(system, simple_preset({setting}))), 1e-6) << setting;
}

TEST(SimpleSettings, CheapSimpleUpdateInverse)
{
  const auto system    = tied_blocks_2d(comm(), {});
  Preset     base      = load_preset("cheapsimple(pa-amg)");
  const auto reference = apply_once(system, base);
  Preset     same      = base;
  apply_overrides(same, {"update inverse approximation=diagonal"});
  EXPECT_LT(relative_difference(*reference, *apply_once(system, same)), 1e-14);
  Preset lumped = base;
  apply_overrides(lumped, {"update inverse approximation=absolute-row-sum"});
  EXPECT_GT(relative_difference(*reference, *apply_once(system, lumped)), 1e-6);
}

namespace
{
  /// Estimate of the spectral radius of one sweep's error propagation E = I - M^-1 K: the growth
  /// per step of a power iteration e <- E e from a random e, after `steps` steps.
  double sweep_growth(const BlockSystem& system, Preset preset, int steps)
  {
    preset.parameters.set("sweeps", 1);
    BlockPreconditioner M(system, preset);
    const auto          K = system.merged_matrix();
    auto                e = MVF::Build(system.full_map(), 1), r = MVF::Build(system.full_map(), 1),
         z = MVF::Build(system.full_map(), 1);
    e->setSeed(11);
    e->randomize();
    Teuchos::Array<double> norm(1);
    double                 growth = 0.0;
    for (int step = 0; step < steps; ++step)
      {
        e->norm2(norm);
        e->scale(1.0 / norm[0]);
        K->apply(*e, *r);
        M.op()->apply(*r, *z);
        e->update(-1.0, *z, 1.0);
        e->norm2(norm);
        growth = norm[0];
      }
    return growth;
  }

  int gmres_iterations(const BlockSystem& system, const Preset& preset)
  {
    BlockPreconditioner M(system, preset);
    auto                x      = MVF::Build(system.full_map(), 1);
    const auto          report = solve(system, M, *x, {});
    EXPECT_TRUE(report.converged) << preset.name;
    return report.iterations;
  }
} // namespace

// The seeds' CheapSIMPLE damping 0.8 with A-hat = diag(A): S = C - B2 diag(A)^-1 B1^T is smaller
// than the Schur complement the SA-AMG predictor sees (much smaller on smooth multiplier modes
// of fine meshes), so one sweep overcorrects the multipliers and its error propagation grows a
// mode, which the preset's second sweep amplifies (GMRES on tied-blocks-2d:3: 285 iterations
// with 0.8, 45 with 0.4; the 3D contact systems at 66 k: spectral radius 2.6 on 2 ranks with 0.8,
// twice the iterations of 1 rank; 0.57-0.92 with 0.4). On this small 2D system neither damping
// contracts (the mode grows ~18x per sweep with 0.4, ~37x with 0.8); the shipped damping halves
// the growth and the iterations.
TEST(SimpleSettings, CheapSimpleSaAmgDamping)
{
  TiedBlocksOptions options;
  options.level        = 2;
  const auto   system  = tied_blocks_2d(comm(), options);
  const Preset shipped = load_preset("cheapsimple(sa-amg)");
  Preset       seeds   = shipped;
  apply_overrides(seeds, {"damping=0.8"});
  const double shipped_growth = sweep_growth(system, shipped, 30);
  const double seeds_growth   = sweep_growth(system, seeds, 30);
  const int    shipped_its    = gmres_iterations(system, shipped);
  const int    seeds_its      = gmres_iterations(system, seeds);
  if (comm()->getRank() == 0)
    std::cout << "tied-blocks-2d:2, cheapsimple(sa-amg): damping "
              << shipped.parameters.get<double>("damping") << ": growth per sweep " << shipped_growth << ", "
              << shipped_its << " GMRES iterations; damping 0.8: " << seeds_growth << ", " << seeds_its
              << "\n";
  EXPECT_LT(shipped_growth, 0.6 * seeds_growth);
  EXPECT_LT(shipped_its, 0.6 * seeds_its);
}
