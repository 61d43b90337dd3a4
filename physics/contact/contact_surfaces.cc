// The contact surfaces of MortarContact: their collection from the mesh (constructor, the slave
// side's bookkeeping), the surface DOFs and the sums over ranks; evaluate() is in
// mortar_contact.cc.
#include "contact/mortar_contact.h"

#include "common/row_exchange.h"
#include "common/mortar_integration.h"
#include "contact/self_contact.h"

#include <deal.II/base/mpi.h>
#include <deal.II/dofs/dof_tools.h>
#include <deal.II/lac/trilinos_vector.h>

#include <boost/serialization/vector.hpp>

#include <limits>
#include <set>
#include <stdexcept>

namespace physics::contact
{
  using namespace physics::mortar; // the mortar integration shared with the FSI class (common/)
  namespace
  {
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
    LocalSurfaceFaces local_surface_faces(const dealii::DoFHandler<dim>& dof_handler,
                                          const ContactSettings&         settings)
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
              const auto                face = cell->face(f);
              std::vector<unsigned int> order =
                  dim == 2 ? std::vector<unsigned int>{0, 1} : std::vector<unsigned int>{0, 1, 3, 2};
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
              double     s = 0;
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
  MortarContact<dim>::MortarContact(const dealii::DoFHandler<dim>& dof_handler,
                                    const ContactSettings&         settings)
      : settings_(settings)
      , comm_(dof_handler.get_triangulation().get_communicator())
      , owned_(dof_handler.locally_owned_dofs())
      , n_dofs_(dof_handler.n_dofs())
  {
    const auto& fe = dof_handler.get_fe();
    if (fe.n_components() != dim || fe.dofs_per_vertex != dim)
      throw std::invalid_argument(
          "mortar contact: expected a vector-valued linear element with dim DOFs per vertex");
    dealii::DoFTools::extract_locally_relevant_dofs(dof_handler, relevant_);

    const auto         local = local_surface_faces(dof_handler, settings);
    const unsigned int rank  = dealii::Utilities::MPI::this_mpi_process(comm_);

    if (!settings.surface_boundaries.empty())
      {
        std::set<unsigned int> bodies;
        for (std::size_t f = 0; f < local.size(); ++f)
          if (local.owned[f] && contains(settings.surface_boundaries, local.boundary[f]))
            bodies.insert(local.body[f]);
        pairs_ = std::make_unique<ContactPairs>(settings.pairs,
                                                dealii::Utilities::MPI::compute_set_union(bodies, comm_));
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
              it = index.emplace(node.dofs[0], nodes.size()).first;
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
      return "two-body mode: slave boundary id " + std::to_string(settings_.slave_boundary) +
             ", master boundary id " + std::to_string(settings_.master_boundary);
    return pairs_->describe();
  }

  template <int dim>
  std::vector<double> MortarContact<dim>::sum_over_ranks(const std::vector<double>& partial,
                                                         int                        n_vectors) const
  {
    // The sums travel in vectors of the displacement layout: each dim-vector in node j's dim DOFs,
    // w_j in its first DOF of one more vector. Adding into the owners, then updating the ghosts,
    // gives every rank the owner's total for each of its nodes (all are locally relevant).
    using dealii::TrilinosWrappers::MPI::Vector;
    const int           stride = n_vectors * dim + 1;
    std::vector<Vector> sums(n_vectors + 1);
    for (auto& v : sums)
      v.reinit(owned_, relevant_, comm_, true);
    auto dof_of = [&](std::size_t j, int i) {
      return slave_nodes_[j].dofs[i < n_vectors * dim ? i % dim : 0];
    };
    for (std::size_t j = 0; j < slave_nodes_.size(); ++j)
      for (int i = 0; i < stride; ++i)
        if (partial[j * stride + i] != 0.0)
          sums[i / dim][dof_of(j, i)] += partial[j * stride + i];
    std::vector<Vector> totals(sums.size());
    for (std::size_t s = 0; s < sums.size(); ++s)
      {
        sums[s].compress(dealii::VectorOperation::add);
        totals[s].reinit(owned_, relevant_, comm_);
        totals[s] = sums[s];
      }
    std::vector<double> total(partial.size());
    for (std::size_t j = 0; j < slave_nodes_.size(); ++j)
      for (int i = 0; i < stride; ++i)
        total[j * stride + i] = totals[i / dim][dof_of(j, i)];
    return total;
  }

  template <int dim>
  std::string
  MortarContact<dim>::detect_self_contact(const std::vector<std::array<double, dim>>& slave_x,
                                          const std::vector<std::array<double, dim>>& master_x,
                                          const std::vector<std::array<double, dim>>& watch_x) const
  {
    auto facets_of = [&](const SurfaceFaces& faces, const std::vector<SurfaceNode<dim>>& nodes,
                         const std::vector<std::array<double, dim>>& x, bool own_only) {
      std::vector<BodyFacet<dim>> facets;
      for (std::size_t f = 0; f < faces.nodes.size(); ++f)
        if (!own_only || faces.locally_owned[f])
          {
            BodyFacet<dim> s;
            s.body = faces.body[f];
            for (const unsigned int k : faces.nodes[f]) // in order around the face
              {
                s.node.push_back(nodes[k].dofs[0]);
                s.x.push_back(x[k]);
              }
            facets.push_back(s);
          }
      return facets;
    };
    // This rank's own slave and watched faces, and those of every rank whose faces' box meets
    // theirs (two crossing faces have meeting boxes); the master surface is here.
    std::vector<BodyFacet<dim>> own = facets_of(slave_faces_, slave_nodes_, slave_x, true);
    for (const auto& s : facets_of(watch_faces_, watch_nodes_, watch_x, true))
      own.push_back(s);
    std::vector<BodyFacet<dim>> facets = exchange_nearby_facets(own, comm_);
    facets.insert(facets.end(), own.begin(), own.end());
    for (const auto& s : facets_of(master_faces_, master_nodes_, master_x, false))
      facets.push_back(s);
    return lowest_rank_message(find_self_crossing(facets), comm_);
  }

  template class MortarContact<2>;
  template class MortarContact<3>;
} // namespace physics::contact
