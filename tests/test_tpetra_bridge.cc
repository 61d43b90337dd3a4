// The deal.II -> Tpetra bridge on a distributed elasticity problem (p4est mesh, Q1, Dirichlet
// constraints, ghosted assembly into TrilinosWrappers): the copied Tpetra matrix applies exactly
// like deal.II's, and the block-AMG module solves the resulting system. Run with 1 and 2 ranks.
#include "block_preconditioner.h"
#include "common/tpetra_bridge.h"
#include "krylov_solver.h"
#include "presets.h"

#include <deal.II/base/mpi.h>
#include <deal.II/base/quadrature_lib.h>
#include <deal.II/distributed/tria.h>
#include <deal.II/dofs/dof_handler.h>
#include <deal.II/dofs/dof_tools.h>
#include <deal.II/fe/fe_q.h>
#include <deal.II/fe/fe_system.h>
#include <deal.II/fe/fe_values.h>
#include <deal.II/fe/mapping_q1.h>
#include <deal.II/grid/grid_generator.h>
#include <deal.II/lac/affine_constraints.h>
#include <deal.II/lac/dynamic_sparsity_pattern.h>
#include <deal.II/lac/sparsity_tools.h>
#include <deal.II/lac/trilinos_sparse_matrix.h>
#include <deal.II/lac/trilinos_vector.h>
#include <deal.II/numerics/vector_tools.h>


#include <map>
#include <Xpetra_MultiVectorFactory.hpp>
#include <gtest/gtest.h>

using namespace dealii;

namespace
{
  constexpr int dim = 2;

  struct Elasticity
  {
    parallel::distributed::Triangulation<dim> mesh{MPI_COMM_WORLD};
    FESystem<dim>                             fe{FE_Q<dim>(1), dim};
    DoFHandler<dim>                           dofs{mesh};
    AffineConstraints<double>                 constraints;
    TrilinosWrappers::SparseMatrix            matrix;
    TrilinosWrappers::MPI::Vector             rhs;

    /// Plane-strain linear elasticity on [0,2]x[0,1], clamped at x = 0, body force (0, -1).
    explicit Elasticity(unsigned int refinements)
    {
      GridGenerator::subdivided_hyper_rectangle(mesh, {2, 1}, Point<dim>(), Point<dim>(2.0, 1.0), true);
      mesh.refine_global(refinements);
      dofs.distribute_dofs(fe);
      const IndexSet owned = dofs.locally_owned_dofs();
      IndexSet       relevant;
      DoFTools::extract_locally_relevant_dofs(dofs, relevant);
      constraints.reinit(relevant);
      VectorTools::interpolate_boundary_values(dofs, 0, Functions::ZeroFunction<dim>(dim), constraints);
      constraints.close();
      DynamicSparsityPattern pattern(relevant);
      DoFTools::make_sparsity_pattern(dofs, pattern, constraints, false);
      SparsityTools::distribute_sparsity_pattern(pattern, owned, MPI_COMM_WORLD, relevant);
      matrix.reinit(owned, owned, pattern, MPI_COMM_WORLD);
      rhs.reinit(owned, MPI_COMM_WORLD);
      assemble();
    }

    void assemble()
    {
      const double       lambda = 0.577, mu = 0.385; // E = 1, nu = 0.3
      QGauss<dim>        quadrature(2);
      FEValues<dim>      fe_values(fe, quadrature, update_gradients | update_values | update_JxW_values);
      const unsigned int n = fe.n_dofs_per_cell();
      FullMatrix<double> cell_matrix(n, n);
      Vector<double>     cell_rhs(n);
      std::vector<types::global_dof_index> indices(n);
      for (const auto& cell : dofs.active_cell_iterators())
        if (cell->is_locally_owned())
          {
            fe_values.reinit(cell);
            cell_matrix = 0;
            cell_rhs    = 0;
            for (unsigned int q = 0; q < quadrature.size(); ++q)
              for (unsigned int i = 0; i < n; ++i)
                {
                  const unsigned int ci = fe.system_to_component_index(i).first;
                  for (unsigned int j = 0; j < n; ++j)
                    {
                      const unsigned int cj  = fe.system_to_component_index(j).first;
                      const auto&        gi  = fe_values.shape_grad(i, q);
                      const auto&        gj  = fe_values.shape_grad(j, q);
                      double             val = lambda * gi[ci] * gj[cj] + mu * gi[cj] * gj[ci];
                      if (ci == cj)
                        val += mu * (gi * gj);
                      cell_matrix(i, j) += val * fe_values.JxW(q);
                    }
                  if (ci == 1)
                    cell_rhs(i) -= fe_values.shape_value(i, q) * fe_values.JxW(q);
                }
            cell->get_dof_indices(indices);
            constraints.distribute_local_to_global(cell_matrix, cell_rhs, indices, matrix, rhs);
          }
      matrix.compress(VectorOperation::add);
      rhs.compress(VectorOperation::add);
    }
  };
} // namespace

TEST(TpetraBridge, CopiedMatrixAppliesLikeDealII)
{
  Elasticity problem(4);
  auto       A   = physics::to_xpetra(problem.matrix);
  const auto map = A->getRowMap();
  EXPECT_EQ(A->getGlobalNumRows(), problem.dofs.n_dofs());
  EXPECT_EQ(A->getGlobalNumEntries(), problem.matrix.n_nonzero_elements());

  TrilinosWrappers::MPI::Vector x(problem.dofs.locally_owned_dofs(), MPI_COMM_WORLD), y(x), z(x);
  for (const auto i : problem.dofs.locally_owned_dofs())
    x[i] = std::sin(0.37 * i) + 0.1;
  x.compress(VectorOperation::insert);
  problem.matrix.vmult(y, x);
  auto xx = physics::to_xpetra(x, map);
  auto yy =
      Xpetra::MultiVectorFactory<multigrid::SC, multigrid::LO, multigrid::GO, multigrid::NO>::Build(map, 1);
  A->apply(*xx, *yy);
  physics::copy_to_dealii(*yy, z);
  z -= y;
  EXPECT_LT(z.l2_norm(), 1e-14 * y.l2_norm());
  EXPECT_NEAR(A->getFrobeniusNorm(), problem.matrix.frobenius_norm(),
              1e-12 * problem.matrix.frobenius_norm());
}

TEST(TpetraBridge, BlockAMGSolvesTheAssembledSystem)
{
  Elasticity                 problem(5);
  auto                       A   = physics::to_xpetra(problem.matrix);
  auto                       rhs = physics::to_xpetra(problem.rhs, A->getRowMap());
  std::vector<multigrid::GO> owned;
  for (const auto i : problem.dofs.locally_owned_dofs())
    owned.push_back(static_cast<multigrid::GO>(i));
  multigrid::BlockInfo block;
  block.name          = "displacement";
  block.dofs_per_node = dim;
  block.global_size   = problem.dofs.n_dofs();
  auto system =
      multigrid::BlockSystem::from_merged(physics::teuchos_comm(MPI_COMM_WORLD), {block}, {owned}, A, rhs);
  // Rigid-body modes from the support points of the owned DOFs (node-major: Q1 vertex DOFs are
  // consecutive components of one node).
  std::map<types::global_dof_index, Point<dim>> points;
  DoFTools::map_dofs_to_support_points(MappingQ1<dim>(), problem.dofs, points);
  std::vector<double> xy;
  for (std::size_t k = 0; k < owned.size(); k += dim)
    for (int d = 0; d < dim; ++d)
      xy.push_back(points.at(owned[k])[d]);
  system.block(0).nullspace = multigrid::rigid_body_modes(system.block(0).map, dim, xy);
  multigrid::BlockPreconditioner M(system, multigrid::load_preset("sa-amg"));
  auto x = Xpetra::MultiVectorFactory<multigrid::SC, multigrid::LO, multigrid::GO, multigrid::NO>::Build(
      system.full_map(), 1);
  const auto report = multigrid::solve(system, M, *x, {});
  if (Utilities::MPI::this_mpi_process(MPI_COMM_WORLD) == 0)
    std::cout << problem.dofs.n_dofs() << " DOFs: sa-amg " << report.iterations << " GMRES iterations, "
              << report.preconditioner.levels.size() << " levels\n";
  EXPECT_TRUE(report.converged);
  EXPECT_LE(report.relative_residual, 1.01e-8);
  EXPECT_GT(report.preconditioner.levels.size(), 1u);
}
