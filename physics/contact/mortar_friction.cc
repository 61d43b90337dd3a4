// The tangential (stick/slip) rows of Coulomb friction at an active slave node (mortar_contact.h,
// coulomb_friction.h), linearized exactly with Sacado's forward AD.
#include "contact/coulomb_friction.h"
#include "contact/mortar_contact.h"

#include <Sacado.hpp>

#include <algorithm>

namespace physics::contact
{
  template <int dim>
  void MortarContact<dim>::add_friction_rows(
      unsigned int j, const std::vector<std::array<double, dim>>& slave_x, const std::vector<double>& lambda,
      const std::vector<double>& total, const std::map<global_dof_index, std::array<double, dim>>& dslip,
      const std::map<global_dof_index, double>& dw, const std::function<bool(global_dof_index)>& free_dof,
      ContactContribution& out)
  {
    using AD = Sacado::Fad::DFad<double>;
    // The node's rows are a function of lambda_j, of the positions of the nodes of its adjacent
    // faces (through the nodal frame), and of the nodal sums s_j = v_j - v_j^start and w_j. AD
    // variables in that order: lambda (dim), frame nodes (dim each), s_j (dim), w_j.
    const std::vector<unsigned int> frame_nodes = this->frame_nodes(j);
    const int n_frame = frame_nodes.size() * dim, first_slip = dim + n_frame, w_var = first_slip + dim,
              n_vars = w_var + 1;
    std::vector<std::vector<Point<AD, dim>>> faces;
    for (unsigned int f : slave_node_faces_[j])
      {
        std::vector<Point<AD, dim>> x;
        for (unsigned int k : slave_faces_.nodes[f])
          {
            const int      i = std::find(frame_nodes.begin(), frame_nodes.end(), k) - frame_nodes.begin();
            Point<AD, dim> p;
            for (int d = 0; d < dim; ++d)
              p[d] = AD(n_vars, dim + i * dim + d, slave_x[k][d]);
            x.push_back(p);
          }
        faces.push_back(x);
      }
    const int      stride = 2 * dim + 1;
    Point<AD, dim> lam, slip;
    for (int d = 0; d < dim; ++d)
      {
        lam[d]  = AD(n_vars, d, lambda[dim * j + d]);
        slip[d] = AD(n_vars, first_slip + d, total[j * stride + dim + d]);
      }
    const AD          w(n_vars, w_var, total[j * stride + stride - 1]);
    const FrictionLaw law{settings_.friction_coefficient, settings_.tangential_parameter,
                          settings_.complementarity_parameter};
    const auto        rows = coulomb_rows<AD, dim>(nodal_frame<AD, dim>(faces), lam, slip, w,
                                            state_.weighted_gap[j] / state_.weight[j], law);

    // The node's friction state (the same on every rank holding it).
    state_.slip[j] = rows.slip;
    double t2 = 0, u2 = 0, work = 0;
    for (int m = 0; m < dim - 1; ++m)
      {
        const double t = rows.tangential_multiplier[m].val(), u = rows.slip_increment[m].val();
        t2 += t * t;
        u2 += u * u;
        work += t * u;
      }
    state_.tangential[j]    = std::sqrt(t2);
    state_.slip_distance[j] = std::sqrt(u2) / state_.weight[j];
    state_.dissipation[j]   = work;

    auto add = [&](global_dof_index row, global_dof_index col, double value) {
      if (value != 0.0)
        out.matrix[row][col] += value;
    };
    for (int m = 1; m < dim; ++m)
      {
        const AD&              r   = rows.residual[m - 1];
        const global_dof_index row = constraint_row(j, m);
        // Every rank: the derivatives through its own faces' share of s_j and w_j.
        for (const auto& [dof, grad] : dslip)
          if (free_dof(dof))
            {
              double value = 0;
              for (int d = 0; d < dim; ++d)
                value += r.dx(first_slip + d) * grad[d];
              add(row, dof, value);
            }
        for (const auto& [dof, grad] : dw)
          if (free_dof(dof))
            add(row, dof, r.dx(w_var) * grad);
        if (!owns_slave_node(j))
          continue;
        // The owner: the residual and the derivatives with respect to lambda_j and the frame.
        out.constraint_residual[row] = r.val();
        for (int c = 0; c < dim; ++c)
          add(row, multiplier_index(j, c), r.dx(c));
        for (int i = 0; i < n_frame; ++i)
          {
            const global_dof_index dof = slave_nodes_[frame_nodes[i / dim]].dofs[i % dim];
            if (free_dof(dof))
              add(row, dof, r.dx(dim + i));
          }
      }
  }

  // MortarContact is instantiated in mortar_contact.cc; here only the member this file defines.
  template void MortarContact<2>::add_friction_rows(unsigned int, const std::vector<std::array<double, 2>>&,
                                                    const std::vector<double>&, const std::vector<double>&,
                                                    const std::map<global_dof_index, std::array<double, 2>>&,
                                                    const std::map<global_dof_index, double>&,
                                                    const std::function<bool(global_dof_index)>&,
                                                    ContactContribution&);
  template void MortarContact<3>::add_friction_rows(unsigned int, const std::vector<std::array<double, 3>>&,
                                                    const std::vector<double>&, const std::vector<double>&,
                                                    const std::map<global_dof_index, std::array<double, 3>>&,
                                                    const std::map<global_dof_index, double>&,
                                                    const std::function<bool(global_dof_index)>&,
                                                    ContactContribution&);
} // namespace physics::contact
