// Pseudo-elastic ALE mesh motion (the seeds' ALE field; FSI.md): the grid displacement d^G of
// the fluid mesh solves linear elasticity on the reference mesh,
//   int_Omega0 E_K (lambda' div d div e + 2 mu' eps(d) : eps(e)) dX = 0   for all e, e = 0 on Gamma_D,
//   d = g on Gamma_D (the FSI interface: the structure's displacement; other walls: fixed),
// with unit Young's modulus scaled per cell by the Jacobian-based stiffening of Stein,
// Tezduyar and Benney (2003),
//   E_K = (|K|_mean / |K|)^chi,   chi >= 0 (chi = 0: plain elasticity),
// so small cells (boundary layers, the interface) are stiff and move nearly rigidly, while the
// large cells away from them take up the deformation. The operator is linear and assembled once;
// the monolithic FSI Newton takes it as the ALE block, the fluid alone solves it directly.
#pragma once

#include <deal.II/base/function.h>
#include <deal.II/dofs/dof_handler.h>
#include <deal.II/lac/affine_constraints.h>
#include <deal.II/lac/trilinos_sparse_matrix.h>
#include <deal.II/lac/trilinos_vector.h>
#include <deal.II/lac/vector.h>

#include <map>
#include <memory>

namespace physics::fsi
{
  struct MeshMotionSettings
  {
    double poisson_ratio       = 0.3; ///< of the pseudo-material, in [0, 0.5)
    double stiffening_exponent = 1.0; ///< chi >= 0
    /// Throws std::invalid_argument naming 'Poisson ratio' or 'Stiffening exponent' (ALE mesh).
    void check() const;
  };

  template <int dim>
  class AleMeshMotion
  {
  public:
    /// `mesh_dofs`: FE_Q(1)^dim on the fluid's reference mesh (it must outlive this).
    AleMeshMotion(const dealii::DoFHandler<dim>& mesh_dofs, MeshMotionSettings settings, MPI_Comm comm);

    /// The unconstrained stiffness K_G (owned rows; for the monolithic system).
    const dealii::TrilinosWrappers::SparseMatrix& stiffness() const { return stiffness_; }
    /// The stiffening factor E_K of every active cell (order of active cells; 0 off this rank).
    const dealii::Vector<double>& cell_stiffening() const { return stiffening_; }

    /// d^G with d = g(X) on the boundary ids of `boundary` (each function dim components) and
    /// free elsewhere; `d` is the owned vector on return. Solved with a direct solver.
    void solve(const std::map<dealii::types::boundary_id, const dealii::Function<dim>*>& boundary,
               dealii::TrilinosWrappers::MPI::Vector&                                    d) const;

  private:
    void assemble();

    const dealii::DoFHandler<dim>&         dofs_;
    MeshMotionSettings                     settings_;
    MPI_Comm                               comm_;
    dealii::IndexSet                       owned_, relevant_;
    dealii::TrilinosWrappers::SparseMatrix stiffness_;
    dealii::Vector<double>                 stiffening_;
  };
} // namespace physics::fsi
