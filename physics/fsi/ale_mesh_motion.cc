#include "fsi/ale_mesh_motion.h"

#include "common/distributed_mesh.h"

#include <deal.II/base/quadrature_lib.h>
#include <deal.II/dofs/dof_tools.h>
#include <deal.II/fe/fe_values.h>
#include <deal.II/lac/dynamic_sparsity_pattern.h>
#include <deal.II/lac/full_matrix.h>
#include <deal.II/lac/solver_control.h>
#include <deal.II/lac/sparsity_tools.h>
#include <deal.II/lac/trilinos_solver.h>

#include <cmath>
#include <stdexcept>
#include <string>

namespace physics::fsi
{
  using namespace dealii;

  void MeshMotionSettings::check() const
  {
    if (!(poisson_ratio >= 0 && poisson_ratio < 0.5))
      throw std::invalid_argument("parameter 'Poisson ratio' (ALE mesh): expected 0 <= nu < 0.5, got " +
                                  std::to_string(poisson_ratio));
    if (!(stiffening_exponent >= 0) || !std::isfinite(stiffening_exponent))
      throw std::invalid_argument("parameter 'Stiffening exponent' (ALE mesh): expected chi >= 0, got " +
                                  std::to_string(stiffening_exponent));
  }

  namespace
  {
    /// The local stiffness of linear elasticity with Young's modulus `E` (Lame parameters of
    /// the pseudo-material's Poisson ratio) on the reference cell of `fe_values`.
    template <int dim>
    void cell_stiffness(const FEValues<dim>& fe_values, double E, double nu, FullMatrix<double>& K)
    {
      const double                     lambda = E * nu / ((1 + nu) * (1 - 2 * nu)), mu = E / (2 * (1 + nu));
      const FEValuesExtractors::Vector displacement(0);
      const unsigned int               n = fe_values.get_fe().n_dofs_per_cell();
      K                                  = 0;
      for (const unsigned int q : fe_values.quadrature_point_indices())
        for (unsigned int i = 0; i < n; ++i)
          {
            const auto   eps_i = fe_values[displacement].symmetric_gradient(i, q);
            const double div_i = fe_values[displacement].divergence(i, q);
            for (unsigned int j = 0; j < n; ++j)
              K(i, j) += (lambda * div_i * fe_values[displacement].divergence(j, q) +
                          2 * mu * scalar_product(eps_i, fe_values[displacement].symmetric_gradient(j, q))) *
                         fe_values.JxW(q);
          }
    }
  } // namespace

  template <int dim>
  AleMeshMotion<dim>::AleMeshMotion(const DoFHandler<dim>& mesh_dofs, MeshMotionSettings settings,
                                    MPI_Comm comm)
      : dofs_(mesh_dofs)
      , settings_(settings)
      , comm_(comm)
  {
    settings_.check();
    owned_ = dofs_.locally_owned_dofs();
    DoFTools::extract_locally_relevant_dofs(dofs_, relevant_);
    assemble();
  }

  template <int dim>
  void AleMeshMotion<dim>::assemble()
  {
    // Stiffening E_K = (mean |K| / |K|)^chi; the mean over all cells of all ranks.
    const auto& tria = dofs_.get_triangulation();
    stiffening_.reinit(tria.n_active_cells());
    double local[2] = {0, 0};
    for (const auto& cell : dofs_.active_cell_iterators())
      if (cell->is_locally_owned())
        {
          local[0] += cell->measure();
          local[1] += 1;
        }
    double global[2];
    MPI_Allreduce(local, global, 2, MPI_DOUBLE, MPI_SUM, comm_);
    const double mean = global[0] / global[1];
    for (const auto& cell : dofs_.active_cell_iterators())
      if (cell->is_locally_owned())
        stiffening_[cell->active_cell_index()] =
            std::pow(mean / cell->measure(), settings_.stiffening_exponent);

    DynamicSparsityPattern pattern(relevant_);
    DoFTools::make_sparsity_pattern(dofs_, pattern);
    SparsityTools::distribute_sparsity_pattern(pattern, owned_, comm_, relevant_);
    stiffness_.reinit(owned_, owned_, pattern, comm_);
    FEValues<dim>      fe_values(dofs_.get_fe(), QGauss<dim>(2), update_gradients | update_JxW_values);
    FullMatrix<double> K(dofs_.get_fe().n_dofs_per_cell(), dofs_.get_fe().n_dofs_per_cell());
    std::vector<types::global_dof_index> indices(K.m());
    for (const auto& cell : dofs_.active_cell_iterators())
      if (cell->is_locally_owned())
        {
          fe_values.reinit(cell);
          cell_stiffness(fe_values, stiffening_[cell->active_cell_index()], settings_.poisson_ratio, K);
          cell->get_dof_indices(indices);
          stiffness_.add(indices, K);
        }
    stiffness_.compress(VectorOperation::add);
  }

  template <int dim>
  void AleMeshMotion<dim>::solve(const std::map<types::boundary_id, const Function<dim>*>& boundary,
                                 TrilinosWrappers::MPI::Vector&                            d) const
  {
    // Dirichlet data on the owned DOFs, made consistent on the ghosts (a fully distributed
    // mesh's ghost layer ends in faces that look like boundary faces; common/distributed_mesh.h).
    AffineConstraints<double> constraints(relevant_);
    for (const auto& [id, g] : boundary)
      add_boundary_constraints(dofs_, id, *g, constraints);
    close_distributed_constraints(dofs_, relevant_, constraints);
    // The constrained system: K_G with the Dirichlet rows/columns eliminated, their values on
    // the right-hand side (distribute_local_to_global with inhomogeneities).
    DynamicSparsityPattern pattern(relevant_);
    DoFTools::make_sparsity_pattern(dofs_, pattern, constraints, false);
    SparsityTools::distribute_sparsity_pattern(pattern, owned_, comm_, relevant_);
    TrilinosWrappers::SparseMatrix A;
    A.reinit(owned_, owned_, pattern, comm_);
    TrilinosWrappers::MPI::Vector b(owned_, comm_), x(owned_, comm_);
    FEValues<dim>      fe_values(dofs_.get_fe(), QGauss<dim>(2), update_gradients | update_JxW_values);
    const unsigned int n = dofs_.get_fe().n_dofs_per_cell();
    FullMatrix<double> K(n, n);
    Vector<double>     zero(n);
    std::vector<types::global_dof_index> indices(n);
    for (const auto& cell : dofs_.active_cell_iterators())
      if (cell->is_locally_owned())
        {
          fe_values.reinit(cell);
          cell_stiffness(fe_values, stiffening_[cell->active_cell_index()], settings_.poisson_ratio, K);
          cell->get_dof_indices(indices);
          zero = 0;
          constraints.distribute_local_to_global(K, zero, indices, A, b);
        }
    A.compress(VectorOperation::add);
    b.compress(VectorOperation::add);
    SolverControl                  control(1, 0);
    TrilinosWrappers::SolverDirect solver(control);
    solver.solve(A, x, b);
    constraints.distribute(x);
    d.reinit(owned_, comm_);
    d = x;
  }

  template class AleMeshMotion<2>;
  template class AleMeshMotion<3>;
} // namespace physics::fsi
