// n x n block systems (the FSI layout: structure, fluid, ALE) and their preconditioners
// fully-coupled-sa-amg(bgs), bgs(amg), block-jacobi(amg), direct(superlu):
//  - the manifest round trip of a 3-block system (names, DOFs per node, nullspaces, coordinates);
//  - the fully coupled hierarchy's tentative prolongator is block-diagonal and reproduces every
//    field's nullspace exactly;
//  - one block Gauss-Seidel sweep with exact block solves is exact on a block-lower-triangular
//    system (block Jacobi is not);
//  - the preset's Chebyshev and ILU(0) sub-smoothers reduce the error on their blocks;
//  - the project's ILU(0) computes Ifpack2's RILUK(0) to round-off (the model's and the FSI
//    channel's fluid blocks), is exact where elimination fills nothing, names a zero pivot, and
//    takes the placeholder's place in hierarchies from easy-style lists (also after a refresh);
//  - every preset solves the 3-block model system (and the FSI channel systems exported by the
//    fsi app in a ctest fixture) to 1e-6, with the same iteration count within 10 % on
//    one rank (a split communicator) as on all ranks;
//  - clean one-line errors for a field too small to aggregate and a diverging level smoother.
#include "block_preconditioner.h"
#include "block_relaxation.h"
#include "block_system_io.h"
#include "coupled_fields.h"
#include "hierarchy_utils.h"
#include "ilu0_smoother.h"
#include "krylov_solver.h"
#include "node_interface_aggregation.h"
#include "presets.h"
#include "spatial_order.h"

#include <Ifpack2_Factory.hpp>
#include <MueLu_Hierarchy.hpp>
#include <MueLu_Level.hpp>
#include <MueLu_SmootherBase.hpp>
#include <MueLu_Utilities.hpp>
#include <Tpetra_Core.hpp>
#include <Xpetra_BlockedCrsMatrix.hpp>
#include <Xpetra_MultiVectorFactory.hpp>
#include <gtest/gtest.h>

#include "test_helpers.h"

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <functional>
#include <memory>

using namespace multigrid;
using test_helpers::comm;
using test_helpers::error_of;
namespace fs = std::filesystem;

namespace
{
  using MVF = Xpetra::MultiVectorFactory<SC, LO, GO, NO>;

  const std::vector<std::string> nxn_presets = {"fully-coupled-sa-amg(bgs)", "fully-coupled-pa-amg(bgs)",
                                                "bgs(amg)", "block-jacobi(amg)", "direct(superlu)"};

  double norm(const MultiVector& v)
  {
    Teuchos::Array<double> n(1);
    v.norm2(n);
    return n[0];
  }

  /// ||b - A x|| / ||b|| after x = M^-1 b.
  double residual_after_one_application(const BlockSystem& system, const Xpetra::Operator<SC, LO, GO, NO>& M)
  {
    auto x = MVF::Build(system.full_map(), 1, true), r = MVF::Build(system.full_map(), 1);
    M.apply(*system.rhs(), *x);
    system.merged_matrix()->apply(*x, *r);
    r->update(1.0, *system.rhs(), -1.0);
    return norm(*r) / norm(*system.rhs());
  }

  /// GMRES iterations to 1e-6 with `preset` (and overrides) on the system `make(comm)` builds,
  /// on all ranks and on rank 0 alone (split communicator); both runs must converge.
  std::pair<int, int> iterations_on_all_and_one_rank(const std::function<BlockSystem(RCP<const Comm>)>& make,
                                                     const std::string&                                 name,
                                                     const std::vector<std::string>& overrides)
  {
    auto run = [&](RCP<const Comm> c) {
      const BlockSystem system = make(c);
      Preset            preset = load_preset(name);
      apply_overrides(preset, overrides);
      BlockPreconditioner M(system, preset);
      auto                x = MVF::Build(system.full_map(), 1, true);
      SolveOptions        options;
      options.tolerance = 1e-6;
      const auto report = solve(system, M, *x, options);
      EXPECT_TRUE(report.converged) << name << " on " << c->getSize() << " rank(s): " << report.failure;
      EXPECT_LT(report.relative_residual, 1e-6 * 1.01) << name;
      return report.iterations;
    };
    const int all = run(comm());
    int       one = all;
    if (comm()->getSize() > 1)
      {
        auto single = comm()->split(comm()->getRank() == 0 ? 0 : 1, 0);
        if (comm()->getRank() == 0)
          one = run(single);
        Teuchos::broadcast(*comm(), 0, &one);
      }
    return {all, one};
  }

  void expect_iterations_within_ten_percent(const std::pair<int, int>& its, const std::string& what)
  {
    const auto [all, one] = its;
    if (comm()->getRank() == 0)
      std::cout << "[ iterations ] " << what << ": " << all << " on " << comm()->getSize() << " rank(s), "
                << one << " on 1" << std::endl;
    EXPECT_LE(std::abs(all - one), std::max(1, static_cast<int>(std::ceil(0.1 * one)))) << what;
  }

  /// The FSI channel Newton systems exported by the fsi app into $NXN_FSI_SYSTEMS (ctest's
  /// fixture nxn.export_fsi_channel: the first time step of apps/fsi_channel_2d.prm). Throws when
  /// there are none, so the test fails instead of passing on nothing.
  std::vector<std::string> fsi_channel_systems()
  {
    const char* env = std::getenv("NXN_FSI_SYSTEMS");
    if (!env || !fs::is_directory(env))
      throw std::runtime_error("NXN_FSI_SYSTEMS does not name a directory of exported FSI systems");
    std::vector<std::string> dirs;
    for (const auto& entry : fs::directory_iterator(env))
      if (fs::is_regular_file(entry.path() / "manifest.txt"))
        dirs.push_back(entry.path().string());
    std::sort(dirs.begin(), dirs.end());
    return dirs;
  }
} // namespace

TEST(NxnBlockSystem, ManifestRoundTripKeepsThreeBlocks)
{
  const auto        system = coupled_fields_2d(comm(), {1, false});
  const std::string dir =
      (fs::temp_directory_path() / ("nxn_round_trip_np" + std::to_string(comm()->getSize()))).string();
  write_block_system(system, dir);
  const auto read = read_block_system(dir, comm());
  ASSERT_EQ(read.n_blocks(), 3u);
  for (std::size_t k = 0; k < 3; ++k)
    {
      const auto &a = system.block(k), &b = read.block(k);
      EXPECT_EQ(a.name, b.name);
      EXPECT_EQ(a.dofs_per_node, b.dofs_per_node);
      EXPECT_EQ(a.global_size, b.global_size);
      EXPECT_EQ(a.offset, b.offset);
      ASSERT_FALSE(b.nullspace.is_null()) << b.name;
      EXPECT_EQ(a.nullspace->getNumVectors(), b.nullspace->getNumVectors()) << b.name;
      ASSERT_FALSE(b.coordinates.is_null()) << b.name;
      EXPECT_EQ(b.coordinates->getNumVectors(), 2u);
      for (std::size_t j = 0; j < a.nullspace->getNumVectors(); ++j)
        {
          Teuchos::Array<double> na(1), nb(1);
          a.nullspace->getVector(j)->norm2(na);
          b.nullspace->getVector(j)->norm2(nb);
          EXPECT_NEAR(na[0], nb[0], 1e-12 * na[0]) << b.name << " nullspace vector " << j;
        }
      Teuchos::Array<double> ca(2), cb(2);
      a.coordinates->norm1(ca);
      b.coordinates->norm1(cb);
      EXPECT_NEAR(ca[0], cb[0], 1e-12 * ca[0]);
      EXPECT_NEAR(ca[1], cb[1], 1e-12 * ca[1]);
    }
  // The same operator and right-hand side: A x for x = (1, 2, 3, ...) by global id.
  auto x = MVF::Build(system.full_map(), 1), y = MVF::Build(system.full_map(), 1);
  auto xr = MVF::Build(read.full_map(), 1), yr = MVF::Build(read.full_map(), 1);
  for (auto [v, map] : {std::pair{x, system.full_map()}, std::pair{xr, read.full_map()}})
    {
      auto data = v->getDataNonConst(0);
      for (std::size_t i = 0; i < map->getNodeNumElements(); ++i)
        data[i] = 1.0 + static_cast<double>(map->getGlobalElement(i));
    }
  system.merged_matrix()->apply(*x, *y);
  read.merged_matrix()->apply(*xr, *yr);
  EXPECT_NEAR(norm(*y), norm(*yr), 1e-12 * norm(*y));
  EXPECT_NEAR(norm(*system.rhs()), norm(*read.rhs()), 1e-12 * norm(*system.rhs()));
  comm()->barrier();
  if (comm()->getRank() == 0)
    fs::remove_all(dir);
}

TEST(FullyCoupledAmg, TentativeProlongatorIsBlockDiagonalAndReproducesNullspaces)
{
  const auto system = coupled_fields_2d(comm(), {2, false});
  Preset     preset = load_preset("fully-coupled-sa-amg(bgs)");
  apply_overrides(preset, {"prolongator=tentative", "block prolongators/fluid=tentative",
                           "coarse: max size=500", "max levels=2"});
  BlockPreconditioner M(system, preset);
  ASSERT_EQ(M.info().levels.size(), 2u);
  auto P = Teuchos::rcp_dynamic_cast<const BlockedCrsMatrix>(M.prolongator(0));
  ASSERT_FALSE(P.is_null());
  ASSERT_EQ(P->Rows(), 3u);
  ASSERT_EQ(P->Cols(), 3u);
  for (std::size_t i = 0; i < 3; ++i)
    for (std::size_t j = 0; j < 3; ++j)
      {
        if (i != j)
          {
            EXPECT_TRUE(P->getMatrix(i, j).is_null() || P->getMatrix(i, j)->getGlobalNumEntries() == 0)
                << "P(" << i << "," << j << ") couples two fields";
          }
      }
  for (std::size_t k = 0; k < 3; ++k)
    {
      // Ptent_k has orthonormal columns (QR per aggregate), so B_k = Ptent_k Bc_k holds iff
      // Ptent_k Ptent_k^T B_k = B_k. MueLu leaves Dirichlet (identity) rows out of the
      // aggregates: those rows of Ptent_k are empty, and only they may differ.
      const auto Pk = P->getMatrix(k, k);
      const auto Ak = system.blocked_matrix()->getMatrix(k, k);
      const auto B  = system.nullspace_or_translations(k);
      auto       Bc = MVF::Build(Pk->getDomainMap(), B->getNumVectors());
      auto       PB = MVF::Build(Pk->getRangeMap(), B->getNumVectors());
      Pk->apply(*B, *Bc, Teuchos::TRANS);
      Pk->apply(*Bc, *PB);
      PB->update(-1.0, *B, 1.0);
      double    worst = 0;
      long long empty = 0, empty_not_dirichlet = 0;
      for (std::size_t i = 0; i < Pk->getNodeNumRows(); ++i)
        {
          if (Pk->getNumEntriesInLocalRow(i) == 0)
            {
              ++empty;
              empty_not_dirichlet += Ak->getNumEntriesInLocalRow(i) != 1;
              continue;
            }
          for (std::size_t j = 0; j < B->getNumVectors(); ++j)
            worst = std::max(worst, std::abs(PB->getData(j)[i]) / (1.0 + std::abs(B->getData(j)[i])));
        }
      Teuchos::reduceAll(*comm(), Teuchos::REDUCE_MAX, worst, Teuchos::outArg(worst));
      Teuchos::reduceAll(*comm(), Teuchos::REDUCE_SUM, empty, Teuchos::outArg(empty));
      Teuchos::reduceAll(*comm(), Teuchos::REDUCE_SUM, empty_not_dirichlet,
                         Teuchos::outArg(empty_not_dirichlet));
      if (comm()->getRank() == 0)
        std::cout << "[ Ptent      ] " << system.block(k).name << ": max |Ptent Ptent^T B - B| = " << worst
                  << " (" << empty << " Dirichlet rows outside the aggregates)" << std::endl;
      EXPECT_LT(worst, 1e-13) << system.block(k).name;
      EXPECT_EQ(empty_not_dirichlet, 0)
          << system.block(k).name << ": a row that is no Dirichlet row is in no aggregate";
      EXPECT_LE(empty, 2 * 33) << system.block(k).name;
      ASSERT_EQ(M.info().levels[1].block_rows.size(), 3u);
      EXPECT_EQ(static_cast<std::size_t>(M.info().levels[1].block_rows[k]),
                Pk->getDomainMap()->getGlobalNumElements());
    }
}

TEST(BlockRelaxation, OneGaussSeidelSweepWithExactBlockSolvesIsExactOnBlockTriangularSystem)
{
  const auto system = coupled_fields_2d(comm(), {1, true});
  for (const std::string name : {"bgs(amg)", "block-jacobi(amg)"})
    {
      Preset preset = load_preset(name);
      for (const std::string block : {"structure", "fluid", "ale"})
        preset.parameters.sublist("block solvers").sublist(block).set("solver", std::string("direct"));
      BlockRelaxationOperator M(system, preset.parameters);
      const double            r = residual_after_one_application(system, M);
      if (name == "bgs(amg)")
        EXPECT_LT(r, 1e-12) << name;
      else
        EXPECT_GT(r, 1e-3) << name << ": block Jacobi ignores the couplings below the diagonal";
    }
}

TEST(SubSmoothers, ChebyshevAndIluOfThePresetReduceTheErrorOnTheirBlocks)
{
  const auto  system   = coupled_fields_2d(comm(), {2, false});
  const auto  preset   = load_preset("fully-coupled-sa-amg(bgs)");
  const auto& settings = preset.parameters.sublist("block smoothers");
  using TMV            = Tpetra::MultiVector<SC, LO, GO, NO>;
  for (std::size_t k = 0; k < 3; ++k)
    {
      const std::string name = system.block(k).name;
      const auto&       s    = settings.sublist(name);
      auto              A =
          MueLu::Utilities<SC, LO, GO, NO>::Op2NonConstTpetraCrs(system.blocked_matrix()->getMatrix(k, k));
      // M^-1 r: Ifpack2's smoother of that type, or the project's ILU(0) (ilu0_smoother.h)
      std::function<void(const TMV&, TMV&)> inverse;
      if (s.get<std::string>("type") == "ILU(0)")
        {
          auto factors = std::make_shared<Ilu0Factors>(system.blocked_matrix()->getMatrix(k, k),
                                                       ilu0_thresholds(s, "ParameterList", name));
          inverse      = [factors](const TMV& r, TMV& dx) {
            factors->solve(r.getData(0).get(), dx.getDataNonConst(0).get());
          };
        }
      else
        {
          auto smoother =
              Ifpack2::Factory::create<Tpetra::RowMatrix<SC, LO, GO, NO>>(s.get<std::string>("type"), A);
          auto params = s.sublist("ParameterList");
          smoother->setParameters(params);
          smoother->initialize();
          smoother->compute();
          inverse = [smoother](const TMV& r, TMV& dx) { smoother->apply(r, dx); };
        }
      // Error e = x* - x of x <- x + M^-1 (b - A x) from x = 0, b = A x*, x* random.
      TMV exact(A->getRowMap(), 1), x(A->getRowMap(), 1), b(A->getRowMap(), 1), r(A->getRowMap(), 1),
          dx(A->getRowMap(), 1);
      exact.randomize();
      A->apply(exact, b);
      x.putScalar(0.0);
      Teuchos::Array<double> e0(1), e(1);
      exact.norm2(e0);
      for (int it = 0; it < 3; ++it)
        {
          A->apply(x, r);
          r.update(1.0, b, -1.0);
          inverse(r, dx);
          x.update(1.0, dx, 1.0);
        }
      x.update(1.0, exact, -1.0);
      x.norm2(e);
      if (comm()->getRank() == 0)
        std::cout << "[ smoother   ] " << s.get<std::string>("type") << " on " << name
                  << ": ||e_3|| / ||e_0|| = " << e[0] / e0[0] << std::endl;
      EXPECT_LT(e[0] / e0[0], 0.7) << s.get<std::string>("type") << " on " << name;
    }
}

namespace
{
  using TpetraVector = Tpetra::MultiVector<SC, LO, GO, NO>;

  /// ||M1^-1 x - M2^-1 x|| / ||M2^-1 x|| for Ifpack2's RILUK with level of fill 0 (M2) and the
  /// project's ILU(0) (M1) of A, x random.
  double ilu0_against_riluk(const RCP<const Matrix>& A)
  {
    auto tA    = MueLu::Utilities<SC, LO, GO, NO>::Op2NonConstTpetraCrs(Teuchos::rcp_const_cast<Matrix>(A));
    auto riluk = Ifpack2::Factory::create<Tpetra::RowMatrix<SC, LO, GO, NO>>("RILUK", tA);
    Teuchos::ParameterList params;
    params.set("fact: iluk level-of-fill", 0);
    riluk->setParameters(params);
    riluk->initialize();
    riluk->compute();
    const Ilu0Factors ilu(A);
    TpetraVector      x(tA->getRowMap(), 1), y1(tA->getRowMap(), 1), y2(tA->getRowMap(), 1);
    x.randomize();
    riluk->apply(x, y2);
    ilu.solve(x.getData(0).get(), y1.getDataNonConst(0).get());
    Teuchos::Array<double> difference(1), reference(1);
    y2.norm2(reference);
    y1.update(-1.0, y2, 1.0);
    y1.norm2(difference);
    return difference[0] / reference[0];
  }

  /// A nonsymmetric tridiagonal matrix of n rows per rank, coupled only inside each rank (a
  /// pattern on which elimination fills nothing), with diagonal `first` in each rank's first row.
  RCP<Matrix> rank_local_tridiagonal(LO n, double first)
  {
    auto map =
        Tpetra::createContigMap<LO, GO>(Teuchos::OrdinalTraits<Tpetra::global_size_t>::invalid(), n, comm());
    auto A = Teuchos::rcp(new Tpetra::CrsMatrix<SC, LO, GO, NO>(map, 3));
    for (LO i = 0; i < n; ++i)
      {
        const GO        g = map->getGlobalElement(i);
        std::vector<GO> columns{g};
        std::vector<SC> values{i == 0 ? first : 3.0};
        if (i > 0)
          columns.push_back(g - 1), values.push_back(-1.3);
        if (i + 1 < n)
          columns.push_back(g + 1), values.push_back(-0.6);
        A->insertGlobalValues(g, Teuchos::ArrayView<const GO>(columns), Teuchos::ArrayView<const SC>(values));
      }
    A->fillComplete();
    return MueLu::TpetraCrs_To_XpetraMatrix(A);
  }
} // namespace

TEST(Ilu0, IsIfpack2sRilukWithoutFill)
{
  std::vector<RCP<const Matrix>> fluid{
      coupled_fields_2d(comm(), {2, false}).blocked_matrix()->getMatrix(1, 1)};
  for (const auto& dir : fsi_channel_systems()) // convection: nonsymmetric
    fluid.push_back(read_block_system(dir, comm()).blocked_matrix()->getMatrix(1, 1));
  ASSERT_GE(fluid.size(), 2u);
  for (std::size_t i = 0; i < fluid.size(); ++i)
    EXPECT_LT(ilu0_against_riluk(fluid[i]), 1e-12) << "fluid block " << i;
}

TEST(Ilu0, IsExactWhereEliminationFillsNothingAndNamesAZeroPivot)
{
  const auto        A = rank_local_tridiagonal(50, 2.0);
  const Ilu0Factors ilu(A);
  auto              exact = MVF::Build(A->getRowMap(), 1), b = MVF::Build(A->getRowMap(), 1),
       x = MVF::Build(A->getRowMap(), 1);
  exact->randomize();
  A->apply(*exact, *b);
  ilu.solve(b->getData(0).get(), x->getDataNonConst(0).get());
  x->update(-1.0, *exact, 1.0);
  EXPECT_LT(norm(*x), 1e-13 * norm(*exact));

  const auto        singular = rank_local_tridiagonal(50, 0.0);
  const std::string e        = error_of([&] { Ilu0Factors f(singular); });
  EXPECT_NE(e.find("ILU(0): pivot 0.000000 in local row 0 of 50"), std::string::npos) << e;
  EXPECT_NE(e.find("'fact: absolute threshold' > 0"), std::string::npos) << e;
  EXPECT_NO_THROW(Ilu0Factors(singular, Ilu0Thresholds{1.0, 1.0}));

  Teuchos::ParameterList fill;
  fill.set("fact: iluk level-of-fill", 1);
  Teuchos::ParameterList settings;
  settings.set("ParameterList", fill);
  const std::string f =
      error_of([&] { ilu0_thresholds(settings, "ParameterList", "block smoothers/fluid"); });
  EXPECT_NE(f.find("block smoothers/fluid: ILU(0) has no parameter 'fact: iluk level-of-fill'"),
            std::string::npos)
      << f;
}

TEST(Ilu0, TakesThePlaceholdersPlaceInEasyListHierarchies)
{
  // bgs(amg) builds every field's hierarchy from MueLu's easy-style list: with "ILU(0)" on the
  // fluid, one application equals the one with Ifpack2's RILUK(0) to round-off.
  const auto                    system = coupled_fields_2d(comm(), {2, false});
  std::vector<RCP<MultiVector>> y;
  for (const std::string type : {"ILU(0)", "RILUK"})
    {
      Preset preset = load_preset("bgs(amg)");
      apply_overrides(
          preset, {"block solvers/fluid/smoother: type=" + type, "block solvers/fluid/coarse: max size=100"});
      BlockPreconditioner M(system, preset);
      y.push_back(MVF::Build(system.full_map(), 1, true));
      M.op()->apply(*system.rhs(), *y.back());
    }
  const double reference = norm(*y[1]);
  y[0]->update(-1.0, *y[1], 1.0);
  EXPECT_LT(norm(*y[0]), 1e-12 * reference);

  // The same hierarchy set up again on its kept transfers keeps the project's ILU(0).
  const auto             A = Teuchos::rcp_const_cast<Matrix>(system.blocked_matrix()->getMatrix(1, 1));
  Teuchos::ParameterList list;
  list.set("max levels", 3);
  list.set("coarse: max size", 100);
  list.set("smoother: type", std::string("ILU(0)"));
  list.set("verbosity", std::string("none"));
  auto H        = build_single_field_hierarchy(A, 3, Teuchos::null, list, Teuchos::null, true);
  auto smoother = [&] {
    return H->GetLevel(0)->Get<RCP<MueLu::SmootherBase<SC, LO, GO, NO>>>("PreSmoother")->description();
  };
  EXPECT_EQ(smoother(), "ILU(0) (project)");
  ASSERT_GE(H->GetNumLevels(), 2);
  refresh_single_field_hierarchy(*H, A, list);
  EXPECT_EQ(smoother(), "ILU(0) (project)");
}

class NxnPresets : public ::testing::TestWithParam<std::string>
{
};

TEST_P(NxnPresets, SolveTheCoupledFieldsModelOnAllRanksAndOneAlike)
{
  const auto its = iterations_on_all_and_one_rank(
      [](RCP<const Comm> c) {
        return coupled_fields_2d(c, {2, false});
      },
      GetParam(), {});
  expect_iterations_within_ten_percent(its, GetParam() + " on coupled-fields-2d:2");
}

TEST_P(NxnPresets, SolveTheExportedFsiChannelSystems)
{
  // The channel systems are smaller than the preset's coarse size 6500: a smaller one makes the
  // fully coupled hierarchy multilevel.
  std::vector<std::string> overrides;
  if (GetParam().rfind("fully-coupled-", 0) == 0)
    overrides = {"coarse: max size=300"};
  const auto systems = fsi_channel_systems();
  ASSERT_GE(systems.size(), 2u) << "expected at least two Newton systems";
  for (const auto& dir : systems)
    {
      const auto its = iterations_on_all_and_one_rank(
          [&](RCP<const Comm> c) { return read_block_system(dir, c); }, GetParam(), overrides);
      expect_iterations_within_ten_percent(its, GetParam() + " on " + fs::path(dir).filename().string());
    }
}

INSTANTIATE_TEST_SUITE_P(FsiPresets, NxnPresets, ::testing::ValuesIn(nxn_presets),
                         test_helpers::PresetName());

TEST(FullyCoupledAmg, FourLevelsOnTheModelKeepTheTrueResidual)
{
  // With the seed's SA on the (saddle-point) fluid block too, this hierarchy made GMRES stop
  // after 16 iterations at a true residual of 5e-6 (see the preset file).
  const auto system = coupled_fields_2d(comm(), {3, false});
  Preset     preset = load_preset("fully-coupled-sa-amg(bgs)");
  apply_overrides(preset, {"coarse: max size=500"});
  BlockPreconditioner M(system, preset);
  EXPECT_EQ(M.info().levels.size(), 4u);
  auto         x = MVF::Build(system.full_map(), 1, true);
  SolveOptions options;
  options.tolerance = 1e-6;
  const auto report = solve(system, M, *x, options);
  EXPECT_TRUE(report.converged) << report.failure;
  EXPECT_LT(report.relative_residual, 1e-6);
  EXPECT_LT(report.iterations, 15);
}

TEST(FullyCoupledAmg, SmoothingAcrossFieldsSolvesTheModelAndTheChannelOnAllRanksAndOneAlike)
{
  // "prolongator: smoothing = across fields" (coupled_prolongator.h): P no longer block-diagonal,
  // the Galerkin products by the project's BlockedGalerkinFactory (MueLu's fails on three blocks).
  const std::vector<std::string> model = {"coarse: max size=500", "prolongator: smoothing=across fields"};
  const auto                     its   = iterations_on_all_and_one_rank(
      [](RCP<const Comm> c) {
        return coupled_fields_2d(c, {3, false});
      },
      "fully-coupled-sa-amg(bgs)", model);
  expect_iterations_within_ten_percent(its, "across fields on coupled-fields-2d:3");
  EXPECT_LT(its.first, 15);
  const auto systems = fsi_channel_systems();
  ASSERT_FALSE(systems.empty());
  const auto channel = iterations_on_all_and_one_rank(
      [&](RCP<const Comm> c) { return read_block_system(systems.front(), c); }, "fully-coupled-sa-amg(bgs)",
      {"coarse: max size=300", "prolongator: smoothing=across fields"});
  expect_iterations_within_ten_percent(channel,
                                       "across fields on " + fs::path(systems.front()).filename().string());
}

TEST(FullyCoupledAmg, ProjectBlockGaussSeidelIsMueLusIteration)
{
  // The project's level smoother (block_gauss_seidel_smoother.h) against MueLu's
  // BlockedGaussSeidelSmoother: the same V-cycle on a 3-level hierarchy, for 1 and 3 sweeps, to
  // round-off (the project's skips products with zero blocks of the start and the sub-smoothers'
  // residuals of a zero guess, which are exact zeros there).
  const auto system = coupled_fields_2d(comm(), {2, false});
  for (const std::string sweeps : {"1", "3"})
    {
      std::vector<RCP<MultiVector>> y;
      for (const std::string implementation : {"project", "muelu"})
        {
          Preset preset = load_preset("fully-coupled-sa-amg(bgs)");
          apply_overrides(preset, {"coarse: max size=500", "smoother: sweeps=" + sweeps,
                                   "smoother: implementation=" + implementation});
          BlockPreconditioner M(system, preset);
          ASSERT_GE(M.info().levels.size(), 3u) << implementation;
          y.push_back(MVF::Build(system.full_map(), 1, true));
          M.op()->apply(*system.rhs(), *y.back());
        }
      const double reference = norm(*y[1]);
      y[0]->update(-1.0, *y[1], 1.0);
      EXPECT_LT(norm(*y[0]), 1e-12 * reference) << sweeps << " sweeps";
    }
  Preset preset = load_preset("fully-coupled-sa-amg(bgs)");
  apply_overrides(preset, {"smoother: implementation=mine"});
  const std::string e = error_of([&] { BlockPreconditioner M(system, preset); });
  EXPECT_NE(e.find("'smoother: implementation' is 'mine', expected project or muelu"), std::string::npos)
      << e;
}

TEST(FullyCoupledAmg, FieldTooSmallToAggregateIsAOneLineError)
{
  const auto system = coupled_fields_2d(comm(), {1, false});
  Preset     preset = load_preset("fully-coupled-sa-amg(bgs)");
  apply_overrides(preset, {"coarse: max size=100", "aggregation: min agg size=1000"});
  const std::string e = error_of([&] { BlockPreconditioner M(system, preset); });
  EXPECT_NE(e.find("block 'structure' has 289 nodes, fewer than one aggregate"), std::string::npos) << e;
  EXPECT_EQ(e.find('\n'), std::string::npos) << e;
}

TEST(FullyCoupledAmg, DivergingLevelSmootherIsAOneLineError)
{
  const auto system = coupled_fields_2d(comm(), {1, false});
  Preset     preset = load_preset("fully-coupled-sa-amg(bgs)");
  apply_overrides(preset, {"coarse: max size=100", "smoother: damping=30"});
  const std::string e = error_of([&] { BlockPreconditioner M(system, preset); });
  EXPECT_NE(e.find("the level smoother does not contract"), std::string::npos) << e;
  EXPECT_EQ(e.find('\n'), std::string::npos) << e;
  // The set-ups after a run's first one skip the check (SetupOptions::check_level_smoother) and
  // say so in their report.
  SetupOptions later;
  later.check_level_smoother = false;
  const BlockPreconditioner M(system, preset, later);
  EXPECT_EQ(M.info().notes.back(), "level smoother: contraction not checked in this set-up");
}

TEST(FullyCoupledAmg, BlockWithoutNullspaceFallsBackToTranslations)
{
  auto system               = coupled_fields_2d(comm(), {2, false});
  system.block(0).nullspace = Teuchos::null; // structure: translations instead of rigid-body modes
  EXPECT_EQ(system.nullspace_or_translations(0)->getNumVectors(), 2u);
  Preset              preset = load_preset("fully-coupled-sa-amg(bgs)");
  BlockPreconditioner M(system, preset);
  auto                x = MVF::Build(system.full_map(), 1, true);
  SolveOptions        options;
  options.tolerance = 1e-6;
  EXPECT_TRUE(solve(system, M, *x, options).converged);
}

namespace
{
  /// Whether block `follower`'s aggregates are block `leader`'s on every coarse level where their
  /// nodes lie at the same positions: two such follower nodes share a level-l aggregate exactly
  /// when their leader nodes do; nodes in no aggregate (Dirichlet nodes) and nodes without a node
  /// of the other block at their position are left aside. Counts the pairs of aggregates
  /// (follower, leader) that break the one-to-one correspondence, over all levels and ranks.
  long long aggregates_differing(const BlockSystem& system, const BlockPreconditioner& M,
                                 std::size_t follower, std::size_t leader)
  {
    auto positions = [](const BlockInfo& b) {
      std::vector<double> x;
      for (std::size_t i = 0; i < b.coordinates->getLocalLength(); ++i)
        for (std::size_t c = 0; c < b.coordinates->getNumVectors(); ++c)
          x.push_back(b.coordinates->getData(c)[i]);
      return x;
    };
    const auto fluid_node =
        same_positions(positions(system.block(follower)), positions(system.block(leader)), 2, 1e-9);
    const auto& fluid      = M.aggregates().at(leader).levels;
    const auto& ale        = M.aggregates().at(follower).levels;
    long long   differing  = 0;
    for (std::size_t l = 1; l < ale.size(); ++l)
      {
        std::map<GO, GO> ale_to_fluid, fluid_to_ale;
        for (std::size_t i = 0; i < fluid_node.size(); ++i)
          if (ale[l][i] >= 0 && fluid_node[i] >= 0)
            {
              const GO a = ale[l][i], f = fluid[l][fluid_node[i]];
              differing += ale_to_fluid.emplace(a, f).first->second != f;
              differing += fluid_to_ale.emplace(f, a).first->second != a;
            }
      }
    Teuchos::reduceAll(*comm(), Teuchos::REDUCE_SUM, differing, Teuchos::outArg(differing));
    return differing;
  }

  /// The fully coupled SA preset with coarse size 200 (4 levels on coupled-fields-2d:3) and one
  /// "block aggregates" setting, its aggregates kept.
  std::unique_ptr<BlockPreconditioner> with_block_aggregates(const BlockSystem& system,
                                                             const std::string& setting)
  {
    Preset preset = load_preset("fully-coupled-sa-amg(bgs)");
    apply_overrides(preset, {"coarse: max size=200", "block aggregates/" + setting});
    SetupOptions keep;
    keep.keep_aggregates = true;
    return std::make_unique<BlockPreconditioner>(system, preset, keep);
  }

  /// The set-up's note that contains `text` ("" and a failure if there is none).
  std::string note_with(const BlockPreconditioner& M, const std::string& text)
  {
    for (const auto& note : M.info().notes)
      if (note.find(text) != std::string::npos)
        return note;
    ADD_FAILURE() << "no note with '" << text << "'";
    return "";
  }

  /// GMRES with M reaches 1e-6 on the system in fewer than 15 iterations.
  void expect_fast_solve(const BlockSystem& system, const BlockPreconditioner& M)
  {
    auto         x = MVF::Build(system.full_map(), 1, true);
    SolveOptions options;
    options.tolerance = 1e-6;
    const auto report = solve(system, M, *x, options);
    EXPECT_TRUE(report.converged) << report.failure;
    EXPECT_LT(report.iterations, 15);
  }
} // namespace

TEST(FullyCoupledAmg, AleTakesTheFluidsAggregatesOnEveryLevel)
{
  // coupled-fields-2d: the ALE field lives on the fluid's grid. With "block aggregates/ale=fluid"
  // both fields coarsen onto one coarse grid (a 4-level hierarchy: 3 coarse levels checked); on
  // their own they do not, which shows that the check can fail.
  const auto system = coupled_fields_2d(comm(), {3, false});
  for (const std::string ale : {"fluid", "own"})
    {
      const auto  preconditioner = with_block_aggregates(system, "ale=" + ale);
      const auto& M              = *preconditioner;
      ASSERT_EQ(M.info().levels.size(), 4u) << ale;
      const long long differing = aggregates_differing(system, M, 2, 1);
      if (ale == "fluid")
        {
          EXPECT_EQ(differing, 0);
          // the ALE grid's fixed column x = 2 (identity rows) is in no aggregate: per coarse node
          // of the fluid (3 DOFs) at most one of the ALE (2 DOFs)
          for (std::size_t l = 1; l < 4; ++l)
            EXPECT_LE(M.info().levels[l].block_rows[2] * 3, M.info().levels[l].block_rows[1] * 2) << l;
          const auto note = note_with(M, "block 'ale' takes the aggregates of 'fluid'");
          EXPECT_NE(note.find("4225 of 4225 nodes matched"), std::string::npos) << note;
          expect_fast_solve(system, M);
        }
      else
        EXPECT_GT(differing, 0);
    }
  // a leader that is no block before the follower, and one without positions
  Preset preset = load_preset("fully-coupled-sa-amg(bgs)");
  apply_overrides(preset, {"coarse: max size=200", "block aggregates/ale=water"});
  std::string e = error_of([&] { BlockPreconditioner M(system, preset); });
  EXPECT_NE(e.find("'block aggregates/ale' = 'water' names no block before 'ale'"), std::string::npos) << e;
  auto without                 = coupled_fields_2d(comm(), {3, false});
  without.block(1).coordinates = Teuchos::null;
  apply_overrides(preset, {"block aggregates/ale=fluid"});
  e = error_of([&] { BlockPreconditioner M(without, preset); });
  EXPECT_NE(e.find("block 'fluid' has no coordinates"), std::string::npos) << e;
  EXPECT_EQ(e.find('\n'), std::string::npos) << e;
  // the coarse-level rebalancing does not move the follower's node mapping
  apply_overrides(preset, {"repartition/enable=true"});
  e = error_of([&] { BlockPreconditioner M(system, preset); });
  EXPECT_NE(e.find("which the coarse-level rebalancing does not support yet"), std::string::npos) << e;
}

TEST(FullyCoupledAmg, FluidTakesTheStructuresInterfaceAggregatesAndAggregatesTheRest)
{
  // coupled-fields-2d: the fluid grid's column x = 1 lies on the structure's. With "block
  // aggregates/fluid=structure" the fluid's interface nodes take the structure's aggregates on
  // every level (one coarse interface), its other nodes are aggregated on its own graph (no
  // one-node aggregates, as the plain follower would make them) and grow those aggregates.
  const auto system = coupled_fields_2d(comm(), {3, false});
  for (const std::string fluid : {"structure", "own"})
    {
      const auto  preconditioner = with_block_aggregates(system, "fluid=" + fluid);
      const auto& M              = *preconditioner;
      ASSERT_EQ(M.info().levels.size(), 4u) << fluid;
      const long long differing = aggregates_differing(system, M, 1, 0);
      if (fluid == "own")
        {
          EXPECT_GT(differing, 0); // the check can fail
          continue;
        }
      EXPECT_EQ(differing, 0);
      // 65 x 65 fluid nodes, the column x = 1 matched (on 2 ranks: each rank its own part of it)
      const auto note = note_with(M, "block 'fluid' takes the aggregates of 'structure'");
      EXPECT_NE(note.find(" of 4225 nodes matched (the others aggregated on its own graph)"),
                std::string::npos)
          << note;
      // level 1: no one-node fluid aggregate, more than 4 nodes per aggregate on average (a coarse
      // fluid node has 3 DOFs)
      const auto&       fluid_levels = M.aggregates().at(1).levels;
      std::map<GO, int> size;
      for (const GO a : fluid_levels.at(1))
        if (a >= 0)
          ++size[a];
      long long singletons =
          std::count_if(size.begin(), size.end(), [](const auto& s) { return s.second == 1; });
      Teuchos::reduceAll(*comm(), Teuchos::REDUCE_SUM, singletons, Teuchos::outArg(singletons));
      EXPECT_EQ(singletons, 0);
      EXPECT_LT(M.info().levels[1].block_rows[1], 3 * 4225 / 4);
      expect_fast_solve(system, M);
    }
}

TEST(NodeInterfaceAggregation, FreeNodesAreAggregatedAndGrowTheCopiedAggregates)
{
  // a path 0 - 1 - ... - 9: node 0 in copied aggregate 0, node 9 excluded (a Dirichlet node)
  std::vector<std::vector<LO>> path(10);
  for (LO i = 0; i + 1 < 10; ++i)
    {
      path[i].push_back(i + 1);
      path[i + 1].push_back(i);
    }
  std::vector<LO>   aggregate(10, -1);
  std::vector<bool> excluded(10, false);
  aggregate[0] = 0;
  excluded[9]  = true;
  const LO n   = aggregate_free_nodes(path, aggregate, excluded, 1);
  // node 1 touches the copied node, so the roots are 2 {1, 2, 3}, 5 {4, 5, 6} and 8 {7, 8}
  // (the excluded neighbour 9 neither stops a root nor joins it)
  EXPECT_EQ(aggregate[0], 0);
  EXPECT_EQ(aggregate[9], -1);
  for (LO i = 1; i < 9; ++i)
    EXPECT_GE(aggregate[i], 0) << i;
  EXPECT_EQ(n, 4);
  EXPECT_EQ(aggregate[1], aggregate[2]);
  EXPECT_EQ(aggregate[2], aggregate[3]);
  EXPECT_EQ(aggregate[4], aggregate[6]);
  EXPECT_EQ(aggregate[7], aggregate[8]);
  // a star: the free centre's neighbours are all copied -> it joins the one it has most edges to
  std::vector<std::vector<LO>> star{{1, 2, 3}, {0}, {0}, {0}};
  std::vector<LO>              star_aggregate{-1, 0, 1, 1};
  EXPECT_EQ(aggregate_free_nodes(star, star_aggregate, std::vector<bool>(4, false), 2), 2);
  EXPECT_EQ(star_aggregate[0], 1);
  // the copied aggregates grow by a layer: a copied node with a free neighbour that is no root
  std::vector<std::vector<LO>> two{{1}, {0}};
  std::vector<LO>              two_aggregate{0, -1};
  EXPECT_EQ(aggregate_free_nodes(two, two_aggregate, std::vector<bool>(2, false), 1), 1);
  EXPECT_EQ(two_aggregate[1], 0);
}
