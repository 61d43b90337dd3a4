// The FSI class's fluid alone (physics/fsi/ale_fluid.h, fluid_flow.h): the AD Jacobian against
// finite differences (fluid unknowns on a moving mesh, and the shape derivative), steady
// Poiseuille flow in a 2D channel and a 3D pipe, the convergence orders on Kovasznay flow (Re = 40), and
// geometric conservation: a fluid at rest, or in uniform motion with its mesh, on a deforming
// mesh stays so to round-off; the same on fully distributed meshes. Runs on 1 and 2 ranks;
// prints the measured numbers.
#include "common/distributed_mesh.h"
#include "common/newton_solver.h"
#include "common/step_driver.h"
#include "fsi/fluid_flow.h"
#include "fsi_test_helpers.h"

#include <deal.II/base/function.h>
#include <deal.II/base/mpi.h>
#include <deal.II/base/timer.h>
#include <deal.II/base/quadrature_lib.h>
#include <deal.II/distributed/fully_distributed_tria.h>
#include <deal.II/distributed/tria.h>
#include <deal.II/fe/fe_values.h>
#include <deal.II/dofs/dof_tools.h>
#include <deal.II/fe/fe_q.h>
#include <deal.II/fe/fe_system.h>
#include <deal.II/grid/grid_generator.h>
#include <deal.II/lac/dynamic_sparsity_pattern.h>
#include <deal.II/lac/sparsity_tools.h>
#include <deal.II/numerics/vector_tools.h>

#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <iomanip>
#include <iostream>
#include <memory>
#include <numeric>

using namespace dealii;

namespace
{
  using physics::fsi::FluidFlow;
  using physics::fsi::FluidFlowSetup;
  using physics::fsi::FluidTimeScheme;
  using Vec = TrilinosWrappers::MPI::Vector;

  const MPI_Comm comm = MPI_COMM_WORLD;

  using fsi_test::root;
  using fsi_test::solve;

  physics::StepSettings one_step()
  {
    return physics::StepSettings{1.0, 1.0, 0.0, 0, 0, 0, "", ""};
  }

  /// Poiseuille flow in [0, L] x [0, H]: u = 4 U y (H - y) / H^2, p = G (L - x), G = 8 mu U / H^2.
  class Poiseuille : public Function<2>
  {
  public:
    Poiseuille(double U, double H, double L, double mu)
        : Function<2>(3)
        , U_(U)
        , H_(H)
        , L_(L)
        , G_(8 * mu * U / (H * H))
    {
    }
    double value(const Point<2>& x, unsigned int c) const override
    {
      return c == 0 ? 4 * U_ * x[1] * (H_ - x[1]) / (H_ * H_) : c == 1 ? 0.0 : G_ * (L_ - x[0]);
    }
    Tensor<1, 2> gradient(const Point<2>& x, unsigned int c) const override
    {
      Tensor<1, 2> g;
      if (c == 0)
        g[1] = 4 * U_ * (H_ - 2 * x[1]) / (H_ * H_);
      if (c == 2)
        g[0] = -G_;
      return g;
    }

  private:
    double U_, H_, L_, G_;
  };

  /// Hagen-Poiseuille flow in a pipe along x of radius R (mean velocity U): u = 2 U (1 - r^2 / R^2)
  /// e_x, p = G (L - x), G = 8 mu U / R^2.
  class PipePoiseuille : public Function<3>
  {
  public:
    PipePoiseuille(double U, double R, double L, double mu)
        : Function<3>(4)
        , U_(U)
        , R_(R)
        , L_(L)
        , G_(8 * mu * U / (R * R))
    {
    }
    double value(const Point<3>& x, unsigned int c) const override
    {
      const double r2 = x[1] * x[1] + x[2] * x[2];
      return c == 0 ? 2 * U_ * (1 - r2 / (R_ * R_)) : c == 3 ? G_ * (L_ - x[0]) : 0.0;
    }
    Tensor<1, 3> gradient(const Point<3>& x, unsigned int c) const override
    {
      Tensor<1, 3> g;
      if (c == 0)
        for (unsigned d = 1; d < 3; ++d)
          g[d] = -4 * U_ * x[d] / (R_ * R_);
      if (c == 3)
        g[0] = -G_;
      return g;
    }

  private:
    double U_, R_, L_, G_;
  };

  /// Kovasznay's exact solution of the steady Navier-Stokes equations (nu = 1/Re).
  class Kovasznay : public Function<2>
  {
  public:
    explicit Kovasznay(double Re)
        : Function<2>(3)
        , l_(Re / 2 - std::sqrt(Re * Re / 4 + 4 * M_PI * M_PI))
    {
    }
    double value(const Point<2>& x, unsigned int c) const override
    {
      const double e = std::exp(l_ * x[0]), y = 2 * M_PI * x[1];
      return c == 0 ? 1 - e * std::cos(y) : c == 1 ? l_ / (2 * M_PI) * e * std::sin(y) : -0.5 * e * e;
    }
    Tensor<1, 2> gradient(const Point<2>& x, unsigned int c) const override
    {
      const double e = std::exp(l_ * x[0]), y = 2 * M_PI * x[1];
      Tensor<1, 2> g;
      if (c == 0)
        g = Tensor<1, 2>({-l_ * e * std::cos(y), 2 * M_PI * e * std::sin(y)});
      else if (c == 1)
        g = Tensor<1, 2>({l_ * l_ / (2 * M_PI) * e * std::sin(y), l_ * e * std::cos(y)});
      else
        g[0] = -l_ * e * e;
      return g;
    }

  private:
    double l_;
  };

  /// A deforming mesh motion that keeps the boundary of [0, 1]^2 fixed, plus a uniform
  /// translation V t (dim = 2 components).
  class DeformingMotion : public Function<2>
  {
  public:
    explicit DeformingMotion(Tensor<1, 2> V = {})
        : Function<2>(2)
        , V_(V)
    {
    }
    double value(const Point<2>& X, unsigned int c) const override
    {
      const double t = get_time(), bump = std::sin(M_PI * X[0]) * std::sin(M_PI * X[1]);
      return 0.15 * bump * std::sin(3 * M_PI * t) * (c == 0 ? 1.0 : -0.7) + V_[c] * t;
    }

  private:
    Tensor<1, 2> V_;
  };

  /// The top wall of [0, 1]^2 bulges in and out, the other walls stay (plus a translation V t).
  class WallMotion : public Function<2>
  {
  public:
    explicit WallMotion(Tensor<1, 2> V = {})
        : Function<2>(2)
        , V_(V)
    {
    }
    double value(const Point<2>& X, unsigned int c) const override
    {
      const double t = get_time();
      return (c == 1 ? 0.2 * X[1] * std::sin(M_PI * X[0]) * std::sin(3 * M_PI * t) : 0.0) + V_[c] * t;
    }

  private:
    Tensor<1, 2> V_;
  };

  void channel(Triangulation<2>& tria, unsigned nx, unsigned ny, double L, double H)
  {
    GridGenerator::subdivided_hyper_rectangle(tria, {nx, ny}, Point<2>(), Point<2>(L, H), true);
  }

  /// ||a - b|| / ||b||
  double relative_difference(const Vec& a, const Vec& b)
  {
    Vec d(a);
    d.add(-1.0, b);
    return d.l2_norm() / b.l2_norm();
  }

  /// A state of many scales on `n` DOFs: smooth plus pseudo-random, amplitude `a`.
  Vec perturbed(const IndexSet& all, double a, double seed)
  {
    Vec v(all, MPI_COMM_SELF);
    for (const auto i : all)
      v[i] = a * (std::sin(seed + 1.3 * i) + 0.5 * std::cos(seed * i));
    return v;
  }

  TEST(FsiFluid, JacobianAndShapeDerivativeMatchFiniteDifferences)
  {
    // The assembler alone, serial on every rank: BDF2 on a deforming, translating mesh, a
    // pressure boundary, a state that is no solution; no constraints, so every row is checked.
    Triangulation<2> tria;
    GridGenerator::subdivided_hyper_rectangle(tria, {5, 4}, Point<2>(), Point<2>(1.0, 0.8), true);
    const FESystem<2> fluid_fe(FE_Q<2>(1), 3), mesh_fe(FE_Q<2>(1), 2);
    DoFHandler<2>     fluid(tria), mesh(tria);
    fluid.distribute_dofs(fluid_fe);
    mesh.distribute_dofs(mesh_fe);
    const IndexSet fluid_all = complete_index_set(fluid.n_dofs()),
                   mesh_all  = complete_index_set(mesh.n_dofs());
    const AffineConstraints<double> none_fluid, none_mesh;
    DynamicSparsityPattern          ff(fluid.n_dofs()), fm(fluid.n_dofs(), mesh.n_dofs());
    DoFTools::make_sparsity_pattern(fluid, ff);
    std::vector<types::global_dof_index> fi(fluid_fe.n_dofs_per_cell()), mi(mesh_fe.n_dofs_per_cell());
    for (const auto& cell : fluid.active_cell_iterators())
      {
        cell->get_dof_indices(fi);
        typename DoFHandler<2>::active_cell_iterator(&tria, cell->level(), cell->index(), &mesh)
            ->get_dof_indices(mi);
        for (const auto i : fi)
          for (const auto j : mi)
            fm.add(i, j);
      }
    TrilinosWrappers::SparseMatrix K, S;
    K.reinit(fluid_all, fluid_all, ff, MPI_COMM_SELF);
    S.reinit(fluid_all, mesh_all, fm, MPI_COMM_SELF);

    physics::fsi::FluidModel<2> model;
    model.properties            = {2.0, 0.05};
    model.scheme                = FluidTimeScheme::bdf2;
    model.time_step             = 0.1;
    model.boundary_pressures[1] = 0.3;
    Vec u = perturbed(fluid_all, 1.0, 0.3), u_old = perturbed(fluid_all, 0.8, 0.7),
        u_older = perturbed(fluid_all, 0.6, 1.1);
    Vec d = perturbed(mesh_all, 0.02, 0.2), d_old = perturbed(mesh_all, 0.015, 0.5),
        d_older   = perturbed(mesh_all, 0.01, 0.9);
    auto residual = [&](const Vec& uu, const Vec& dd, TrilinosWrappers::SparseMatrix* KK,
                        TrilinosWrappers::SparseMatrix* SS) {
      physics::fsi::FluidState<2> state{&uu, &u_old, &u_older, &dd, &d_old, &d_older};
      Vec                         r(fluid_all, MPI_COMM_SELF);
      if (KK != nullptr)
        *KK = 0;
      if (SS != nullptr)
        *SS = 0;
      physics::fsi::assemble_ale_fluid<2>(fluid, &mesh, model, state, none_fluid, r, KK, SS, &none_mesh);
      return r;
    };
    residual(u, d, &K, &S);

    const double eps = 1e-6;
    // dR/du v against central differences.
    const Vec v = perturbed(fluid_all, 1.0, 2.3);
    Vec       up(u), um(u), Kv(fluid_all, MPI_COMM_SELF);
    up.add(eps, v);
    um.add(-eps, v);
    Vec fd = residual(up, d, nullptr, nullptr);
    fd.add(-1.0, residual(um, d, nullptr, nullptr));
    fd /= 2 * eps;
    K.vmult(Kv, v);
    const double jacobian_error = relative_difference(fd, Kv);
    // dR/dd^G e (the shape derivative) against central differences.
    const Vec e = perturbed(mesh_all, 1.0, 4.1);
    Vec       dp(d), dm(d), Se(fluid_all, MPI_COMM_SELF);
    dp.add(eps, e);
    dm.add(-eps, e);
    Vec fd_shape = residual(u, dp, nullptr, nullptr);
    fd_shape.add(-1.0, residual(u, dm, nullptr, nullptr));
    fd_shape /= 2 * eps;
    S.vmult(Se, e);
    const double shape_error = relative_difference(fd_shape, Se);
    if (root())
      std::cout << "fluid Jacobian vs finite differences: relative error " << jacobian_error
                << "; shape derivative: " << shape_error << "\n";
    EXPECT_LT(jacobian_error, 1e-6);
    EXPECT_LT(shape_error, 1e-6);
    EXPECT_GT(Kv.l2_norm(), 0.0);
    EXPECT_GT(Se.l2_norm(), 0.0);
  }

  TEST(FsiFluid, SteadyPoiseuilleInAChannel)
  {
    const double U = 1.0, H = 1.0, L = 2.0, mu = 0.1, rho = 1.0;
    double       previous = 0;
    for (const unsigned n : {4u, 8u, 16u})
      {
        parallel::distributed::Triangulation<2> tria(comm);
        channel(tria, 2 * n, n, L, H);
        FluidFlowSetup<2> s;
        s.model.properties = {rho, mu};
        auto exact         = std::make_shared<Poiseuille>(U, H, L, mu);
        for (types::boundary_id b = 0; b < 4; ++b)
          s.velocity[b] = exact;
        s.pressure_point = std::make_pair(Point<2>(L, 0.0), exact);
        FluidFlow<2> flow(tria, s, comm);
        const auto   result = solve(flow, one_step());
        ASSERT_TRUE(result.converged) << result.failure;
        const auto e = flow.errors(*exact);
        if (root())
          std::cout << "Poiseuille " << 2 * n << " x " << n << ": Newton steps "
                    << result.newton[0].iterations << ", ||u - u_h|| = " << e.velocity_l2
                    << ", |u - u_h|_1 = " << e.velocity_h1 << ", ||p - p_h|| = " << e.pressure_l2 << "\n";
        // Not exact: Q1 cannot represent the viscous term of the strong residual (zero on each
        // cell), so PSPG/SUPG see r_M = grad p = -G e_x instead of 0, an O(tau) = O(h^2) error.
        if (previous > 0) // second order in the velocity under refinement
          {
            EXPECT_LT(e.velocity_l2, previous / 3.0);
          }
        previous = e.velocity_l2;
      }
    EXPECT_LT(previous, 0.02);
  }

  TEST(FsiFluid, SteadyPoiseuilleInAPipe)
  {
    // deal.II's cylinder along x (radius R, x in [-L, L]; boundary ids 0 the wall, 1 and 2 the
    // ends), refined with its cylindrical manifold, so the wall nodes lie on the circle: the
    // exact velocity on every boundary, the pressure at the outlet's centre.
    const double U = 1.0, R = 0.5, L = 1.0, mu = 0.1, rho = 1.0;
    double       previous = 0;
    for (const unsigned refinements : {1u, 2u, 3u})
      {
        parallel::distributed::Triangulation<3> tria(comm);
        GridGenerator::cylinder(tria, R, L);
        tria.refine_global(refinements);
        FluidFlowSetup<3> s;
        s.model.properties = {rho, mu};
        auto exact         = std::make_shared<PipePoiseuille>(U, R, L, mu);
        for (types::boundary_id b = 0; b < 3; ++b)
          s.velocity[b] = exact;
        s.pressure_point = std::make_pair(Point<3>(L, 0.0, 0.0), exact);
        FluidFlow<3> flow(tria, s, comm);
        const auto   result = solve(flow, one_step());
        ASSERT_TRUE(result.converged) << result.failure;
        const auto e = flow.errors(*exact);
        if (root())
          std::cout << "Pipe Poiseuille, " << tria.n_global_active_cells() << " cells: Newton steps "
                    << result.newton[0].iterations << ", ||u - u_h|| = " << e.velocity_l2
                    << ", |u - u_h|_1 = " << e.velocity_h1 << ", ||p - p_h|| = " << e.pressure_l2 << "\n";
        // Not exact either (as in the channel, and the wall is a polygon through the circle's
        // nodes): measured ||u - u_h|| 0.502, 0.190, 0.058 (ratios 2.6 and 3.3: second order
        // reached from the second refinement on; 4 % of ||u|| = 1.45 at 5120 cells).
        if (previous > 0)
          {
            EXPECT_LT(e.velocity_l2, previous / (refinements == 2 ? 2.5 : 3.0));
          }
        previous = e.velocity_l2;
      }
    EXPECT_LT(previous, 0.06);
  }

  TEST(FsiFluid, KovasznayConvergenceOrders)
  {
    // Re = 40 on [-0.5, 1] x [-0.5, 1.5], the exact velocity on the whole boundary, the pressure
    // fixed at one corner; errors on three meshes and the observed orders of the finest pair.
    const double                          Re = 40.0;
    std::vector<physics::fsi::FlowErrors> errors;
    std::vector<double>                   h;
    for (const unsigned n : {8u, 16u, 32u})
      {
        parallel::distributed::Triangulation<2> tria(comm);
        GridGenerator::subdivided_hyper_rectangle(tria, {3 * n / 2, 2 * n}, Point<2>(-0.5, -0.5),
                                                  Point<2>(1.0, 1.5), true);
        FluidFlowSetup<2> s;
        s.model.properties = {1.0, 1.0 / Re};
        auto exact         = std::make_shared<Kovasznay>(Re);
        for (types::boundary_id b = 0; b < 4; ++b)
          s.velocity[b] = exact;
        s.pressure_point = std::make_pair(Point<2>(-0.5, -0.5), exact);
        FluidFlow<2> flow(tria, s, comm);
        Timer        timer;
        const auto   result = solve(flow, one_step());
        ASSERT_TRUE(result.converged) << result.failure;
        errors.push_back(flow.errors(*exact));
        h.push_back(1.0 / n);
        if (root())
          std::cout << "Kovasznay h = 1/" << n << " (" << flow.dof_handler().n_dofs()
                    << " DOFs): Newton steps " << result.newton[0].iterations << ", " << timer.wall_time()
                    << " s, ||u - u_h|| = " << errors.back().velocity_l2
                    << ", |u - u_h|_1 = " << errors.back().velocity_h1
                    << ", ||p - p_h|| = " << errors.back().pressure_l2 << "\n";
      }
    for (std::size_t k = 1; k < errors.size(); ++k)
      {
        const double r    = std::log(h[k - 1] / h[k]);
        const double u_l2 = std::log(errors[k - 1].velocity_l2 / errors[k].velocity_l2) / r;
        const double u_h1 = std::log(errors[k - 1].velocity_h1 / errors[k].velocity_h1) / r;
        const double p_l2 = std::log(errors[k - 1].pressure_l2 / errors[k].pressure_l2) / r;
        if (root())
          std::cout << "Kovasznay orders (h = 1/" << 8 * (1 << (k - 1)) << " -> 1/" << 8 * (1 << k)
                    << "): velocity L2 " << u_l2 << ", velocity H1 " << u_h1 << ", pressure L2 " << p_l2
                    << "\n";
        // Q1/Q1: 2 for the velocity in L2 (reached from below: at Re = 40 the cell Peclet numbers
        // are near 1 here, where tau is still O(h), not O(h^2)), 1 in H1, 1.5 for p (observed).
        if (k + 1 == errors.size())
          {
            EXPECT_GT(u_l2, 1.65);
            EXPECT_GT(u_h1, 0.95);
            EXPECT_GT(p_l2, 1.4);
          }
      }
  }

  /// Geometric conservation: the state u = V (uniform, the pressure zero) on the unit square,
  /// whose mesh translates with V and deforms (inside only, or pseudo-elastically with a moving
  /// wall), stays so over BDF steps.
  /// `mesh` (a serial-mesh generator) on a parallel::distributed triangulation, or on a fully
  /// distributed one (common/distributed_mesh.h: only cells and one ghost layer per rank).
  std::unique_ptr<Triangulation<2>> distributed(const std::function<void(Triangulation<2>&)>& mesh,
                                                bool fully_distributed)
  {
    if (!fully_distributed)
      {
        auto tria = std::make_unique<parallel::distributed::Triangulation<2>>(comm);
        mesh(*tria);
        return tria;
      }
    auto tria = std::make_unique<parallel::fullydistributed::Triangulation<2>>(comm);
    physics::create_distributed_mesh<2>(*tria, mesh);
    return tria;
  }

  void check_uniform_state_preserved(Tensor<1, 2> V, FluidTimeScheme scheme, bool pseudo_elastic,
                                     bool fully_distributed = false)
  {
    const auto tria =
        distributed([](Triangulation<2>& t) { GridGenerator::subdivided_hyper_cube(t, 6, 0.0, 1.0, true); },
                    fully_distributed);
    FluidFlowSetup<2> s;
    s.model.properties = {1.0, 0.01};
    s.model.scheme     = scheme;
    s.model.theta      = 0.5;
    auto state = std::make_shared<Functions::ConstantFunction<2>>(std::vector<double>{V[0], V[1], 0.0});
    for (types::boundary_id b = 0; b < 4; ++b)
      s.velocity[b] = state;
    s.pressure_point = std::make_pair(Point<2>(0.0, 0.0), state);
    if (pseudo_elastic)
      {
        s.mesh_motion    = std::make_shared<WallMotion>(V);
        s.pseudo_elastic = physics::fsi::MeshMotionSettings{};
      }
    else
      s.mesh_motion = std::make_shared<DeformingMotion>(V);
    FluidFlow<2> flow(*tria, s, comm);
    flow.set_initial_state(*state);
    const auto result = solve(flow, physics::StepSettings{0.5, 0.05, 0.0, 0, 0, 0, "", ""});
    ASSERT_TRUE(result.converged) << result.failure;
    Vec exact(flow.owned_dofs(), comm);
    VectorTools::interpolate(flow.dof_handler(), *state, exact);
    Vec difference(exact);
    difference.add(-1.0, flow.owned_solution());
    const double deviation = difference.linfty_norm();
    const double residual  = flow.residual_norm();
    const double moved     = flow.mesh_displacement().linfty_norm();
    if (root())
      std::cout << "geometric conservation, V = " << V << ", "
                << (scheme == FluidTimeScheme::bdf1   ? "BDF1"
                    : scheme == FluidTimeScheme::bdf2 ? "BDF2"
                                                      : "one-step-theta 1/2")
                << (pseudo_elastic ? ", pseudo-elastic mesh" : ", prescribed mesh")
                << (fully_distributed ? ", fully distributed" : "") << ": " << result.steps
                << " steps, max |d^G| = " << moved << ", max |x - x_exact| = " << deviation
                << ", ||R|| = " << residual << "\n";
    EXPECT_EQ(result.steps, 10);
    EXPECT_GT(moved, 0.01); // the mesh did move
    EXPECT_LT(deviation, 1e-12);
    EXPECT_LT(residual, 1e-12);
  }

  TEST(FsiFluid, FluidAtRestOnAMovingMeshStaysAtRest)
  {
    for (const bool pseudo_elastic : {false, true})
      {
        for (const auto scheme :
             {FluidTimeScheme::bdf1, FluidTimeScheme::bdf2, FluidTimeScheme::one_step_theta})
          check_uniform_state_preserved({}, scheme, pseudo_elastic);
      }
  }

  TEST(FsiFluid, UniformFlowWithATranslatingDeformingMeshStaysUniform)
  {
    for (const bool pseudo_elastic : {false, true})
      {
        for (const auto scheme :
             {FluidTimeScheme::bdf1, FluidTimeScheme::bdf2, FluidTimeScheme::one_step_theta})
          check_uniform_state_preserved(Tensor<1, 2>({0.7, -0.4}), scheme, pseudo_elastic);
      }
  }

  TEST(FsiFluid, FullyDistributedMeshesGiveTheSameFlow)
  {
    // The fluid alone on a fully distributed mesh (its Dirichlet data, a pressure point and the
    // pseudo-elastic mesh's walls from the DOFs' owners, as on every such mesh): Poiseuille gives
    // the errors of parallel::distributed, the uniform state on a pseudo-elastic moving mesh stays.
    const double                          U = 1.0, H = 1.0, L = 2.0, mu = 0.1;
    auto                                  exact = std::make_shared<Poiseuille>(U, H, L, mu);
    std::vector<physics::fsi::FlowErrors> errors;
    for (const bool fully_distributed : {false, true})
      {
        const auto tria =
            distributed([&](Triangulation<2>& t) { channel(t, 16, 8, L, H); }, fully_distributed);
        FluidFlowSetup<2> s;
        s.model.properties = {1.0, mu};
        for (types::boundary_id b = 0; b < 4; ++b)
          s.velocity[b] = exact;
        s.pressure_point = std::make_pair(Point<2>(L, 0.0), exact);
        FluidFlow<2> flow(*tria, s, comm);
        const auto   result = solve(flow, one_step());
        ASSERT_TRUE(result.converged) << result.failure;
        errors.push_back(flow.errors(*exact));
      }
    if (root())
      std::cout << "Poiseuille 16 x 8, parallel::distributed / fully distributed: ||u - u_h|| = "
                << std::setprecision(12) << errors[0].velocity_l2 << " / " << errors[1].velocity_l2
                << ", ||p - p_h|| = " << errors[0].pressure_l2 << " / " << errors[1].pressure_l2 << "\n";
    // The two meshes are partitioned differently (p4est / METIS), and the fluid alone's solution
    // depends on the partition at 1e-8 (velocity) and 1e-6 (pressure) relative even on
    // parallel::distributed alone (1 and 2 ranks, also before the fully distributed meshes, not
    // yet explained), so equal to 1e-5 here; on 1 rank they agree to 12 digits.
    EXPECT_GT(errors[0].velocity_l2, 0.0);
    EXPECT_NEAR(errors[1].velocity_l2, errors[0].velocity_l2, 1e-5 * errors[0].velocity_l2);
    EXPECT_NEAR(errors[1].velocity_h1, errors[0].velocity_h1, 1e-5 * errors[0].velocity_h1);
    EXPECT_NEAR(errors[1].pressure_l2, errors[0].pressure_l2, 1e-5 * errors[0].pressure_l2);
    check_uniform_state_preserved(Tensor<1, 2>({0.7, -0.4}), FluidTimeScheme::bdf2, true, true);
  }

  /// A mesh motion that folds the cells next to x = 1 over once t > 0.5: d_x = 2 t X^2 (1 - X),
  /// det F = 1 - 2 t at X = 1.
  class FoldingMotion : public Function<2>
  {
  public:
    FoldingMotion()
        : Function<2>(2)
    {
    }
    double value(const Point<2>& X, unsigned int c) const override
    {
      return c == 0 ? 2.0 * get_time() * X[0] * X[0] * (1.0 - X[0]) : 0.0;
    }
  };

  TEST(FsiFluid, InvertedMeshCellsCutTheStepAndStopTheRunCleanly)
  {
    // The prescribed motion inverts cells during the run: the assembly's std::domain_error
    // reaches every rank, Newton reports it, the step driver cuts the step until its limit.
    parallel::distributed::Triangulation<2> tria(comm);
    GridGenerator::subdivided_hyper_cube(tria, 8, 0.0, 1.0, true);
    FluidFlowSetup<2> s;
    s.model.properties = {1.0, 0.1};
    s.model.scheme     = FluidTimeScheme::bdf1;
    auto rest          = std::make_shared<Functions::ZeroFunction<2>>(3);
    for (types::boundary_id b = 0; b < 4; ++b)
      s.velocity[b] = rest;
    s.pressure_point = std::make_pair(Point<2>(0.0, 0.0), rest);
    s.mesh_motion    = std::make_shared<FoldingMotion>();
    FluidFlow<2> flow(tria, s, comm);
    flow.set_initial_state(*rest);
    const auto result = solve(flow, physics::StepSettings{1.0, 0.25, 0.01, 3, 2, 0, "", ""});
    if (root())
      std::cout << "inverted ALE cells: " << result.steps << " steps, " << result.cuts
                << " cuts, failure: " << result.failure << "\n";
    EXPECT_FALSE(result.converged);
    EXPECT_GT(result.cuts, 0);
    EXPECT_NE(result.failure.find("inverted fluid cell"), std::string::npos) << result.failure;
  }

  /// min over cells and quadrature points of det(I + Grad d).
  double min_jacobian(const DoFHandler<2>& dofs, const Vec& d_owned)
  {
    IndexSet relevant;
    DoFTools::extract_locally_relevant_dofs(dofs, relevant);
    Vec d(dofs.locally_owned_dofs(), relevant, comm);
    d = d_owned;
    FEValues<2>               fe_values(dofs.get_fe(), QGauss<2>(2), update_gradients);
    std::vector<Tensor<2, 2>> grads(4);
    double                    result = 1e300;
    for (const auto& cell : dofs.active_cell_iterators())
      if (cell->is_locally_owned())
        {
          fe_values.reinit(cell);
          fe_values[FEValuesExtractors::Vector(0)].get_function_gradients(d, grads);
          for (const auto& G : grads)
            result = std::min(result, determinant(unit_symmetric_tensor<2>() + G));
        }
    return Utilities::MPI::min(result, comm);
  }

  TEST(FsiFluid, PseudoElasticMeshMotion)
  {
    // A mesh graded towards the bottom wall (cells 16 times thinner there), the bottom wall
    // pushed up by a bump of 11 bottom-cell heights.
    std::vector<double> dy;
    for (int k = 0; k < 10; ++k)
      dy.push_back(std::pow(1.36, k) / 56.8);
    parallel::distributed::Triangulation<2> tria(comm);
    GridGenerator::subdivided_hyper_rectangle(tria, {std::vector<double>(10, 0.1), dy}, Point<2>(),
                                              Point<2>(1.0, std::accumulate(dy.begin(), dy.end(), 0.0)),
                                              true);
    FESystem<2>   fe(FE_Q<2>(1), 2);
    DoFHandler<2> dofs(tria);
    dofs.distribute_dofs(fe);
    struct Bump : Function<2>
    {
      Bump()
          : Function<2>(2)
      {
      }
      double value(const Point<2>& X, unsigned int c) const override
      {
        return c == 1 ? 0.2 * std::sin(M_PI * X[0]) : 0.0;
      }
    } bump;
    Functions::ZeroFunction<2>                             zero(2);
    const std::map<types::boundary_id, const Function<2>*> walls{
        {0, &zero}, {1, &zero}, {2, &bump}, {3, &zero}};
    double det_min[2];
    for (const int chi : {0, 1})
      {
        physics::fsi::AleMeshMotion<2> motion(dofs, {0.3, double(chi)}, comm);
        Vec                            d;
        motion.solve(walls, d);
        det_min[chi] = min_jacobian(dofs, d);
        if (root())
          std::cout << "pseudo-elastic mesh, stiffening exponent " << chi << ": min det F = " << det_min[chi]
                    << "\n";
      }
    EXPECT_GT(det_min[1], det_min[0] + 0.05); // stiffening protects the small cells
    EXPECT_GT(det_min[1], 0.0);

    // A rigid translation of the whole boundary moves every node by it.
    Functions::ConstantFunction<2> shift(std::vector<double>{0.3, -0.2});
    physics::fsi::AleMeshMotion<2> motion(dofs, {}, comm);
    Vec                            d;
    motion.solve({{0, &shift}, {1, &shift}, {2, &shift}, {3, &shift}}, d);
    Vec exact(d);
    VectorTools::interpolate(dofs, shift, exact);
    exact.add(-1.0, d);
    EXPECT_LT(exact.linfty_norm(), 1e-12);
  }
} // namespace
