#include "contact/mortar_contact.h"

#include "common/row_exchange.h"
#include "contact/mortar_integration.h"
#include "contact/self_contact.h"

#include <deal.II/base/bounding_box.h>
#include <deal.II/base/mpi.h>
#include <deal.II/boost_adaptors/bounding_box.h>
#include <deal.II/dofs/dof_tools.h>
#include <deal.II/lac/trilinos_vector.h>
#include <deal.II/numerics/rtree.h>

#include <Sacado.hpp>
#include <boost/serialization/vector.hpp>

#include <limits>
#include <set>
#include <stdexcept>
#include <unordered_map>

namespace physics::contact
{
  using AD = Sacado::Fad::DFad<double>;

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
    std::vector<Point<AD, dim>> seed(const std::vector<std::array<double, dim>>& x, int n_vars, int first)
    {
      std::vector<Point<AD, dim>> r(x.size());
      for (std::size_t i = 0; i < x.size(); ++i)
        for (int d = 0; d < dim; ++d)
          r[i][d] = AD(n_vars, first + static_cast<int>(i) * dim + d, x[i][d]);
      return r;
    }

    /// Unit normal and dim-1 unit tangents at a slave node from its adjacent faces (outward unit
    /// normals at the face centres, averaged), for any scalar type.
    template <typename T, int dim>
    std::array<Point<T, dim>, dim> nodal_frame(const std::vector<std::vector<Point<T, dim>>>& faces)
    {
      Point<T, dim> n;
      for (int d = 0; d < dim; ++d)
        n[d] = 0.0;
      for (const auto& f : faces)
        {
          const auto nf = face_unit_normal<T, dim>(f);
          for (int d = 0; d < dim; ++d)
            n[d] += nf[d];
        }
      const T len = sqrt_of(dot<T, dim>(n, n));
      for (int d = 0; d < dim; ++d)
        n[d] /= len;
      std::array<Point<T, dim>, dim> frame;
      frame[0] = n;
      if constexpr (dim == 2)
        frame[1] = {{-n[1], n[0]}};
      else
        {
          // First tangent: the coordinate axis least aligned with n, made orthogonal to n.
          int axis = 0;
          for (int d = 1; d < 3; ++d)
            if (std::abs(value_of(n[d])) < std::abs(value_of(n[axis])))
              axis = d;
          Point<T, 3> t;
          for (int d = 0; d < 3; ++d)
            t[d] = (d == axis ? 1.0 : 0.0) - n[axis] * n[d];
          const T tl = sqrt_of(dot<T, 3>(t, t));
          for (int d = 0; d < 3; ++d)
            t[d] /= tl;
          frame[1] = t;
          frame[2] = cross<T>(n, t);
        }
      return frame;
    }

    /// The contact faces of this rank's own and ghost cells, flattened (for an all-gather of the
    /// master faces): face f has the vertices offsets[f] .. offsets[f+1]-1, ordered around the
    /// face for an outward normal.
    struct LocalSurfaceFaces
    {
      std::vector<unsigned int>     boundary;    ///< per face: its boundary id
      std::vector<unsigned int>     body;        ///< per face: material id of its cell
      std::vector<unsigned int>     owned;       ///< per face: 1 if its cell is locally owned
      std::vector<unsigned int>     offsets{0};  ///< per face, and one past the last
      std::vector<global_dof_index> dofs;        ///< dim per vertex
      std::vector<double>           coordinates; ///< dim per vertex (reference position)

      template <class Archive>
      void serialize(Archive& ar, const unsigned int)
      {
        ar& boundary& body& owned& offsets& dofs& coordinates& components;
      }

      std::size_t size() const { return body.size(); }

      /// The faces f with keep(f), in order.
      template <class Predicate>
      LocalSurfaceFaces select(const Predicate& keep) const
      {
        LocalSurfaceFaces r;
        for (std::size_t f = 0; f < size(); ++f)
          if (keep(f))
            {
              r.boundary.push_back(boundary[f]);
              r.body.push_back(body[f]);
              r.owned.push_back(owned[f]);
              for (unsigned int v = offsets[f]; v < offsets[f + 1]; ++v)
                for (int c = 0; c < components; ++c)
                  {
                    r.dofs.push_back(dofs[components * v + c]);
                    r.coordinates.push_back(coordinates[components * v + c]);
                  }
              r.offsets.push_back(r.offsets.back() + offsets[f + 1] - offsets[f]);
            }
        r.components = components;
        return r;
      }

      int components = 0; ///< DOFs (and coordinates) per vertex
    };

    bool contains(const std::vector<dealii::types::boundary_id>& ids, unsigned int id)
    {
      return std::find(ids.begin(), ids.end(), id) != ids.end();
    }

    /// Is boundary id `id` a contact (or watched) surface of the settings?
    bool is_surface(const ContactSettings& settings, unsigned int id)
    {
      if (settings.surface_boundaries.empty())
        return id == settings.slave_boundary || id == settings.master_boundary ||
               contains(settings.watch_boundaries, id);
      return contains(settings.surface_boundaries, id) || contains(settings.watch_boundaries, id);
    }

    template <int dim>
    LocalSurfaceFaces local_surface_faces(const dealii::DoFHandler<dim>& dof_handler, const ContactSettings& settings)
    {
      LocalSurfaceFaces result;
      result.components = dim;
      for (const auto& cell : dof_handler.active_cell_iterators())
        {
          if (!cell->is_locally_owned() && !cell->is_ghost())
            continue;
          for (const unsigned int f : cell->face_indices())
            {
              if (!cell->face(f)->at_boundary())
                continue;
              const auto id = cell->face(f)->boundary_id();
              if (!is_surface(settings, id))
                continue;
              // Around the face: deal.II numbers quadrilateral face vertices lexicographically.
              const auto                face  = cell->face(f);
              std::vector<unsigned int> order = dim == 2 ? std::vector<unsigned int>{0, 1}
                                                          : std::vector<unsigned int>{0, 1, 3, 2};
              if (face->n_vertices() == 3)
                order = {0, 1, 2};
              std::vector<Point<double, dim>> x;
              for (unsigned int v : order)
                {
                  Point<double, dim> p;
                  for (int d = 0; d < dim; ++d)
                    p[d] = face->vertex(v)[d];
                  x.push_back(p);
                }
              // Outward: the face normal must point away from the cell centre.
              const auto n  = face_unit_normal<double, dim>(x);
              const auto fc = face->center(), cc = cell->center();
              double     s  = 0;
              for (int d = 0; d < dim; ++d)
                s += n[d] * (fc[d] - cc[d]);
              if (s < 0)
                std::reverse(order.begin(), order.end());
              for (unsigned int v : order)
                for (unsigned int c = 0; c < dim; ++c)
                  {
                    result.dofs.push_back(face->vertex_dof_index(v, c));
                    result.coordinates.push_back(face->vertex(v)[c]);
                  }
              result.boundary.push_back(id);
              result.body.push_back(cell->material_id());
              result.owned.push_back(cell->is_locally_owned() ? 1 : 0);
              result.offsets.push_back(result.offsets.back() + order.size());
            }
        }
      return result;
    }
  } // namespace

  template <int dim>
  MortarContact<dim>::MortarContact(const dealii::DoFHandler<dim>& dof_handler, const ContactSettings& settings)
      : settings_(settings)
      , comm_(dof_handler.get_triangulation().get_communicator())
      , owned_(dof_handler.locally_owned_dofs())
      , n_dofs_(dof_handler.n_dofs())
  {
    const auto& fe = dof_handler.get_fe();
    if (fe.n_components() != dim || fe.dofs_per_vertex != dim)
      throw std::invalid_argument("mortar contact: expected a vector-valued linear element with dim DOFs per vertex");
    dealii::DoFTools::extract_locally_relevant_dofs(dof_handler, relevant_);

    const auto local          = local_surface_faces(dof_handler, settings);
    const unsigned int rank   = dealii::Utilities::MPI::this_mpi_process(comm_);

    if (!settings.surface_boundaries.empty())
      {
        std::set<unsigned int> bodies;
        for (std::size_t f = 0; f < local.size(); ++f)
          if (local.owned[f] && contains(settings.surface_boundaries, local.boundary[f]))
            bodies.insert(local.body[f]);
        pairs_ = std::make_unique<ContactPairs>(settings.pairs, dealii::Utilities::MPI::compute_set_union(bodies, comm_));
      }
    // The lists a face belongs to: 0 slave, 1 master, 2 watched only (two-body mode: by boundary
    // id; multi-body mode: by the pairs of its body).
    auto in_list = [&](const LocalSurfaceFaces& faces, std::size_t f, int list) {
      const unsigned int boundary = faces.boundary[f], body = faces.body[f];
      std::vector<int>   lists;
      if (!pairs_)
        {
          if (boundary == settings.slave_boundary)
            lists.push_back(0);
          else if (boundary == settings.master_boundary)
            lists.push_back(1);
        }
      else if (contains(settings.surface_boundaries, boundary))
        {
          if (pairs_->slave_bodies().count(body))
            lists.push_back(0);
          if (pairs_->master_bodies().count(body))
            lists.push_back(1);
        }
      if (lists.empty() && contains(settings.watch_boundaries, boundary))
        lists.push_back(2);
      return std::find(lists.begin(), lists.end(), list) != lists.end();
    };

    // Appends face f of `faces` to a side's lists, numbering its nodes by first appearance.
    auto append = [&](const LocalSurfaceFaces& faces, std::size_t f, bool owned_here,
                      std::map<global_dof_index, unsigned int>& index, std::vector<SurfaceNode<dim>>& nodes,
                      SurfaceFaces& side) {
      std::vector<unsigned int> face_nodes;
      for (unsigned int v = faces.offsets[f]; v < faces.offsets[f + 1]; ++v)
        {
          auto it = index.find(faces.dofs[dim * v]);
          if (it == index.end())
            {
              SurfaceNode<dim> node;
              for (unsigned int c = 0; c < dim; ++c)
                {
                  node.dofs[c]      = faces.dofs[dim * v + c];
                  node.reference[c] = faces.coordinates[dim * v + c];
                }
              it         = index.emplace(node.dofs[0], nodes.size()).first;
              nodes.push_back(node);
            }
          face_nodes.push_back(it->second);
        }
      side.nodes.push_back(face_nodes);
      side.locally_owned.push_back(owned_here);
      side.body.push_back(faces.body[f]);
    };

    // Master surface: every rank's own master faces, gathered on every rank in rank order.
    {
      const auto gathered = dealii::Utilities::MPI::all_gather(
          comm_, local.select([&](std::size_t f) { return local.owned[f] && in_list(local, f, 1); }));
      std::map<global_dof_index, unsigned int> index;
      for (unsigned int r = 0; r < gathered.size(); ++r)
        for (std::size_t f = 0; f < gathered[r].size(); ++f)
          append(gathered[r], f, r == rank, index, master_nodes_, master_faces_);
    }
    // Watched faces: this rank's own (the self-contact check exchanges them where needed).
    {
      std::map<global_dof_index, unsigned int> index;
      for (std::size_t f = 0; f < local.size(); ++f)
        if (local.owned[f] && in_list(local, f, 2))
          append(local, f, true, index, watch_nodes_, watch_faces_);
    }
    // Slave side: the slave faces of own cells, and those of ghost cells that touch a node of an
    // own slave face or an owned node -- together all faces around every node whose state this
    // rank needs (a node of an own cell has all its cells among the own and ghost cells).
    {
      std::set<global_dof_index> touched; // first DOFs of the nodes of own slave faces
      for (std::size_t f = 0; f < local.size(); ++f)
        if (local.owned[f] && in_list(local, f, 0))
          for (unsigned int v = local.offsets[f]; v < local.offsets[f + 1]; ++v)
            touched.insert(local.dofs[dim * v]);
      std::map<global_dof_index, unsigned int> index;
      for (std::size_t f = 0; f < local.size(); ++f)
        {
          if (!in_list(local, f, 0))
            continue;
          bool needed = local.owned[f];
          for (unsigned int v = local.offsets[f]; v < local.offsets[f + 1] && !needed; ++v)
            needed = touched.count(local.dofs[dim * v]) || owned_.is_element(local.dofs[dim * v]);
          if (needed)
            append(local, f, local.owned[f] != 0, index, slave_nodes_, slave_faces_);
        }
      finish_slave_side(touched);
    }

    if (n_global_slave_nodes_ == 0)
      throw std::invalid_argument("no boundary face has the slave boundary id " +
                                  std::to_string(settings.slave_boundary));
    if (master_nodes_.empty())
      throw std::invalid_argument("no boundary face has the master boundary id " +
                                  std::to_string(settings.master_boundary));
  }

  template <int dim>
  void MortarContact<dim>::finish_slave_side(const std::set<global_dof_index>& touched)
  {
    const unsigned int S = slave_nodes_.size();
    needs_state_.assign(S, false);
    for (unsigned int j = 0; j < S; ++j)
      {
        needs_state_[j] = touched.count(slave_nodes_[j].dofs[0]) || owns_slave_node(j);
        n_global_slave_nodes_ += owns_slave_node(j);
      }
    n_global_slave_nodes_ = dealii::Utilities::MPI::sum(n_global_slave_nodes_, comm_);

    // Faces around each node in an order every rank shares (by their nodes' DOFs), so that the
    // nodal normals, and with them the active set, come out bitwise the same on every rank.
    slave_node_faces_.assign(S, {});
    for (unsigned int f = 0; f < slave_faces_.nodes.size(); ++f)
      for (unsigned int j : slave_faces_.nodes[f])
        slave_node_faces_[j].push_back(f);
    auto key = [&](unsigned int f) {
      std::vector<global_dof_index> k;
      for (unsigned int j : slave_faces_.nodes[f])
        k.push_back(slave_nodes_[j].dofs[0]);
      return k;
    };
    for (auto& faces : slave_node_faces_)
      std::sort(faces.begin(), faces.end(), [&](unsigned int a, unsigned int b) { return key(a) < key(b); });

    normals_.resize(S);
    constraint_row_.resize(S);
    h_min_ = std::numeric_limits<double>::max();
    for (std::size_t f = 0; f < slave_faces_.nodes.size(); ++f)
      if (slave_faces_.locally_owned[f])
        {
          const auto& nodes = slave_faces_.nodes[f];
          for (std::size_t a = 0; a < nodes.size(); ++a)
            h_min_ = std::min(h_min_, slave_nodes_[nodes[a]].reference.distance(
                                          slave_nodes_[nodes[(a + 1) % nodes.size()]].reference));
        }
    h_min_ = dealii::Utilities::MPI::min(h_min_, comm_);
  }

  template <int dim>
  std::vector<global_dof_index> MortarContact<dim>::surface_dofs() const
  {
    std::vector<global_dof_index> dofs;
    for (const auto* list : {&slave_nodes_, &master_nodes_, &watch_nodes_})
      for (const auto& node : *list)
        dofs.insert(dofs.end(), node.dofs.begin(), node.dofs.end());
    std::sort(dofs.begin(), dofs.end());
    dofs.erase(std::unique(dofs.begin(), dofs.end()), dofs.end()); // a node may be slave and master
    return dofs;
  }

  template <int dim>
  std::string MortarContact<dim>::describe_pairs() const
  {
    if (!pairs_)
      return "two-body mode: slave boundary id " + std::to_string(settings_.slave_boundary) + ", master boundary id " +
             std::to_string(settings_.master_boundary);
    return pairs_->describe();
  }

  template <int dim>
  std::vector<double> MortarContact<dim>::sum_over_ranks(const std::vector<double>& partial) const
  {
    // The sums travel in vectors of the displacement layout: v_j in node j's dim DOFs, w_j in its
    // first DOF of a second vector. Adding into the owners, then updating the ghosts, gives every
    // rank the owner's total for each of its nodes (all are locally relevant).
    using dealii::TrilinosWrappers::MPI::Vector;
    Vector v_add, w_add;
    v_add.reinit(owned_, relevant_, comm_, true);
    w_add.reinit(owned_, relevant_, comm_, true);
    for (std::size_t j = 0; j < slave_nodes_.size(); ++j)
      {
        for (int d = 0; d < dim; ++d)
          if (partial[j * (dim + 1) + d] != 0.0)
            v_add[slave_nodes_[j].dofs[d]] += partial[j * (dim + 1) + d];
        if (partial[j * (dim + 1) + dim] != 0.0)
          w_add[slave_nodes_[j].dofs[0]] += partial[j * (dim + 1) + dim];
      }
    v_add.compress(dealii::VectorOperation::add);
    w_add.compress(dealii::VectorOperation::add);
    Vector v(owned_, relevant_, comm_), w(owned_, relevant_, comm_);
    v = v_add;
    w = w_add;
    std::vector<double> total(partial.size());
    for (std::size_t j = 0; j < slave_nodes_.size(); ++j)
      {
        for (int d = 0; d < dim; ++d)
          total[j * (dim + 1) + d] = v[slave_nodes_[j].dofs[d]];
        total[j * (dim + 1) + dim] = w[slave_nodes_[j].dofs[0]];
      }
    return total;
  }

  template <int dim>
  std::string MortarContact<dim>::detect_self_contact(const std::vector<std::array<double, dim>>& slave_x,
                                                      const std::vector<std::array<double, dim>>& master_x,
                                                      const std::vector<std::array<double, dim>>& watch_x) const
  {
    if constexpr (dim != 2)
      return "";
    else
      {
        auto segments_of = [&](const SurfaceFaces& faces, const std::vector<SurfaceNode<dim>>& nodes,
                               const std::vector<std::array<double, dim>>& x, bool own_only) {
          std::vector<BodySegment> segments;
          for (std::size_t f = 0; f < faces.nodes.size(); ++f)
            if (!own_only || faces.locally_owned[f])
              {
                BodySegment s;
                s.body = faces.body[f];
                for (int a = 0; a < 2; ++a)
                  {
                    const unsigned int k = faces.nodes[f][a];
                    s.node[a]            = nodes[k].dofs[0];
                    s.x[a]               = {{x[k][0], x[k][1]}};
                  }
                segments.push_back(s);
              }
          return segments;
        };
        // This rank's own slave and watched faces, and those of every rank whose faces' box
        // meets theirs (two crossing faces have meeting boxes); the master surface is here.
        std::vector<BodySegment> own = segments_of(slave_faces_, slave_nodes_, slave_x, true);
        for (const auto& s : segments_of(watch_faces_, watch_nodes_, watch_x, true))
          own.push_back(s);
        std::vector<BodySegment> segments = exchange_nearby_segments(own, comm_);
        segments.insert(segments.end(), own.begin(), own.end());
        for (const auto& s : segments_of(master_faces_, master_nodes_, master_x, false))
          segments.push_back(s);
        return lowest_rank_message(find_self_crossing(segments), comm_);
      }
  }

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

    // Per slave node: partial sums of this rank's faces: v_j (dim) and w_j, and the gradient of
    // v_j (by DOF, dim components).
    std::vector<double> partial(S * (dim + 1), 0.0);
    std::vector<std::map<global_dof_index, std::array<double, dim>>> dv(S);

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
            const int  ns = sf.size(), nm = mf.size(), n_vars = (ns + nm) * dim;
            const auto ads = seed<dim>(xs, n_vars, 0), adm = seed<dim>(xm, n_vars, ns * dim);
            const auto pair = integrate_pair<AD, dim>(ads, adm, settings_.dual);
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
                    AD v = 0.0;
                    for (int l = 0; l < nm; ++l)
                      v += pair.M[a][l] * adm[l][d];
                    for (int k = 0; k < ns; ++k)
                      v -= pair.D[a][k] * ads[k][d];
                    partial[j * (dim + 1) + d] += v.val();
                    for (int i = 0; i < n_vars; ++i)
                      if (v.dx(i) != 0.0)
                        dv[j][var_dof(i)][d] += v.dx(i);
                  }
                for (int k = 0; k < ns; ++k)
                  partial[j * (dim + 1) + dim] += pair.D[a][k].val();

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
    const std::vector<double> total = sum_over_ranks(partial);
    state_.active.assign(S, false);
    state_.covered.assign(S, false);
    state_.weighted_gap.assign(S, 0.0);
    state_.weight.assign(S, 0.0);
    state_.normal_pressure.assign(S, 0.0);
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
        // Which multiplier row holds which constraint: the normal row goes to the Cartesian
        // component the normal is most aligned with, each tangential row to the best remaining
        // one. The rows' diagonals (and those of the Schur complement the block smoothers
        // build) are then nonzero, which pointwise smoothers (SGS, ILU) need.
        {
          std::array<bool, dim> taken{};
          for (int m = 0; m < dim; ++m)
            {
              int best = -1;
              for (int c = 0; c < dim; ++c)
                if (!taken[c] && (best < 0 || std::abs(frame[m][c]) > std::abs(frame[m][best])))
                  best = c;
              taken[best]       = true;
              constraint_row_[j][m] = best;
            }
        }
        const double w   = total[j * (dim + 1) + dim];
        double       g = 0, ln = 0;
        for (int d = 0; d < dim; ++d)
          {
            g += frame[0][d] * total[j * (dim + 1) + d];
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
        if (first_evaluation_)
          state_.active[j] = state_.covered[j] && g / w <= 1e-8 * minimal_slave_face_size();
        else
          state_.active[j] = state_.covered[j] && ln - settings_.complementarity_parameter * g / w > 0.0;
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
        std::vector<unsigned int> vars; // slave node of each AD variable block
        for (unsigned int f : slave_node_faces_[j])
          for (unsigned int k : slave_faces_.nodes[f])
            if (std::find(vars.begin(), vars.end(), k) == vars.end())
              vars.push_back(k);
        const int n_vars = vars.size() * dim;
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
                value += total[j * (dim + 1) + d] * frame[0][d].dx(i);
              add(constraint_row(j, 0), dof_of(i), value);
            }
        // Tangential rows: tau_m . lambda_j = 0.
        for (int m = 1; m < dim; ++m)
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
