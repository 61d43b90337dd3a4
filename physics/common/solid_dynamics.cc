#include "common/solid_dynamics.h"

#include <deal.II/dofs/dof_tools.h>
#include <deal.II/lac/solver_control.h>
#include <deal.II/lac/sparsity_tools.h>
#include <deal.II/lac/trilinos_precondition.h>
#include <deal.II/lac/trilinos_solver.h>

namespace physics
{
  using namespace dealii;

  template <int dim>
  SolidDynamics<dim>::SolidDynamics(double spectral_radius, double time_step, const DoFHandler<dim>& dof_handler,
                                    const SolidModel<dim>& model, const IndexSet& owned, const IndexSet& relevant,
                                    MPI_Comm comm)
      : spectral_radius_(spectral_radius)
      , scheme_(spectral_radius, time_step)
      , dof_handler_(dof_handler)
      , model_(model)
      , owned_(owned)
      , relevant_(relevant)
      , comm_(comm)
      , pattern_(relevant.size(), relevant.size(), relevant)
  {
    DoFTools::make_sparsity_pattern(dof_handler, pattern_);
    SparsityTools::distribute_sparsity_pattern(pattern_, owned, comm, relevant);
    mass_.reinit(owned, owned, pattern_, comm);
    assemble_mass(dof_handler, model, AffineConstraints<double>(), mass_);
    u_old_.reinit(owned, comm);
    v_.reinit(owned, comm);
    a_.reinit(owned, comm);
    h_.reinit(owned, comm);
  }

  template <int dim>
  void SolidDynamics<dim>::residual(const TrilinosWrappers::MPI::Vector& u, const AffineConstraints<double>& constraints,
                                    TrilinosWrappers::MPI::Vector& r) const
  {
    TrilinosWrappers::MPI::Vector ghosted(owned_, relevant_, comm_);
    ghosted = u;
    r.reinit(owned_, comm_);
    assemble_solid(dof_handler_, model_, ghosted, constraints, r, nullptr);
  }

  template <int dim>
  void SolidDynamics<dim>::initial_acceleration(const TrilinosWrappers::MPI::Vector& u,
                                                const AffineConstraints<double>& constraints)
  {
    TrilinosWrappers::MPI::Vector r;
    residual(u, constraints, r);
    a_ = 0;
    if (r.l2_norm() == 0)
      return;
    // Through `constraints`: unit-like diagonal rows with zero right-hand side where constrained.
    TrilinosWrappers::SparseMatrix M;
    M.reinit(owned_, owned_, pattern_, comm_);
    assemble_mass(dof_handler_, model_, constraints, M);
    r *= -1.0;
    SolverControl                        control(1000, 1e-12 * r.l2_norm());
    TrilinosWrappers::SolverCG           cg(control);
    TrilinosWrappers::PreconditionJacobi jacobi;
    jacobi.initialize(M);
    cg.solve(M, a_, r, jacobi);
  }

  template <int dim>
  void SolidDynamics<dim>::begin_step(const TrilinosWrappers::MPI::Vector& u, const AffineConstraints<double>& constraints)
  {
    TrilinosWrappers::MPI::Vector r_old;
    residual(u, AffineConstraints<double>(), r_old);
    u_old_ = u;
    scheme_.history(mass_, u_old_, v_, a_, r_old, h_);
    for (const auto i : owned_)
      if (constraints.is_constrained(i))
        h_[i] = 0.0;
    h_.compress(VectorOperation::insert);
  }

  template <int dim>
  void SolidDynamics<dim>::end_step(const TrilinosWrappers::MPI::Vector& u)
  {
    scheme_.update(u, u_old_, v_, a_);
  }

  template <int dim>
  double SolidDynamics<dim>::kinetic_energy() const
  {
    TrilinosWrappers::MPI::Vector Mv(owned_, comm_);
    mass_.vmult(Mv, v_);
    return 0.5 * (Mv * v_);
  }

  template <int dim>
  void SolidDynamics<dim>::save(Checkpoint& checkpoint, const std::string& prefix) const
  {
    checkpoint.store(prefix + "/u_old", u_old_);
    checkpoint.store(prefix + "/velocity", v_);
    checkpoint.store(prefix + "/acceleration", a_);
  }

  template <int dim>
  void SolidDynamics<dim>::load(const Checkpoint& checkpoint, const std::string& prefix)
  {
    checkpoint.restore(prefix + "/u_old", u_old_);
    checkpoint.restore(prefix + "/velocity", v_);
    checkpoint.restore(prefix + "/acceleration", a_);
  }

  template class SolidDynamics<2>;
  template class SolidDynamics<3>;
} // namespace physics
