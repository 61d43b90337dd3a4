// Total-Lagrangian hyperelastic solid: residual and consistent tangent of the internal forces,
// minus dead nominal tractions on boundary parts, assembled with deal.II (any dim, any vector
// FE with dim components). Shared by every problem class with a solid.
//
// With P = F S (first Piola-Kirchhoff stress) and the virtual deformation gradient grad(dphi):
//   r_i     = int_Omega0 P : grad N_i dV - int_Gamma0 t0 . N_i dA
//   K_ij    = int_Omega0 grad N_i : (dP/dF) : grad N_j dV,
//   dP/dF : H = H S + F (CC : sym(F^T H))        (geometric + material part).
#pragma once

#include "common/hyperelastic_material.h"

#include <deal.II/base/tensor.h>
#include <deal.II/dofs/dof_handler.h>
#include <deal.II/lac/affine_constraints.h>
#include <deal.II/lac/trilinos_sparse_matrix.h>
#include <deal.II/lac/trilinos_vector.h>

#include <map>
#include <memory>

namespace physics
{
  template <int dim>
  struct SolidModel
  {
    /// Material law per cell material id.
    std::map<dealii::types::material_id, std::shared_ptr<const HyperelasticMaterial<dim>>> materials;
    /// Dead nominal traction (force per reference area) per boundary id.
    std::map<dealii::types::boundary_id, dealii::Tensor<1, dim>> tractions;
  };

  /// Assembles r(u) (and K(u) if `tangent` is not null) over the locally owned cells, through the
  /// homogeneous `constraints` (Dirichlet DOFs get zero residual and a diagonal entry). `u` must
  /// hold the locally relevant entries. Throws std::domain_error if an element inverts, and
  /// std::invalid_argument for a cell whose material id has no law.
  template <int dim>
  void assemble_solid(const dealii::DoFHandler<dim>& dof_handler, const SolidModel<dim>& model,
                      const dealii::TrilinosWrappers::MPI::Vector& u,
                      const dealii::AffineConstraints<double>& constraints,
                      dealii::TrilinosWrappers::MPI::Vector& residual,
                      dealii::TrilinosWrappers::SparseMatrix* tangent);

  /// Cell averages of the Cauchy stress (dim*dim components per locally owned cell, in the order
  /// of active cells; zero for cells not owned) and of the von Mises stress, for output.
  template <int dim>
  void cell_cauchy_stress(const dealii::DoFHandler<dim>& dof_handler, const SolidModel<dim>& model,
                          const dealii::TrilinosWrappers::MPI::Vector& u,
                          std::vector<dealii::Vector<float>>& components, dealii::Vector<float>& von_mises);
} // namespace physics
