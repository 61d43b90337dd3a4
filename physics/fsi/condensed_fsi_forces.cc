// CondensedFsi (condensed_fsi_problem.h): a prescribed parabolic inflow, the fluid's force on a
// rigid obstacle and the structure, and the displacement of a monitor point: the quantities of
// the Turek-Hron benchmark (drag, lift, point A), logged after every converged time step.
//
// The force by the residual ("reaction") method. Let B be the velocity nodes on the obstacle
// and on the fluid/structure interface, and test the fluid's momentum equation with
// v = sum_{i in B} phi_i e_k: v = e_k on the obstacle and the interface and 0 on every other
// boundary (B touches no other boundary), so the unconstrained fluid residual R (Galerkin terms
// and stabilization, on the moved mesh) sums to
//   sum_{i in B} R_{i,k} = int_{obstacle + interface} (sigma n)_k ds,   n the fluid's outward normal,
// the traction the bodies exert on the fluid, for R the converged step's own residual (its time
// derivative and grid velocity included: an accelerating fluid's inertia in the boundary cells is
// part of the force the test function measures). The force of the fluid on the bodies is its
// negative, F_k = -sum_{i in B} R_{i,k}; k = x is the drag, k = y the lift. Unlike the boundary
// integral of the discrete traction (a Q1 velocity gradient on the wall), this functional
// converges at the rate of the solution's energy error squared (Giles, Larson, Levenstam and
// Suli 1997); it is the same R whose interface rows the condensed coupling adds to the structure.
#include "common/distributed_mesh.h"
#include "fsi/condensed_fsi_problem.h"

#include <deal.II/base/function.h>
#include <deal.II/base/mpi.h>
#include <deal.II/base/numbers.h>
#include <deal.II/fe/fe_values_extractors.h>

#include <algorithm>
#include <cmath>
#include <iomanip>
#include <limits>
#include <sstream>

namespace physics::fsi
{
  using namespace dealii;

  namespace
  {
    /// The bounding box of the owned fluid faces with boundary id `id` (over all ranks).
    template <int dim>
    std::pair<Point<dim>, Point<dim>> boundary_box(const DoFHandler<dim>& dofs, types::boundary_id id,
                                                   MPI_Comm comm)
    {
      Point<dim> low, high;
      for (unsigned d = 0; d < dim; ++d)
        {
          low[d]  = std::numeric_limits<double>::max();
          high[d] = -low[d];
        }
      for (const auto& cell : dofs.active_cell_iterators())
        if (cell->is_locally_owned())
          for (const unsigned f : cell->face_indices())
            if (cell->at_boundary(f) && cell->face(f)->boundary_id() == id)
              for (const unsigned v : cell->face(f)->vertex_indices())
                for (unsigned d = 0; d < dim; ++d)
                  {
                    low[d]  = std::min(low[d], cell->face(f)->vertex(v)[d]);
                    high[d] = std::max(high[d], cell->face(f)->vertex(v)[d]);
                  }
      for (unsigned d = 0; d < dim; ++d)
        {
          low[d]  = Utilities::MPI::min(low[d], comm);
          high[d] = Utilities::MPI::max(high[d], comm);
        }
      return {low, high};
    }
  } // namespace

  template <int dim>
  void CondensedFsi<dim>::setup_inflow_and_monitors()
  {
    const ComponentMask velocity = fluid_fe_.component_mask(FEValuesExtractors::Vector(0));
    if (p_.parabolic_inflow)
      {
        // The profile across the inlet plane (normal to x): 2D the channel's parabola over the
        // inlet's extent in y, mean U (peak 1.5 U); 3D the pipe's paraboloid on the circular
        // inlet, mean U (peak 2 U), radius from the inlet's extent in y.
        const auto [low, high] = boundary_box(fluid_dofs_, boundary::inlet, comm_);
        const double                                      U = p_.mean_inflow_velocity;
        const VectorFunctionFromScalarFunctionObject<dim> profile(
            [low = low, high = high, U](const Point<dim>& x) {
              if constexpr (dim == 2)
                {
                  const double s = (x[1] - low[1]) / (high[1] - low[1]);
                  return 6.0 * U * s * (1 - s);
                }
              else
                {
                  const double R = (high[1] - low[1]) / 2, y = x[1] - (low[1] + high[1]) / 2,
                               z = x[2] - (low[2] + high[2]) / 2;
                  return 2.0 * U * std::max(0.0, 1 - (y * y + z * z) / (R * R));
                }
            },
            0, dim + 1);
        AffineConstraints<double> values(fluid_relevant_);
        add_boundary_constraints(fluid_dofs_, boundary::inlet, profile, values, velocity);
        for (const auto f : fluid_owned_)
          if (values.is_constrained(f))
            inflow_profile_[f] = values.get_inhomogeneity(f);
      }

    // The velocity nodes of obstacle and interface (the force's test function), if the fluid
    // has obstacle faces.
    unsigned int obstacle_faces = 0;
    for (const auto& cell : fluid_dofs_.active_cell_iterators())
      if (cell->is_locally_owned())
        for (const unsigned f : cell->face_indices())
          obstacle_faces += cell->at_boundary(f) && cell->face(f)->boundary_id() == boundary::obstacle;
    has_obstacle_ = Utilities::MPI::sum(obstacle_faces, comm_) > 0;
    if (has_obstacle_)
      {
        const Functions::ZeroFunction<dim> zero(dim + 1);
        AffineConstraints<double>          nodes(fluid_relevant_);
        for (const types::boundary_id id : {boundary::obstacle, boundary::interface})
          add_boundary_constraints(fluid_dofs_, id, zero, nodes, velocity);
        for (const auto f : fluid_owned_)
          if (nodes.is_constrained(f))
            force_dofs_.push_back(f);
      }

    // The monitor point: a structure node at the given reference position (1e-6 of the fluid's
    // diagonal), its DOFs on the rank that owns it.
    if (!p_.monitor_point.empty())
      {
        Point<dim> X;
        for (unsigned d = 0; d < dim; ++d)
          X[d] = p_.monitor_point[d];
        const double tolerance = 1e3 * geometry_tolerance_;
        for (const auto& cell : solid_dofs_.active_cell_iterators())
          if (cell->is_locally_owned() && monitor_dofs_.empty())
            for (const unsigned v : cell->vertex_indices())
              if (cell->vertex(v).distance(X) < tolerance &&
                  solid_owned_.is_element(cell->vertex_dof_index(v, 0)) && monitor_dofs_.empty())
                for (unsigned c = 0; c < dim; ++c)
                  monitor_dofs_.push_back(cell->vertex_dof_index(v, c));
        if (Utilities::MPI::sum(monitor_dofs_.empty() ? 0 : 1, comm_) == 0)
          {
            std::ostringstream where;
            for (unsigned d = 0; d < dim; ++d)
              where << (d > 0 ? ", " : "") << X[d];
            throw std::invalid_argument("parameter 'Monitor point' (Output): no structure mesh node at (" +
                                        where.str() + "); expected the reference position of one");
          }
      }
  }

  template <int dim>
  void CondensedFsi<dim>::apply_inflow(double time)
  {
    if (!p_.parabolic_inflow)
      return;
    const double T      = p_.inflow_ramp_time;
    const double factor = T > 0 && time < T ? (1 - std::cos(numbers::PI * time / T)) / 2 : 1.0;
    for (const auto& [f, value] : inflow_profile_)
      x_F_[f] = factor * value;
    x_F_.compress(VectorOperation::insert);
  }

  template <int dim>
  void CondensedFsi<dim>::record_forces(int number, double time, const TrilinosWrappers::MPI::Vector& R_free)
  {
    if (!has_obstacle_ && p_.monitor_point.empty())
      return;
    JsonLinesLog::Line line;
    line.add("event", std::string("obstacle_forces")).add("load_step", number).add("time", time);
    const char* axis[] = {"x", "y", "z"};
    last_force_.clear();
    if (has_obstacle_)
      {
        last_force_.assign(dim, 0.0);
        for (const auto f : force_dofs_)
          last_force_[f % (dim + 1)] -= R_free[f];
        Utilities::MPI::sum(ArrayView<const double>(last_force_), comm_, ArrayView<double>(last_force_));
        line.add("drag", last_force_[0]).add("lift", last_force_[1]);
        if (dim == 3)
          line.add("force_z", last_force_[2]);
      }
    last_monitor_.clear();
    if (!p_.monitor_point.empty())
      {
        last_monitor_.assign(dim, 0.0);
        for (std::size_t c = 0; c < monitor_dofs_.size(); ++c)
          last_monitor_[c] = d_S_[monitor_dofs_[c]];
        Utilities::MPI::sum(ArrayView<const double>(last_monitor_), comm_, ArrayView<double>(last_monitor_));
        for (unsigned c = 0; c < dim; ++c)
          line.add(std::string("monitor_displacement_") + axis[c], last_monitor_[c]);
      }
    log_.write(line);
    if (!forces_csv_.is_open())
      return;
    forces_csv_ << std::setprecision(12) << time;
    for (const double v : last_force_)
      forces_csv_ << "," << v;
    for (const double v : last_monitor_)
      forces_csv_ << "," << v;
    forces_csv_ << "\n" << std::flush;
  }

  template <int dim>
  std::string CondensedFsi<dim>::forces_csv_header() const
  {
    const char* axis[] = {"x", "y", "z"};
    std::string header = "time";
    if (has_obstacle_)
      header += dim == 3 ? ",drag,lift,force_z" : ",drag,lift";
    for (unsigned c = 0; c < dim && !p_.monitor_point.empty(); ++c)
      header += std::string(",monitor_displacement_") + axis[c];
    return header + "\n";
  }

  // The class is instantiated once, in condensed_fsi.cc; here the members this file defines.
#define PHYSICS_FSI_FORCE_MEMBERS(dim)                                                                       \
  template void        CondensedFsi<dim>::setup_inflow_and_monitors();                                       \
  template void        CondensedFsi<dim>::apply_inflow(double);                                              \
  template void        CondensedFsi<dim>::record_forces(int, double, const TrilinosWrappers::MPI::Vector&);  \
  template std::string CondensedFsi<dim>::forces_csv_header() const;
  PHYSICS_FSI_FORCE_MEMBERS(2)
  PHYSICS_FSI_FORCE_MEMBERS(3)
#undef PHYSICS_FSI_FORCE_MEMBERS
} // namespace physics::fsi
