#include "fsi/ale_fluid.h"

#include <deal.II/base/mpi.h>
#include <deal.II/base/quadrature_lib.h>
#include <deal.II/fe/fe_values.h>
#include <deal.II/lac/full_matrix.h>
#include <deal.II/lac/vector.h>

#include <Sacado.hpp>

#include <array>
#include <cmath>
#include <stdexcept>
#include <string>
#include <vector>

namespace physics::fsi
{
  using namespace dealii;

  TimeStencil TimeStencil::of(FluidTimeScheme scheme, double step_ratio, double theta)
  {
    const double w = step_ratio;
    switch (scheme)
      {
      case FluidTimeScheme::bdf1:
        return {1.0, -1.0, 0.0, 0.0};
      case FluidTimeScheme::bdf2:
        return {(1 + 2 * w) / (1 + w), -(1 + w), w * w / (1 + w), 0.0};
      case FluidTimeScheme::one_step_theta:
        return {1 / theta, -1 / theta, 0.0, -(1 - theta) / theta};
      default:
        return {};
      }
  }

  void TimeStencil::rate(const TrilinosWrappers::MPI::Vector& x, const TrilinosWrappers::MPI::Vector& x_old,
                         const TrilinosWrappers::MPI::Vector& x_older,
                         const TrilinosWrappers::MPI::Vector& rate_old, double dt,
                         TrilinosWrappers::MPI::Vector& out) const
  {
    // Owned copies first: any of the vectors may carry ghosts (assignment imports the owned part).
    const IndexSet                owned = x.locally_owned_elements();
    TrilinosWrappers::MPI::Vector r(owned, x.get_mpi_communicator()), v(r);
    const std::pair<const TrilinosWrappers::MPI::Vector*, double> terms[] = {
        {&x, a0 / dt}, {&x_old, a1 / dt}, {&x_older, a2 / dt}, {&rate_old, a3}};
    for (const auto& [vector, weight] : terms)
      if (weight != 0)
        {
          v = *vector;
          r.add(weight, v);
        }
    out = r;
  }

  void FluidProperties::check() const
  {
    if (!(density > 0) || !std::isfinite(density))
      throw std::invalid_argument("parameter 'Density' (Fluid): expected a positive number, got " +
                                  std::to_string(density));
    if (!(viscosity > 0) || !std::isfinite(viscosity))
      throw std::invalid_argument("parameter 'Viscosity' (Fluid): expected a positive number, got " +
                                  std::to_string(viscosity));
  }

  namespace
  {
    /// Forward AD with storage on the stack: 3D fluid (32) plus mesh (24) derivatives fit.
    using AD = Sacado::Fad::SLFad<double, 64>;

    inline double value_of(double x)
    {
      return x;
    }
    inline double value_of(const AD& x)
    {
      return x.val();
    }

    template <int dim, typename T>
    using Matrix = std::array<std::array<T, dim>, dim>;

    /// det A and A^-1 (closed forms for 2 x 2 and 3 x 3).
    template <int dim, typename T>
    T determinant_and_inverse(const Matrix<dim, T>& A, Matrix<dim, T>& inverse)
    {
      if constexpr (dim == 2)
        {
          const T det   = A[0][0] * A[1][1] - A[0][1] * A[1][0];
          inverse[0][0] = A[1][1] / det;
          inverse[0][1] = -A[0][1] / det;
          inverse[1][0] = -A[1][0] / det;
          inverse[1][1] = A[0][0] / det;
          return det;
        }
      else
        {
          Matrix<dim, T> cof;
          for (int i = 0; i < 3; ++i)
            for (int j = 0; j < 3; ++j)
              {
                const int i1 = (i + 1) % 3, i2 = (i + 2) % 3, j1 = (j + 1) % 3, j2 = (j + 2) % 3;
                cof[i][j] = A[i1][j1] * A[i2][j2] - A[i1][j2] * A[i2][j1];
              }
          const T det = A[0][0] * cof[0][0] + A[0][1] * cof[0][1] + A[0][2] * cof[0][2];
          for (int i = 0; i < 3; ++i)
            for (int j = 0; j < 3; ++j)
              inverse[i][j] = cof[j][i] / det;
          return det;
        }
    }

    /// Shape data of one FE on one cell's reference geometry: value, reference gradient and
    /// component of every local DOF at every quadrature point.
    template <int dim>
    struct ShapeData
    {
      std::vector<std::vector<double>>         value; ///< [q][i]
      std::vector<std::vector<Tensor<1, dim>>> grad;  ///< [q][i], reference gradient
      std::vector<unsigned int>                component;

      template <typename Values>
      void fill(const Values& fe_values)
      {
        const auto&        fe = fe_values.get_fe();
        const unsigned int n = fe.n_dofs_per_cell(), nq = fe_values.n_quadrature_points;
        value.assign(nq, std::vector<double>(n));
        grad.assign(nq, std::vector<Tensor<1, dim>>(n));
        component.resize(n);
        for (unsigned int i = 0; i < n; ++i)
          component[i] = fe.system_to_component_index(i).first;
        for (unsigned int q = 0; q < nq; ++q)
          for (unsigned int i = 0; i < n; ++i)
            {
              value[q][i] = fe_values.shape_value_component(i, q, component[i]);
              grad[q][i]  = fe_values.shape_grad_component(i, q, component[i]);
            }
      }
    };

    /// The moved geometry at one quadrature point: F = I + Grad d^G, det F, F^-1.
    template <int dim, typename T>
    struct MovedPoint
    {
      Matrix<dim, T> F_inverse;
      T              det_F;
    };

    template <int dim, typename T>
    MovedPoint<dim, T> moved_point(const ShapeData<dim>* mesh, unsigned int q, const std::vector<T>& d)
    {
      Matrix<dim, T> F;
      for (int a = 0; a < dim; ++a)
        for (int b = 0; b < dim; ++b)
          F[a][b] = a == b ? 1.0 : 0.0;
      if (mesh != nullptr)
        for (std::size_t j = 0; j < d.size(); ++j)
          for (int b = 0; b < dim; ++b)
            F[mesh->component[j]][b] += d[j] * mesh->grad[q][j][b];
      MovedPoint<dim, T> m;
      m.det_F = determinant_and_inverse<dim, T>(F, m.F_inverse);
      if (!(value_of(m.det_F) > 0))
        throw std::domain_error("inverted fluid cell: the ALE mesh motion gives det F = " +
                                std::to_string(value_of(m.det_F)));
      return m;
    }

    /// Everything the cell residual reads besides the unknowns.
    template <int dim>
    struct CellInput
    {
      ShapeData<dim>          fluid;
      const ShapeData<dim>*   mesh = nullptr; ///< null: mesh at rest
      std::vector<double>     JxW;            ///< reference dX weights
      std::vector<Point<dim>> X;              ///< reference quadrature points
      // History of the time derivative: a1 x_n + a2 x_{n-1} + a3 dt r_n per local DOF (fluid, mesh)
      std::vector<double> fluid_history, mesh_history;
      /// Boundary faces with a prescribed pressure: their shape data, normals and weights.
      struct Face
      {
        double                      pressure;
        ShapeData<dim>              fluid, mesh;
        std::vector<Tensor<1, dim>> normal; ///< reference outward normal
        std::vector<double>         JxW;
      };
      std::vector<Face> faces;
    };

    /// The cell residual R_i (fluid DOFs i) for fluid values `u` and mesh displacements `d`.
    template <int dim, typename T>
    void cell_residual(const CellInput<dim>& in, const FluidModel<dim>& model, const TimeStencil& stencil,
                       const std::vector<T>& u, const std::vector<T>& d, std::vector<T>& R)
    {
      const auto&        fl = in.fluid;
      const unsigned int n = u.size(), nq = in.JxW.size();
      const double       rho = model.properties.density, mu = model.properties.viscosity, nu = mu / rho;
      const bool         transient = model.scheme != FluidTimeScheme::steady;
      const double       dt        = model.time_step;
      R.assign(n, T(0.0));

      // Pass 1: geometry of the moved cell (grad = F^-T Grad, dx = det F dX) and its size h.
      std::vector<std::vector<std::array<T, dim>>> g(nq, std::vector<std::array<T, dim>>(n));
      std::vector<T>                               dx(nq);
      T                                            volume = 0.0;
      for (unsigned int q = 0; q < nq; ++q)
        {
          const auto m = moved_point<dim, T>(in.mesh, q, d);
          dx[q]        = m.det_F * in.JxW[q];
          volume += dx[q];
          for (unsigned int i = 0; i < n; ++i)
            for (int k = 0; k < dim; ++k)
              {
                g[q][i][k] = 0.0;
                for (int l = 0; l < dim; ++l)
                  g[q][i][k] += m.F_inverse[l][k] * fl.grad[q][i][l];
              }
        }
      using std::pow;
      using std::sqrt;
      const T h2 = pow(volume, 2.0 / dim); // h^2 with the cell size h = |K|^(1/dim)

      // Pass 2: the weak form at each quadrature point.
      for (unsigned int q = 0; q < nq; ++q)
        {
          std::array<T, dim>                  vel, dudt, c, conv, r_M, grad_p;
          std::array<std::array<T, dim>, dim> grad_u;
          T                                   p = 0.0;
          for (int a = 0; a < dim; ++a)
            {
              vel[a] = dudt[a] = c[a] = grad_p[a] = 0.0;
              for (int k = 0; k < dim; ++k)
                grad_u[a][k] = 0.0;
            }
          for (unsigned int i = 0; i < n; ++i)
            {
              const unsigned int a = fl.component[i];
              if (a < dim)
                {
                  vel[a] += u[i] * fl.value[q][i];
                  dudt[a] += (stencil.a0 * u[i] + in.fluid_history[i]) * fl.value[q][i] / dt;
                  for (int k = 0; k < dim; ++k)
                    grad_u[a][k] += u[i] * g[q][i][k];
                }
              else
                {
                  p += u[i] * fl.value[q][i];
                  for (int k = 0; k < dim; ++k)
                    grad_p[k] += u[i] * g[q][i][k];
                }
            }
          // Convective velocity c = u - w, w the grid velocity from the same time stencil.
          for (int a = 0; a < dim; ++a)
            c[a] = vel[a];
          if (in.mesh != nullptr && transient)
            for (std::size_t j = 0; j < d.size(); ++j)
              c[in.mesh->component[j]] -= (stencil.a0 * d[j] + in.mesh_history[j]) * in.mesh->value[q][j] / dt;

          Vector<double> f(dim);
          if (model.body_force != nullptr)
            {
              Point<dim> x = in.X[q];
              if (in.mesh != nullptr)
                for (std::size_t j = 0; j < d.size(); ++j)
                  x[in.mesh->component[j]] += value_of(d[j]) * in.mesh->value[q][j];
              model.body_force->vector_value(x, f);
            }
          T c2 = 0.0, div_u = 0.0;
          for (int a = 0; a < dim; ++a)
            {
              c2 += c[a] * c[a];
              div_u += grad_u[a][a];
              conv[a] = 0.0;
              for (int k = 0; k < dim; ++k)
                conv[a] += c[k] * grad_u[a][k];
              r_M[a] = rho * ((transient ? dudt[a] : T(0.0)) + conv[a]) + grad_p[a] - rho * f[a];
            }
          const T tau_M =
              1.0 / sqrt((transient && model.tau_with_time_step ? 4.0 / (dt * dt) : 0.0) + 4.0 * c2 / h2 +
                         16.0 * nu * nu / (h2 * h2));
          const T tau_C = h2 / (4.0 * tau_M);

          for (unsigned int i = 0; i < n; ++i)
            {
              const unsigned int a   = fl.component[i];
              const double       phi = fl.value[q][i];
              const auto&        gi  = g[q][i];
              T                  r   = 0.0;
              if (a < dim)
                {
                  T c_grad_v = 0.0, viscous = 0.0;
                  for (int k = 0; k < dim; ++k)
                    {
                      c_grad_v += c[k] * gi[k];
                      viscous += (grad_u[a][k] + grad_u[k][a]) * gi[k];
                    }
                  r = (rho * ((transient ? dudt[a] : T(0.0)) + conv[a]) - rho * f[a]) * phi + mu * viscous -
                      p * gi[a] + tau_M * c_grad_v * r_M[a] + rho * tau_C * div_u * gi[a];
                }
              else
                {
                  T pspg = 0.0;
                  for (int k = 0; k < dim; ++k)
                    pspg += gi[k] * r_M[k];
                  r = phi * div_u + tau_M / rho * pspg;
                }
              R[i] += r * dx[q];
            }
        }

      // Prescribed pressure P on boundary faces: + int P n . v ds, n ds = det F F^-T N dS (Nanson).
      for (const auto& face : in.faces)
        for (unsigned int q = 0; q < face.JxW.size(); ++q)
          {
            const auto         m = moved_point<dim, T>(in.mesh != nullptr ? &face.mesh : nullptr, q, d);
            std::array<T, dim> n_ds;
            for (int a = 0; a < dim; ++a)
              {
                n_ds[a] = 0.0;
                for (int l = 0; l < dim; ++l)
                  n_ds[a] += m.F_inverse[l][a] * face.normal[q][l];
                n_ds[a] *= m.det_F * face.JxW[q];
              }
            for (unsigned int i = 0; i < n; ++i)
              if (face.fluid.component[i] < dim)
                R[i] += face.pressure * n_ds[face.fluid.component[i]] * face.fluid.value[q][i];
          }
    }

    template <int dim>
    void read_local(const TrilinosWrappers::MPI::Vector* v, const std::vector<types::global_dof_index>& dofs,
                    std::vector<double>& out)
    {
      out.assign(dofs.size(), 0.0);
      if (v != nullptr)
        for (std::size_t i = 0; i < dofs.size(); ++i)
          out[i] = (*v)[dofs[i]];
    }

    /// a1 x_n + a2 x_{n-1} + a3 dt r_n on the cell's DOFs (missing vectors read as zero).
    template <int dim>
    void history(const TrilinosWrappers::MPI::Vector* old, const TrilinosWrappers::MPI::Vector* older,
                 const TrilinosWrappers::MPI::Vector* rate, const TimeStencil& stencil, double dt,
                 const std::vector<types::global_dof_index>& dofs, std::vector<double>& out)
    {
      std::vector<double> x_old, x_older, r_old;
      read_local<dim>(old, dofs, x_old);
      read_local<dim>(older, dofs, x_older);
      read_local<dim>(rate, dofs, r_old);
      out.resize(dofs.size());
      for (std::size_t i = 0; i < dofs.size(); ++i)
        out[i] = stencil.a1 * x_old[i] + stencil.a2 * x_older[i] + stencil.a3 * dt * r_old[i];
    }
  } // namespace

  template <int dim>
  void assemble_ale_fluid(const DoFHandler<dim>& fluid_dofs, const DoFHandler<dim>* mesh_dofs,
                          const FluidModel<dim>& model, const FluidState<dim>& state,
                          const AffineConstraints<double>& constraints,
                          TrilinosWrappers::MPI::Vector& residual, TrilinosWrappers::SparseMatrix* jacobian,
                          TrilinosWrappers::SparseMatrix*  shape_derivative,
                          const AffineConstraints<double>* mesh_constraints)
  {
    model.properties.check();
    if (model.scheme != FluidTimeScheme::steady && !(model.time_step > 0))
      throw std::invalid_argument("parameter 'Time step' (Fluid): expected a positive number");
    if (model.scheme == FluidTimeScheme::one_step_theta && !(model.theta >= 0.5 && model.theta <= 1))
      throw std::invalid_argument("parameter 'Theta' (Time): expected 1/2 <= theta <= 1 (one-step-theta), got " +
                                  std::to_string(model.theta));
    const bool moving = mesh_dofs != nullptr && state.mesh != nullptr;
    if (shape_derivative != nullptr && (!moving || mesh_constraints == nullptr))
      throw std::invalid_argument(
          "assemble_ale_fluid: shape derivatives need the mesh DoFHandler, state and constraints");
    const TimeStencil stencil = model.stencil();

    const QGauss<dim>     quadrature(2);
    const QGauss<dim - 1> face_quadrature(2);
    const UpdateFlags flags = update_values | update_gradients | update_JxW_values | update_quadrature_points;
    FEValues<dim>     fluid_values(fluid_dofs.get_fe(), quadrature, flags);
    FEFaceValues<dim> fluid_face(fluid_dofs.get_fe(), face_quadrature, flags | update_normal_vectors);
    std::unique_ptr<FEValues<dim>>     mesh_values;
    std::unique_ptr<FEFaceValues<dim>> mesh_face;
    if (moving)
      {
        mesh_values = std::make_unique<FEValues<dim>>(mesh_dofs->get_fe(), quadrature, flags);
        mesh_face   = std::make_unique<FEFaceValues<dim>>(mesh_dofs->get_fe(), face_quadrature, flags);
      }

    const unsigned int                   nf = fluid_dofs.get_fe().n_dofs_per_cell();
    const unsigned int                   nm = moving ? mesh_dofs->get_fe().n_dofs_per_cell() : 0;
    std::vector<types::global_dof_index> fluid_indices(nf), mesh_indices(nm);
    CellInput<dim>                       in;
    ShapeData<dim>                       mesh_shape;
    std::vector<double>                  u_local, d_local, R_local;
    FullMatrix<double>                   K_local(nf, nf), S_local(nf, nm);
    Vector<double>                       r_local(nf);
    const bool                           with_shape    = shape_derivative != nullptr;
    const unsigned int                   n_independent = nf + (with_shape ? nm : 0);

    // An inverted cell is found by its owner only: every rank learns of it (below) before the
    // collective compress(), so that all of them throw and none waits.
    std::string inverted;
    for (const auto& cell : fluid_dofs.active_cell_iterators())
      try
        {
          if (!cell->is_locally_owned() || !inverted.empty())
            continue;
          fluid_values.reinit(cell);
          in.fluid.fill(fluid_values);
          in.JxW = fluid_values.get_JxW_values();
          in.X   = fluid_values.get_quadrature_points();
          cell->get_dof_indices(fluid_indices);
          read_local<dim>(state.fluid, fluid_indices, u_local);
          history<dim>(state.fluid_old, state.fluid_older, state.fluid_rate, stencil, model.time_step, fluid_indices,
                       in.fluid_history);
          typename DoFHandler<dim>::active_cell_iterator mesh_cell;
          in.mesh = nullptr;
          d_local.clear();
          if (moving)
            {
              mesh_cell = typename DoFHandler<dim>::active_cell_iterator(
                  &fluid_dofs.get_triangulation(), cell->level(), cell->index(), mesh_dofs);
              mesh_values->reinit(mesh_cell);
              mesh_shape.fill(*mesh_values);
              in.mesh = &mesh_shape;
              mesh_cell->get_dof_indices(mesh_indices);
              read_local<dim>(state.mesh, mesh_indices, d_local);
              history<dim>(state.mesh_old, state.mesh_older, state.mesh_rate, stencil, model.time_step, mesh_indices,
                           in.mesh_history);
            }
          in.faces.clear();
          for (const unsigned int f : cell->face_indices())
            if (cell->at_boundary(f))
              if (const auto it = model.boundary_pressures.find(cell->face(f)->boundary_id());
                  it != model.boundary_pressures.end())
                {
                  typename CellInput<dim>::Face face;
                  face.pressure = it->second;
                  fluid_face.reinit(cell, f);
                  face.fluid.fill(fluid_face);
                  face.normal = fluid_face.get_normal_vectors();
                  face.JxW    = fluid_face.get_JxW_values();
                  if (moving)
                    {
                      mesh_face->reinit(mesh_cell, f);
                      face.mesh.fill(*mesh_face);
                    }
                  in.faces.push_back(std::move(face));
                }

          if (jacobian == nullptr && !with_shape)
            {
              cell_residual<dim, double>(in, model, stencil, u_local, d_local, R_local);
              for (unsigned int i = 0; i < nf; ++i)
                r_local[i] = R_local[i];
              constraints.distribute_local_to_global(r_local, fluid_indices, residual);
              continue;
            }
          // Forward AD: the independent variables are the cell's fluid values, then (for the
          // shape derivative) its mesh displacements.
          std::vector<AD> u_ad(nf), d_ad(d_local.size()), R_ad;
          for (unsigned int i = 0; i < nf; ++i)
            u_ad[i] = AD(n_independent, i, u_local[i]);
          for (std::size_t j = 0; j < d_local.size(); ++j)
            d_ad[j] = with_shape ? AD(n_independent, nf + j, d_local[j]) : AD(d_local[j]);
          cell_residual<dim, AD>(in, model, stencil, u_ad, d_ad, R_ad);
          for (unsigned int i = 0; i < nf; ++i)
            {
              r_local[i] = R_ad[i].val();
              for (unsigned int j = 0; j < nf; ++j)
                K_local(i, j) = R_ad[i].size() > 0 ? R_ad[i].fastAccessDx(j) : 0.0;
              for (unsigned int j = 0; with_shape && j < nm; ++j)
                S_local(i, j) = R_ad[i].size() > 0 ? R_ad[i].fastAccessDx(nf + j) : 0.0;
            }
          if (jacobian != nullptr)
            constraints.distribute_local_to_global(K_local, r_local, fluid_indices, *jacobian, residual);
          else
            constraints.distribute_local_to_global(r_local, fluid_indices, residual);
          if (with_shape)
            constraints.distribute_local_to_global(S_local, fluid_indices, *mesh_constraints, mesh_indices,
                                                   *shape_derivative);
        }
      catch (const std::domain_error& e)
        {
          inverted = e.what();
        }
    const MPI_Comm comm = residual.get_mpi_communicator();
    if (Utilities::MPI::max(inverted.empty() ? 0 : 1, comm) > 0)
      throw std::domain_error(inverted.empty() ? "inverted fluid cell on another rank" : inverted);
    residual.compress(VectorOperation::add);
    if (jacobian != nullptr)
      jacobian->compress(VectorOperation::add);
    if (shape_derivative != nullptr)
      shape_derivative->compress(VectorOperation::add);
  }

  template void assemble_ale_fluid<2>(const DoFHandler<2>&, const DoFHandler<2>*, const FluidModel<2>&,
                                      const FluidState<2>&, const AffineConstraints<double>&,
                                      TrilinosWrappers::MPI::Vector&, TrilinosWrappers::SparseMatrix*,
                                      TrilinosWrappers::SparseMatrix*, const AffineConstraints<double>*);
  template void assemble_ale_fluid<3>(const DoFHandler<3>&, const DoFHandler<3>*, const FluidModel<3>&,
                                      const FluidState<3>&, const AffineConstraints<double>&,
                                      TrilinosWrappers::MPI::Vector&, TrilinosWrappers::SparseMatrix*,
                                      TrilinosWrappers::SparseMatrix*, const AffineConstraints<double>*);
} // namespace physics::fsi
