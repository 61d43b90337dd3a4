// Total-Lagrangian hyperelastic solid: residual and consistent tangent of the internal forces,
// minus dead nominal tractions on boundary parts and a dead body force, assembled with deal.II
// (any dim, any vector FE with dim components). Shared by every problem class with a solid.
//
// With P = F S (first Piola-Kirchhoff stress) and the virtual deformation gradient grad(dphi):
//   r_i     = int_Omega0 P : grad N_i dV - int_Omega0 rho0 g . N_i dV - int_Gamma0 t0 . N_i dA
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
    /// Reference mass density per cell material id (dynamics and body forces; kg/m^3, per m in 2D).
    std::map<dealii::types::material_id, double> densities;
    /// Dead body force per unit mass (gravity, m/s^2): the force rho0 g per reference volume.
    dealii::Tensor<1, dim> body_force;
  };

  /// Weights of a time-integrated residual  w_f r(u) + c_m M u  and its Jacobian
  /// w_f K(u) + c_m M (see time_integration.h). The defaults are the quasi-static residual.
  struct ResidualWeights
  {
    double force = 1.0; ///< w_f
    double mass  = 0.0; ///< c_m (needs SolidModel::densities)
  };

  /// Assembles r(u) (and K(u) if `tangent` is not null) over the locally owned cells, through
  /// `constraints` (Dirichlet DOFs get a diagonal entry and diagonal x inhomogeneity as residual),
  /// weighted as `weights` says. `u` must hold the locally relevant entries. Throws
  /// std::domain_error if an element inverts, and std::invalid_argument for a cell whose material
  /// id has no law (or no density when weights.mass != 0 or a body force is set).
  template <int dim>
  void assemble_solid(const dealii::DoFHandler<dim>& dof_handler, const SolidModel<dim>& model,
                      const dealii::TrilinosWrappers::MPI::Vector& u,
                      const dealii::AffineConstraints<double>& constraints,
                      dealii::TrilinosWrappers::MPI::Vector& residual,
                      dealii::TrilinosWrappers::SparseMatrix* tangent, const ResidualWeights& weights = {});

  /// Consistent mass matrix M_ij = int rho0 N_i . N_j dV through `constraints` (empty constraints:
  /// the unconstrained M). `M` must be initialized with a suitable sparsity pattern.
  template <int dim>
  void assemble_mass(const dealii::DoFHandler<dim>& dof_handler, const SolidModel<dim>& model,
                     const dealii::AffineConstraints<double>& constraints, dealii::TrilinosWrappers::SparseMatrix& M);

  /// Stored energy int psi(F) dV over all cells (summed over the ranks of `u`'s communicator).
  template <int dim>
  double strain_energy(const dealii::DoFHandler<dim>& dof_handler, const SolidModel<dim>& model,
                       const dealii::TrilinosWrappers::MPI::Vector& u);

  /// Potential of the dead body force, -int rho0 g . u dV (summed over the ranks): with the strain
  /// and kinetic energies the conserved total of a body under gravity.
  template <int dim>
  double body_force_potential(const dealii::DoFHandler<dim>& dof_handler, const SolidModel<dim>& model,
                              const dealii::TrilinosWrappers::MPI::Vector& u);

  /// Cell averages of the Cauchy stress (dim*dim components per locally owned cell, in the order
  /// of active cells; zero for cells not owned) and of the von Mises stress, for output.
  template <int dim>
  void cell_cauchy_stress(const dealii::DoFHandler<dim>& dof_handler, const SolidModel<dim>& model,
                          const dealii::TrilinosWrappers::MPI::Vector& u,
                          std::vector<dealii::Vector<float>>& components, dealii::Vector<float>& von_mises);
} // namespace physics
