#include "common/solid_mechanics.h"

#include "common/row_exchange.h"

#include <deal.II/base/mpi.h>
#include <deal.II/base/quadrature_lib.h>
#include <deal.II/fe/fe_values.h>
#include <deal.II/lac/full_matrix.h>
#include <deal.II/lac/vector.h>

#include <stdexcept>
#include <string>

namespace physics
{
  using namespace dealii;

  namespace
  {
    template <int dim>
    const HyperelasticMaterial<dim>& material_of(const SolidModel<dim>& model, types::material_id id)
    {
      const auto it = model.materials.find(id);
      if (it == model.materials.end())
        throw std::invalid_argument("a cell has material id " + std::to_string(id) +
                                    ", for which no material is defined");
      return *it->second;
    }

    template <int dim>
    double density_of(const SolidModel<dim>& model, types::material_id id)
    {
      const auto it = model.densities.find(id);
      if (it == model.densities.end())
        throw std::invalid_argument("a cell has material id " + std::to_string(id) +
                                    ", for which no density is defined");
      return it->second;
    }

    /// Deformation gradients F = I + grad u at the quadrature points of a cell.
    template <int dim>
    void deformation_gradients(const FEValues<dim>& fe_values, const TrilinosWrappers::MPI::Vector& u,
                               std::vector<Tensor<2, dim>>& F)
    {
      const FEValuesExtractors::Vector displacement(0);
      std::vector<Tensor<2, dim>>      grad_u(fe_values.n_quadrature_points);
      fe_values[displacement].get_function_gradients(u, grad_u);
      F.resize(grad_u.size());
      for (unsigned int q = 0; q < grad_u.size(); ++q)
        F[q] = unit_symmetric_tensor<dim>() + grad_u[q];
    }
  } // namespace

  template <int dim>
  void assemble_solid(const DoFHandler<dim>& dof_handler, const SolidModel<dim>& model,
                      const TrilinosWrappers::MPI::Vector& u, const AffineConstraints<double>& constraints,
                      TrilinosWrappers::MPI::Vector& residual, TrilinosWrappers::SparseMatrix* tangent,
                      const ResidualWeights& weights)
  {
    const auto&           fe = dof_handler.get_fe();
    const QGauss<dim>     quadrature(fe.degree + 1);
    const QGauss<dim - 1> face_quadrature(fe.degree + 1);
    const bool            inertia = weights.mass != 0.0, body_force = model.body_force.norm() > 0.0;
    FEValues<dim>         fe_values(fe, quadrature,
                                    update_gradients | update_JxW_values |
                                        (inertia || body_force ? update_values : update_default));
    FEFaceValues<dim>                fe_face_values(fe, face_quadrature, update_values | update_JxW_values);
    const FEValuesExtractors::Vector displacement(0);

    const unsigned int                   n = fe.n_dofs_per_cell();
    FullMatrix<double>                   cell_matrix(n, n);
    Vector<double>                       cell_residual(n);
    std::vector<types::global_dof_index> dofs(n);
    std::vector<Tensor<2, dim>>          F, grad_N(n);
    std::vector<SymmetricTensor<2, dim>> dE(n);
    std::vector<Tensor<1, dim>>          u_q, N(n);

    // An inverted element on one rank must stop the assembly on every rank at the same point
    // (before the collective compress), with the same message: the Newton solver then cuts the step
    // or shortens the update everywhere alike.
    std::string inverted;
    for (const auto& cell : dof_handler.active_cell_iterators())
      {
        if (!cell->is_locally_owned())
          continue;
        try
          {
            const auto&  material = material_of(model, cell->material_id());
            const double rho      = inertia ? density_of(model, cell->material_id()) : 0.0;
            fe_values.reinit(cell);
            deformation_gradients(fe_values, u, F);
            cell_matrix   = 0;
            cell_residual = 0;
            for (unsigned int q = 0; q < quadrature.size(); ++q)
              {
                const auto           st  = material.stress_and_tangent(F[q]);
                const Tensor<2, dim> S(st.S);
                const Tensor<2, dim> P   = F[q] * S;
                const double         JxW = fe_values.JxW(q);
                // Per shape function once (not per pair): grad N_j and dE_j = sym(F^T grad N_j).
                for (unsigned int i = 0; i < n; ++i)
                  {
                    grad_N[i] = fe_values[displacement].gradient(i, q);
                    dE[i]     = symmetrize(transpose(F[q]) * grad_N[i]);
                  }
                for (unsigned int i = 0; i < n; ++i)
                  {
                    cell_residual(i) += scalar_product(P, grad_N[i]) * JxW;
                    if (!tangent)
                      continue;
                    // K_ij = (grad N_i S) : grad N_j + dE_i : CC : dE_j, symmetric: the upper
                    // triangle here, the lower one mirrored after the cell.
                    const SymmetricTensor<2, dim> dS_i = st.CC * dE[i];
                    const Tensor<2, dim>          gS_i = grad_N[i] * S;
                    for (unsigned int j = i; j < n; ++j)
                      cell_matrix(i, j) += (scalar_product(gS_i, grad_N[j]) + dS_i * dE[j]) * JxW;
                  }
              }
            // Dead nominal tractions: subtract int t0 . N_i dA.
            for (const unsigned int f : cell->face_indices())
              {
                if (!cell->face(f)->at_boundary())
                  continue;
                const auto t = model.tractions.find(cell->face(f)->boundary_id());
                if (t == model.tractions.end())
                  continue;
                fe_face_values.reinit(cell, f);
                for (unsigned int q = 0; q < face_quadrature.size(); ++q)
                  for (unsigned int i = 0; i < n; ++i)
                    cell_residual(i) -=
                        fe_face_values[displacement].value(i, q) * t->second * fe_face_values.JxW(q);
              }
            // Dead body force: subtract int rho0 g . N_i dV.
            if (body_force)
              {
                const double rho = density_of(model, cell->material_id());
                for (unsigned int q = 0; q < quadrature.size(); ++q)
                  for (unsigned int i = 0; i < n; ++i)
                    cell_residual(i) -=
                        rho * (fe_values[displacement].value(i, q) * model.body_force) * fe_values.JxW(q);
              }
            cell_matrix *= weights.force;
            cell_residual *= weights.force;
            // Inertia: + c_m M u (residual) and + c_m M (Jacobian).
            if (inertia)
              {
                u_q.resize(quadrature.size());
                fe_values[displacement].get_function_values(u, u_q);
                for (unsigned int q = 0; q < quadrature.size(); ++q)
                  {
                    const double m = weights.mass * rho * fe_values.JxW(q);
                    for (unsigned int i = 0; i < n; ++i)
                      N[i] = fe_values[displacement].value(i, q);
                    for (unsigned int i = 0; i < n; ++i)
                      {
                        cell_residual(i) += m * (N[i] * u_q[q]);
                        if (tangent)
                          for (unsigned int j = i; j < n; ++j) // upper triangle, as above
                            cell_matrix(i, j) += m * (N[i] * N[j]);
                      }
                  }
              }
            if (tangent)
              for (unsigned int i = 0; i < n; ++i)
                for (unsigned int j = 0; j < i; ++j)
                  cell_matrix(i, j) = cell_matrix(j, i);
            cell->get_dof_indices(dofs);
            if (tangent)
              // true: a constrained row gets (its diagonal x inhomogeneity) in the residual, so that an
              // inhomogeneous constraint is met by the Newton update (load increments).
              constraints.distribute_local_to_global(cell_matrix, cell_residual, dofs, *tangent, residual,
                                                     true);
            else
              constraints.distribute_local_to_global(cell_residual, dofs, residual);
          }
        catch (const std::domain_error& e)
          {
            inverted = e.what();
            break;
          }
      }
    const std::string message = lowest_rank_message(inverted, residual.get_mpi_communicator());
    if (!message.empty())
      throw std::domain_error(message);
    if (tangent)
      tangent->compress(VectorOperation::add);
    residual.compress(VectorOperation::add);
  }

  template <int dim>
  void assemble_mass(const DoFHandler<dim>& dof_handler, const SolidModel<dim>& model,
                     const AffineConstraints<double>& constraints, TrilinosWrappers::SparseMatrix& M)
  {
    const auto&                          fe = dof_handler.get_fe();
    const QGauss<dim>                    quadrature(fe.degree + 1);
    FEValues<dim>                        fe_values(fe, quadrature, update_values | update_JxW_values);
    const FEValuesExtractors::Vector     displacement(0);
    const unsigned int                   n = fe.n_dofs_per_cell();
    FullMatrix<double>                   cell_matrix(n, n);
    std::vector<types::global_dof_index> dofs(n);
    for (const auto& cell : dof_handler.active_cell_iterators())
      {
        if (!cell->is_locally_owned())
          continue;
        const double rho = density_of(model, cell->material_id());
        fe_values.reinit(cell);
        cell_matrix = 0;
        for (unsigned int q = 0; q < quadrature.size(); ++q)
          for (unsigned int i = 0; i < n; ++i)
            for (unsigned int j = 0; j < n; ++j)
              cell_matrix(i, j) +=
                  rho * (fe_values[displacement].value(i, q) * fe_values[displacement].value(j, q)) *
                  fe_values.JxW(q);
        cell->get_dof_indices(dofs);
        constraints.distribute_local_to_global(cell_matrix, dofs, M);
      }
    M.compress(VectorOperation::add);
  }

  template <int dim>
  double strain_energy(const DoFHandler<dim>& dof_handler, const SolidModel<dim>& model,
                       const TrilinosWrappers::MPI::Vector& u)
  {
    const auto&                 fe = dof_handler.get_fe();
    const QGauss<dim>           quadrature(fe.degree + 1);
    FEValues<dim>               fe_values(fe, quadrature, update_gradients | update_JxW_values);
    std::vector<Tensor<2, dim>> F;
    double                      energy = 0;
    for (const auto& cell : dof_handler.active_cell_iterators())
      {
        if (!cell->is_locally_owned())
          continue;
        const auto& material = material_of(model, cell->material_id());
        fe_values.reinit(cell);
        deformation_gradients(fe_values, u, F);
        for (unsigned int q = 0; q < quadrature.size(); ++q)
          energy += material.energy(F[q]) * fe_values.JxW(q);
      }
    return Utilities::MPI::sum(energy, u.get_mpi_communicator());
  }

  template <int dim>
  double body_force_potential(const DoFHandler<dim>& dof_handler, const SolidModel<dim>& model,
                              const TrilinosWrappers::MPI::Vector& u)
  {
    if (model.body_force.norm() == 0.0)
      return 0.0;
    const auto&                      fe = dof_handler.get_fe();
    const QGauss<dim>                quadrature(fe.degree + 1);
    FEValues<dim>                    fe_values(fe, quadrature, update_values | update_JxW_values);
    const FEValuesExtractors::Vector displacement(0);
    std::vector<Tensor<1, dim>>      u_q(quadrature.size());
    double                           potential = 0;
    for (const auto& cell : dof_handler.active_cell_iterators())
      {
        if (!cell->is_locally_owned())
          continue;
        const double rho = density_of(model, cell->material_id());
        fe_values.reinit(cell);
        fe_values[displacement].get_function_values(u, u_q);
        for (unsigned int q = 0; q < quadrature.size(); ++q)
          potential -= rho * (model.body_force * u_q[q]) * fe_values.JxW(q);
      }
    return Utilities::MPI::sum(potential, u.get_mpi_communicator());
  }

  template <int dim>
  void cell_cauchy_stress(const DoFHandler<dim>& dof_handler, const SolidModel<dim>& model,
                          const TrilinosWrappers::MPI::Vector& u, std::vector<Vector<float>>& components,
                          Vector<float>& von_mises)
  {
    const auto&       fe = dof_handler.get_fe();
    const QGauss<dim> quadrature(fe.degree + 1);
    FEValues<dim>     fe_values(fe, quadrature, update_gradients | update_JxW_values);
    const auto        n_cells = dof_handler.get_triangulation().n_active_cells();
    components.assign(dim * dim, Vector<float>(n_cells));
    von_mises.reinit(n_cells);
    std::vector<Tensor<2, dim>> F;
    for (const auto& cell : dof_handler.active_cell_iterators())
      {
        if (!cell->is_locally_owned())
          continue;
        const auto& material = material_of(model, cell->material_id());
        fe_values.reinit(cell);
        deformation_gradients(fe_values, u, F);
        Tensor<2, dim> sigma;
        double         volume = 0;
        for (unsigned int q = 0; q < quadrature.size(); ++q)
          {
            const auto   st = material.stress_and_tangent(F[q]);
            const double J  = determinant(F[q]);
            sigma += (F[q] * Tensor<2, dim>(st.S) * transpose(F[q])) / J * fe_values.JxW(q);
            volume += fe_values.JxW(q);
          }
        sigma /= volume;
        const auto index = cell->active_cell_index();
        for (unsigned int a = 0; a < dim; ++a)
          for (unsigned int b = 0; b < dim; ++b)
            components[a * dim + b](index) = sigma[a][b];
        const Tensor<2, dim> dev = sigma - trace(sigma) / 3.0 * unit_symmetric_tensor<dim>();
        // plane strain (2D): sigma_zz is not tracked; the in-plane deviator is shown
        von_mises(index) = std::sqrt(1.5 * scalar_product(dev, dev));
      }
  }

  template void assemble_solid<2>(const DoFHandler<2>&, const SolidModel<2>&,
                                  const TrilinosWrappers::MPI::Vector&, const AffineConstraints<double>&,
                                  TrilinosWrappers::MPI::Vector&, TrilinosWrappers::SparseMatrix*,
                                  const ResidualWeights&);
  template void assemble_solid<3>(const DoFHandler<3>&, const SolidModel<3>&,
                                  const TrilinosWrappers::MPI::Vector&, const AffineConstraints<double>&,
                                  TrilinosWrappers::MPI::Vector&, TrilinosWrappers::SparseMatrix*,
                                  const ResidualWeights&);
  template void assemble_mass<2>(const DoFHandler<2>&, const SolidModel<2>&, const AffineConstraints<double>&,
                                 TrilinosWrappers::SparseMatrix&);
  template void assemble_mass<3>(const DoFHandler<3>&, const SolidModel<3>&, const AffineConstraints<double>&,
                                 TrilinosWrappers::SparseMatrix&);
  template double strain_energy<2>(const DoFHandler<2>&, const SolidModel<2>&,
                                   const TrilinosWrappers::MPI::Vector&);
  template double strain_energy<3>(const DoFHandler<3>&, const SolidModel<3>&,
                                   const TrilinosWrappers::MPI::Vector&);
  template double body_force_potential<2>(const DoFHandler<2>&, const SolidModel<2>&,
                                          const TrilinosWrappers::MPI::Vector&);
  template double body_force_potential<3>(const DoFHandler<3>&, const SolidModel<3>&,
                                          const TrilinosWrappers::MPI::Vector&);
  template void   cell_cauchy_stress<2>(const DoFHandler<2>&, const SolidModel<2>&,
                                      const TrilinosWrappers::MPI::Vector&, std::vector<Vector<float>>&,
                                      Vector<float>&);
  template void   cell_cauchy_stress<3>(const DoFHandler<3>&, const SolidModel<3>&,
                                      const TrilinosWrappers::MPI::Vector&, std::vector<Vector<float>>&,
                                      Vector<float>&);
} // namespace physics
