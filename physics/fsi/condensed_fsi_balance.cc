// CondensedFsi (condensed_fsi_problem.h): the fluid's mass balance and the wall's displacement
// profile, measured after each converged time step.
//
// Mass balance. The continuity equation tested with q = 1 (the sum of all pressure rows; PSPG
// adds nothing, grad q = 0) says int_Omega div u dx = 0 on the moved mesh at t_{n+1}; with
// 2 x 2 (x 2) Gauss points this integral is exact on Q1 cells (the integrand cof(F) : Grad u is
// of degree 3 at most per reference direction), so the divergence theorem makes
//   inflow - outflow = int_Gamma u . n ds   (u = grid velocity on the wall),
// and the BDF grid velocity makes the wall flux the fluid's BDF volume rate, up to the
// difference between the volume swept in the step and its end-point approximation. Logged per
// step: the volume change of the BDF stencil dV = a0 V_{n+1} + a1 V_n + a2 V_{n-1} (BDF1:
// V_{n+1} - V_n), dt (Q_in - Q_out), their difference relative to dt Q_in, and the wall flux.
#include "fsi/condensed_fsi_problem.h"

#include <deal.II/base/mpi.h>
#include <deal.II/base/quadrature_lib.h>
#include <deal.II/fe/fe_values.h>
#include <deal.II/fe/mapping_q_eulerian.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <iomanip>
#include <sstream>

namespace physics::fsi
{
  using namespace dealii;

  template <int dim>
  typename CondensedFsi<dim>::FluidBalance CondensedFsi<dim>::fluid_balance() const
  {
    MappingQEulerian<dim, TrilinosWrappers::MPI::Vector> moved(1, mesh_dofs_, d_G_ghosted_);
    const QGauss<dim>                                    quadrature(2);
    const QGauss<dim - 1>                                face_quadrature(2);
    FEValues<dim>                    cell_values(moved, fluid_fe_, quadrature, update_JxW_values);
    FEFaceValues<dim>                face_values(moved, fluid_fe_, face_quadrature,
                                                 update_values | update_normal_vectors | update_JxW_values);
    const FEValuesExtractors::Vector velocity(0);
    std::vector<Tensor<1, dim>>      u(face_quadrature.size());
    FluidBalance                     b;
    for (const auto& cell : fluid_dofs_.active_cell_iterators())
      if (cell->is_locally_owned())
        {
          cell_values.reinit(cell);
          for (unsigned q = 0; q < quadrature.size(); ++q)
            b.volume += cell_values.JxW(q);
          for (const unsigned f : cell->face_indices())
            if (cell->at_boundary(f))
              {
                face_values.reinit(cell, f);
                face_values[velocity].get_function_values(x_F_ghosted_, u);
                double flux = 0;
                for (unsigned q = 0; q < face_quadrature.size(); ++q)
                  flux += u[q] * face_values.normal_vector(q) * face_values.JxW(q);
                const auto id = cell->face(f)->boundary_id();
                (id == boundary::inlet    ? b.inflow
                 : id == boundary::outlet ? b.outflow
                                          : b.wall_flux) += id == boundary::inlet ? -flux : flux;
              }
        }
    for (double* v : {&b.volume, &b.inflow, &b.outflow, &b.wall_flux})
      *v = Utilities::MPI::sum(*v, comm_);
    return b;
  }

  template <int dim>
  std::vector<double> CondensedFsi<dim>::wall_profile() const
  {
    std::vector<double> sum(station_x_.size(), 0.0);
    for (const auto& node : wall_nodes_)
      for (unsigned c = 0; c < dim; ++c)
        sum[node.station] += d_S_[node.dof + c] * node.outward[c];
    Utilities::MPI::sum(ArrayView<const double>(sum), comm_, ArrayView<double>(sum));
    for (std::size_t k = 0; k < sum.size(); ++k)
      sum[k] /= station_count_[k];
    return sum;
  }

  template <int dim>
  void CondensedFsi<dim>::record_step(int number, double time)
  {
    // The largest outward wall displacement (normal to the wall).
    double largest = 0;
    for (const auto& node : wall_nodes_)
      {
        double normal = 0;
        for (unsigned c = 0; c < dim; ++c)
          normal += d_S_[node.dof + c] * node.outward[c];
        largest = std::max(largest, std::abs(normal));
      }
    max_wall_displacement_.push_back(Utilities::MPI::max(largest, comm_));

    const FluidBalance b        = fluid_balance();
    const double       dt       = fluid_model_.time_step;
    // The volume's rate through the fluid's stencil, as the interface velocity's: with it the
    // discrete balance dV/dt = Q_in - Q_out holds up to the geometric nonlinearity of V.
    const double       rate     = fluid_model_.stencil().rate(b.volume, volume_old_, volume_older_, volume_rate_, dt);
    const double       change   = dt * rate;
    const double       net      = dt * (b.inflow - b.outflow);
    const double       balance  = change - net;
    const double       relative = std::abs(balance) / std::max(std::abs(dt * b.inflow), 1e-300);
    volume_older_               = volume_old_;
    volume_old_                 = b.volume;
    volume_rate_                = rate;
    if (p_.parabolic_inflow || fluid_model_.boundary_pressures.at(boundary::inlet) != 0)
      max_mass_imbalance_ = std::max(max_mass_imbalance_, relative);
    JsonLinesLog::Line line;
    line.add("event", std::string("fluid_balance"))
        .add("load_step", number)
        .add("time", time)
        .add("volume", b.volume)
        .add("volume_change", change)
        .add("inflow", b.inflow)
        .add("outflow", b.outflow)
        .add("wall_flux", b.wall_flux)
        .add("mass_imbalance", balance)
        .add("mass_imbalance_relative", relative)
        .add("max_wall_displacement", max_wall_displacement_.back());
    log_.write(line);

    const auto profile = wall_profile();
    if (!wall_csv_.is_open())
      return;
    wall_csv_ << std::setprecision(10) << time;
    for (const double d : profile)
      wall_csv_ << "," << d;
    wall_csv_ << "\n" << std::flush;
  }

  template <int dim>
  std::string CondensedFsi<dim>::checkpoint_kind() const
  {
    std::ostringstream kind;
    kind << "fsi " << dim << "D (fluid " << fluid_tria_.n_global_active_cells() << " cells, structure "
         << solid_tria_.n_global_active_cells() << " cells, " << n_solid_ + n_fluid_ + n_mesh_ << " DOFs)";
    return kind.str();
  }

  template <int dim>
  std::vector<std::pair<const char*, TrilinosWrappers::MPI::Vector CondensedFsi<dim>::*>>
  CondensedFsi<dim>::state_vectors()
  {
    return {{"d_S", &CondensedFsi::d_S_},         {"d_S_old", &CondensedFsi::d_S_old_},
            {"d_S_older", &CondensedFsi::d_S_older_}, {"x_F", &CondensedFsi::x_F_},
            {"x_F_old", &CondensedFsi::x_F_old_},     {"x_F_older", &CondensedFsi::x_F_older_},
            {"d_G", &CondensedFsi::d_G_},         {"d_G_old", &CondensedFsi::d_G_old_},
            {"d_G_older", &CondensedFsi::d_G_older_}, {"d_S_rate", &CondensedFsi::d_S_rate_},
            {"x_F_rate", &CondensedFsi::x_F_rate_},   {"d_G_rate", &CondensedFsi::d_G_rate_}};
  }

  template <int dim>
  std::vector<std::tuple<std::string, std::string, std::ofstream CondensedFsi<dim>::*>>
  CondensedFsi<dim>::csv_files()
  {
    return {{"fsi/wall_csv", "wall_displacement.csv", &CondensedFsi::wall_csv_},
            {"fsi/forces_csv", "forces.csv", &CondensedFsi::forces_csv_}};
  }

  template <int dim>
  void CondensedFsi<dim>::save_state(Checkpoint& c) const
  {
    for (const auto& [name, v] : state_vectors())
      c.store(std::string("fsi/") + name, this->*v);
    dynamics_->save(c, "fsi/structure");
    c.store("fsi/lambda_old", lambda_old_);
    c.set("fsi/steps_done", steps_done_);
    c.set("fsi/max_wall_displacement", max_wall_displacement_);
    c.set("fsi/volumes", std::vector<double>{volume_old_, volume_older_, volume_rate_});
    c.set("fsi/last_time_step", last_time_step_);
    c.set("fsi/max_mass_imbalance", max_mass_imbalance_);
    c.set_text("fsi/fluid_vtk", fluid_vtk_->entries());
    c.set_text("fsi/solid_vtk", solid_vtk_->entries());
    c.set("fsi/obstacle_force", last_force_);
    c.set("fsi/monitor_displacement", last_monitor_);
    // The CSV files as they are (rank 0 writes them; empty where a file is not written).
    for (const auto& [key, file, stream] : csv_files())
      {
        std::string csv;
        if (rank_ == 0 && (this->*stream).is_open())
          {
            std::ifstream      in(p_.output_directory + "/" + file);
            std::ostringstream text;
            text << in.rdbuf();
            csv = text.str();
          }
        c.set_text(key, csv);
      }
  }

  template <int dim>
  void CondensedFsi<dim>::load_state(const Checkpoint& c)
  {
    for (const auto& [name, v] : state_vectors())
      c.restore(std::string("fsi/") + name, this->*v);
    dynamics_->load(c, "fsi/structure");
    c.restore("fsi/lambda_old", lambda_old_);
    steps_done_            = static_cast<int>(c.number("fsi/steps_done"));
    max_wall_displacement_ = c.numbers("fsi/max_wall_displacement");
    const auto& volumes    = c.numbers("fsi/volumes");
    volume_old_            = volumes.at(0);
    volume_older_          = volumes.at(1);
    volume_rate_           = volumes.at(2);
    last_time_step_        = c.number("fsi/last_time_step");
    max_mass_imbalance_    = c.number("fsi/max_mass_imbalance");
    fluid_vtk_->restore(c.text("fsi/fluid_vtk"));
    solid_vtk_->restore(c.text("fsi/solid_vtk"));
    last_force_   = c.numbers("fsi/obstacle_force");
    last_monitor_ = c.numbers("fsi/monitor_displacement");
    // The CSV files this run writes, as they were at the checkpoint, continued from there.
    for (const auto& [key, file, stream] : csv_files())
      if (rank_ == 0 && (this->*stream).is_open())
        {
          (this->*stream).close();
          const std::string path = p_.output_directory + "/" + file;
          write_atomically(path, [&, key = key](std::ostream& out) { out << c.text(key); });
          (this->*stream).open(path, std::ios::app);
        }
    // The ghosted copies (the interface velocities follow in the next begin_step).
    d_S_ghosted_ = d_S_;
    x_F_ghosted_ = x_F_;
    d_G_ghosted_ = d_G_;
  }

  // The class is instantiated once, in condensed_fsi.cc; here the members this file defines.
#define PHYSICS_FSI_BALANCE_MEMBERS(dim)                                                         \
  template typename CondensedFsi<dim>::FluidBalance CondensedFsi<dim>::fluid_balance() const;   \
  template std::vector<double> CondensedFsi<dim>::wall_profile() const;                        \
  template void                CondensedFsi<dim>::record_step(int, double);                    \
  template std::string         CondensedFsi<dim>::checkpoint_kind() const;                     \
  template std::vector<std::pair<const char*, TrilinosWrappers::MPI::Vector CondensedFsi<dim>::*>>       \
  CondensedFsi<dim>::state_vectors();                                                          \
  template std::vector<std::tuple<std::string, std::string, std::ofstream CondensedFsi<dim>::*>>         \
  CondensedFsi<dim>::csv_files();                                                              \
  template void                CondensedFsi<dim>::save_state(Checkpoint&) const;               \
  template void                CondensedFsi<dim>::load_state(const Checkpoint&);
  PHYSICS_FSI_BALANCE_MEMBERS(2)
  PHYSICS_FSI_BALANCE_MEMBERS(3)
#undef PHYSICS_FSI_BALANCE_MEMBERS
} // namespace physics::fsi
