#include "contact/mortar_contact.h"

#include "common/row_exchange.h"
#include "common/mortar_integration.h"

#include <deal.II/base/bounding_box.h>
#include <deal.II/base/mpi.h>
#include <deal.II/boost_adaptors/bounding_box.h>
#include <deal.II/lac/trilinos_vector.h>
#include <deal.II/numerics/rtree.h>

#include <Sacado.hpp>

#include <limits>
#include <set>
#include <stdexcept>

namespace physics::contact
{
  using namespace physics::mortar; // the mortar integration shared with the FSI class (common/)
  using AD = Sacado::Fad::DFad<double>;
  /// The AD number of one slave/master face pair: the positions of both faces' vertices (at most
  /// 2 x 2 in 2D, 2 x 4 in 3D), held in the number itself. A DFad allocates its derivatives on the
  /// heap, and the pair loop creates and destroys thousands of them per face pair.
  template <int dim>
  constexpr int max_pair_variables = 2 * (1 << (dim - 1)) * dim;
  template <int dim>
  using PairAD = Sacado::Fad::SLFad<double, max_pair_variables<dim>>;

  namespace
  {
    /// Value and gradient (with respect to a list of DOFs) of one scalar.
    struct Linearized
    {
      double                                            value = 0.0;
      std::vector<std::pair<global_dof_index, double>> gradient;
    };

    /// Positions of a list of nodes as AD variables 0 .. n*dim-1 (variable i*dim+d = node i, axis d).
    template <int dim>
    std::vector<Point<PairAD<dim>, dim>> seed(const std::vector<std::array<double, dim>>& x, int n_vars,
                                              int first)
    {
      std::vector<Point<PairAD<dim>, dim>> r(x.size());
      for (std::size_t i = 0; i < x.size(); ++i)
        for (int d = 0; d < dim; ++d)
          r[i][d] = PairAD<dim>(n_vars, first + static_cast<int>(i) * dim + d, x[i][d]);
      return r;
    }

    /// Every displacement component of the node is prescribed (a Dirichlet node).
    template <int dim>
    bool prescribed(const SurfaceNode<dim>& node, const std::function<bool(global_dof_index)>& is_constrained)
    {
      return std::all_of(node.dofs.begin(), node.dofs.end(), is_constrained);
    }
  } // namespace

  template <int dim>
  void MortarContact<dim>::evaluate(const std::vector<std::array<double, dim>>& slave_x,
                                    const std::vector<std::array<double, dim>>& master_x,
                                    const std::vector<double>& lambda,
                                    const std::function<bool(global_dof_index)>& is_constrained,
                                    ContactContribution& out)
  {
    const unsigned int S = slave_nodes_.size();
    out                     = ContactContribution{};

    // Master faces in an R-tree of (enlarged) current bounding boxes.
    using Box = dealii::BoundingBox<dim>;
    std::vector<std::pair<Box, unsigned int>> master_boxes;
    auto face_box = [&](const std::vector<unsigned int>& nodes, const std::vector<std::array<double, dim>>& x) {
      dealii::Point<dim> lo, hi;
      for (int d = 0; d < dim; ++d)
        {
          lo[d] = hi[d] = x[nodes[0]][d];
          for (unsigned int a : nodes)
            {
              lo[d] = std::min(lo[d], x[a][d]);
              hi[d] = std::max(hi[d], x[a][d]);
            }
        }
      Box box(std::make_pair(lo, hi));
      box.extend(settings_.search_radius_factor * lo.distance(hi));
      return box;
    };
    for (unsigned int g = 0; g < master_faces_.nodes.size(); ++g)
      master_boxes.emplace_back(face_box(master_faces_.nodes[g], master_x), g);
    const auto tree = dealii::pack_rtree(master_boxes);

    // Per slave node: partial sums of this rank's faces: v_j (dim), with friction the slip
    // v_j - v_j^start (dim), and w_j; the gradients of v_j and (friction) of v_j - v_j^start and
    // w_j (by DOF).
    const bool friction = frictional();
    if (friction && (slave_start_.size() != S || master_start_.size() != master_nodes_.size()))
      throw std::logic_error("MortarContact::evaluate: friction needs set_step_start() first");
    const int           n_vectors = friction ? 2 : 1, stride = n_vectors * dim + 1;
    std::vector<double> partial(S * stride, 0.0);
    std::vector<std::map<global_dof_index, std::array<double, dim>>> dv(S), dslip(friction ? S : 0);
    std::vector<std::map<global_dof_index, double>>                 dw(friction ? S : 0);

    auto add = [&](global_dof_index row, global_dof_index col, double value) {
      if (value != 0.0)
        out.matrix[row][col] += value;
    };
    auto free_dof = [&](global_dof_index dof) { return dof >= n_dofs_ || !is_constrained(dof); };

    for (unsigned int f = 0; f < slave_faces_.nodes.size(); ++f)
      {
        if (!slave_faces_.locally_owned[f])
          continue;
        const auto& sf = slave_faces_.nodes[f];
        std::vector<std::array<double, dim>> xs;
        for (unsigned int j : sf)
          xs.push_back(slave_x[j]);
        std::vector<std::pair<Box, unsigned int>> hits;
        tree.query(boost::geometry::index::intersects(face_box(sf, slave_x)), std::back_inserter(hits));
        for (const auto& hit : hits)
          {
            // Multi-body mode: only master faces of bodies paired with this face's body.
            if (pairs_ && !pairs_->paired(slave_faces_.body[f], master_faces_.body[hit.second]))
              continue;
            const auto& mf = master_faces_.nodes[hit.second];
            std::vector<std::array<double, dim>> xm;
            for (unsigned int l : mf)
              xm.push_back(master_x[l]);
            const int ns = sf.size(), nm = mf.size(), n_vars = (ns + nm) * dim;
            if (n_vars > max_pair_variables<dim>)
              throw std::logic_error("mortar contact: a face pair with " + std::to_string(ns) + " + " +
                                     std::to_string(nm) + " vertices (linear faces have at most " +
                                     std::to_string(1 << (dim - 1)) + ")");
            const auto ads = seed<dim>(xs, n_vars, 0), adm = seed<dim>(xm, n_vars, ns * dim);
            const auto pair = integrate_pair<PairAD<dim>, dim>(ads, adm, settings_.dual);
            if (!pair.overlap)
              continue;
            // DOF of AD variable i.
            auto var_dof = [&](int i) {
              const int node = i / dim, d = i % dim;
              return node < ns ? slave_nodes_[sf[node]].dofs[d] : master_nodes_[mf[node - ns]].dofs[d];
            };

            for (int a = 0; a < ns; ++a)
              {
                const unsigned int j = sf[a];
                // v_j partial = sum_l M_jl x_l - sum_k D_jk x_k, with its gradient.
                for (int d = 0; d < dim; ++d)
                  {
                    PairAD<dim> v = 0.0;
                    for (int l = 0; l < nm; ++l)
                      v += pair.M[a][l] * adm[l][d];
                    for (int k = 0; k < ns; ++k)
                      v -= pair.D[a][k] * ads[k][d];
                    partial[j * stride + d] += v.val();
                    for (int i = 0; i < n_vars; ++i)
                      if (v.dx(i) != 0.0)
                        dv[j][var_dof(i)][d] += v.dx(i);
                    if (!friction)
                      continue;
                    // Slip: v_j minus the same sums with the step's start positions.
                    PairAD<dim> slip = v;
                    for (int l = 0; l < nm; ++l)
                      slip -= pair.M[a][l] * master_start_[mf[l]][d];
                    for (int k = 0; k < ns; ++k)
                      slip += pair.D[a][k] * slave_start_[sf[k]][d];
                    partial[j * stride + dim + d] += slip.val();
                    for (int i = 0; i < n_vars; ++i)
                      if (slip.dx(i) != 0.0)
                        dslip[j][var_dof(i)][d] += slip.dx(i);
                  }
                for (int k = 0; k < ns; ++k)
                  {
                    partial[j * stride + stride - 1] += pair.D[a][k].val();
                    if (friction)
                      for (int i = 0; i < n_vars; ++i)
                        if (pair.D[a][k].dx(i) != 0.0)
                          dw[j][var_dof(i)] += pair.D[a][k].dx(i);
                  }

                // Structural rows: slave + D^T lambda, master - M^T lambda; columns lambda and
                // (through dD, dM) the positions.
                for (int c = 0; c < dim; ++c)
                  {
                    const double           lam = lambda[dim * j + c];
                    const global_dof_index col = multiplier_index(j, c);
                    for (int k = 0; k < ns; ++k)
                      {
                        const global_dof_index row = slave_nodes_[sf[k]].dofs[c];
                        if (!free_dof(row))
                          continue;
                        out.residual[row] += pair.D[a][k].val() * lam;
                        add(row, col, pair.D[a][k].val());
                        for (int i = 0; i < n_vars; ++i)
                          if (free_dof(var_dof(i)))
                            add(row, var_dof(i), pair.D[a][k].dx(i) * lam);
                      }
                    for (int l = 0; l < nm; ++l)
                      {
                        const global_dof_index row = master_nodes_[mf[l]].dofs[c];
                        if (!free_dof(row))
                          continue;
                        out.residual[row] -= pair.M[a][l].val() * lam;
                        add(row, col, -pair.M[a][l].val());
                        for (int i = 0; i < n_vars; ++i)
                          if (free_dof(var_dof(i)))
                            add(row, var_dof(i), -pair.M[a][l].dx(i) * lam);
                      }
                  }
              }
          }
      }

    // Totals over all ranks' faces (the same on every rank holding the node): v_j, w_j; normals;
    // the active set.
    const std::vector<double> total = sum_over_ranks(partial, n_vectors);
    state_.active.assign(S, false);
    state_.covered.assign(S, false);
    state_.released.assign(S, false);
    state_.weighted_gap.assign(S, 0.0);
    state_.weight.assign(S, 0.0);
    state_.normal_pressure.assign(S, 0.0);
    state_.slip.assign(S, false);
    state_.tangential.assign(S, 0.0);
    state_.slip_distance.assign(S, 0.0);
    state_.dissipation.assign(S, 0.0);
    auto adjacent_positions = [&](unsigned int j, auto make) {
      using T = typename decltype(make(0, 0))::value_type;
      std::vector<std::vector<Point<T, dim>>> faces;
      for (unsigned int f : slave_node_faces_[j])
        {
          std::vector<Point<T, dim>> x;
          for (unsigned int k : slave_faces_.nodes[f])
            x.push_back(make(k, f));
          faces.push_back(x);
        }
      return faces;
    };
    for (unsigned int j = 0; j < S; ++j)
      {
        if (!needs_state_[j]) // some of its faces are not on this rank
          continue;
        const auto faces =
            adjacent_positions(j, [&](unsigned int k, unsigned int) -> Point<double, dim> { return slave_x[k]; });
        const auto frame = nodal_frame<double, dim>(faces);
        normals_[j]      = frame[0];
        constraint_row_[j] = constraint_components<double, dim>(frame); // which row holds which constraint
        const double w   = total[j * stride + stride - 1];
        double       g = 0, ln = 0;
        for (int d = 0; d < dim; ++d)
          {
            g += frame[0][d] * total[j * stride + d];
            ln += frame[0][d] * lambda[dim * j + d];
          }
        state_.weight[j]          = w;
        state_.weighted_gap[j]    = g;
        state_.normal_pressure[j] = ln;
        // A node is in contact only where a master face lies underneath a sizeable part of its
        // multiplier support (a sliver of overlap gives a meaningless nodal gap).
        state_.covered[j] = w > 1e-8 * std::pow(minimal_slave_face_size(), dim - 1);
        // Semi-smooth Newton: active where lambda_n - c_n g > 0. Before the first solve (lambda = 0)
        // this would leave touching bodies unsupported, so the first evaluation takes the
        // geometric guess: nodes that touch or penetrate start active.
        state_.released[j] =
            !settings_.prescribed_nodes_contact && prescribed(slave_nodes_[j], is_constrained);
        if (state_.released[j])
          state_.active[j] = false;
        else if (first_evaluation_)
          state_.active[j] = state_.covered[j] && g / w <= 1e-8 * minimal_slave_face_size();
        else
          state_.active[j] = state_.covered[j] && ln - settings_.complementarity_parameter * g / w > 0.0;
        state_.slip[j] = state_.active[j] && !friction; // frictionless: every contact node slides
      }

    first_evaluation_ = false;

    // Constraint rows. Every rank adds the n_j . dv_j part of the active normal rows it has partial
    // gradients for; the owner of node j adds the rest (normal derivative, tangential and identity
    // rows) and the constraint residual.
    for (unsigned int j = 0; j < S; ++j)
      {
        if (state_.active[j])
          for (const auto& [dof, grad] : dv[j])
            if (free_dof(dof))
              {
                double value = 0;
                for (int d = 0; d < dim; ++d)
                  value += normals_[j][d] * grad[d];
                add(constraint_row(j, 0), dof, value);
              }
        if (state_.active[j] && friction && needs_state_[j])
          add_friction_rows(j, slave_x, lambda, total, dslip[j], dw[j], free_dof, out);
        if (!owns_slave_node(j))
          continue;
        if (!state_.active[j])
          {
            for (int c = 0; c < dim; ++c)
              {
                out.matrix[multiplier_index(j, c)][multiplier_index(j, c)] += 1.0;
                out.constraint_residual[multiplier_index(j, c)] = lambda[dim * j + c];
              }
            continue;
          }
        // The nodal frame as AD function of the adjacent faces' node positions.
        const std::vector<unsigned int> vars   = frame_nodes(j); // slave node of each AD variable block
        const int                       n_vars = vars.size() * dim;
        const auto faces = adjacent_positions(j, [&](unsigned int k, unsigned int) {
          const int      i = std::find(vars.begin(), vars.end(), k) - vars.begin();
          Point<AD, dim> p;
          for (int d = 0; d < dim; ++d)
            p[d] = AD(n_vars, i * dim + d, slave_x[k][d]);
          return p;
        });
        const auto frame = nodal_frame<AD, dim>(faces);
        auto       dof_of = [&](int i) { return slave_nodes_[vars[i / dim]].dofs[i % dim]; };

        // Normal row: g~_j = n_j . v_j; its derivative through n_j: v_j . dn_j.
        out.constraint_residual[constraint_row(j, 0)] = state_.weighted_gap[j];
        for (int i = 0; i < n_vars; ++i)
          if (free_dof(dof_of(i)))
            {
              double value = 0;
              for (int d = 0; d < dim; ++d)
                value += total[j * stride + d] * frame[0][d].dx(i);
              add(constraint_row(j, 0), dof_of(i), value);
            }
        // Tangential rows, frictionless: tau_m . lambda_j = 0 (with friction: added above).
        for (int m = 1; m < dim && !friction; ++m)
          {
            const global_dof_index row = constraint_row(j, m);
            double                 r   = 0;
            for (int c = 0; c < dim; ++c)
              {
                r += frame[m][c].val() * lambda[dim * j + c];
                out.matrix[row][multiplier_index(j, c)] += frame[m][c].val();
              }
            out.constraint_residual[row] = r;
            for (int i = 0; i < n_vars; ++i)
              if (free_dof(dof_of(i)))
                {
                  double value = 0;
                  for (int c = 0; c < dim; ++c)
                    value += lambda[dim * j + c] * frame[m][c].dx(i);
                  add(row, dof_of(i), value);
                }
          }
      }
  }

  template class MortarContact<2>;
  template class MortarContact<3>;
} // namespace physics::contact
