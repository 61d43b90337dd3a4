#include "coupled_fields.h"

#include <Xpetra_MapFactory.hpp>
#include <Xpetra_MatrixFactory.hpp>
#include <Xpetra_MultiVectorFactory.hpp>

#include <array>
#include <map>
#include <set>

namespace multigrid
{
  namespace
  {
    enum Field
    {
      structure = 0,
      fluid     = 1,
      ale       = 2
    };
    constexpr std::array<int, 3> dofs_per_node = {2, 3, 2};

    /// DOF numbering of the three fields on m x m node grids (node (i, j) = j * m + i), block by
    /// block (Xpetra numbering: block k starts after block k - 1).
    struct Layout
    {
      int m;
      GO  nodes() const { return static_cast<GO>(m) * m; }
      GO  offset(int field) const
      {
        GO o = 0;
        for (int k = 0; k < field; ++k)
          o += dofs_per_node[k] * nodes();
        return o;
      }
      GO dof(int field, int i, int j, int c) const
      {
        return offset(field) + (static_cast<GO>(j) * m + i) * dofs_per_node[field] + c;
      }
      bool inside(int i, int j) const { return i >= 0 && j >= 0 && i < m && j < m; }
    };

    using Rows = std::map<GO, std::map<GO, double>>;

    /// Adds the entries of one field's stencil whose row and column nodes are both on the grid
    /// (the principal submatrix of the infinite-grid operator) and whose row is owned.
    class Assembler
    {
    public:
      Assembler(const Layout& layout, const std::set<GO>& owned_rows, const std::set<GO>& identity_rows)
          : l_(layout)
          , owned_(owned_rows)
          , identity_(identity_rows)
      {
      }
      void add(int row_field, int i, int j, int c, int col_field, int ii, int jj, int cc, double v)
      {
        if (!l_.inside(i, j) || !l_.inside(ii, jj))
          return;
        const GO r = l_.dof(row_field, i, j, c), col = l_.dof(col_field, ii, jj, cc);
        if (owned_.count(r) == 0 || identity_.count(r) > 0 || identity_.count(col) > 0)
          return;
        rows[r][col] += v;
      }
      /// coefficient * (4 x_ij - x_i+1,j - x_i-1,j - x_i,j+1 - x_i,j-1) for component c.
      void laplacian(int field, int i, int j, int c, double coefficient)
      {
        add(field, i, j, c, field, i, j, c, 4 * coefficient);
        for (const auto& [di, dj] : neighbours)
          add(field, i, j, c, field, i + di, j + dj, c, -coefficient);
      }
      Rows rows;

    private:
      static constexpr std::array<std::array<int, 2>, 4> neighbours = {{{1, 0}, {-1, 0}, {0, 1}, {0, -1}}};
      const Layout&                                      l_;
      const std::set<GO>&                                owned_;
      const std::set<GO>&                                identity_;
    };

    /// -mu Lap(d) - (lambda + mu) grad div(d): second differences along x (y) for the first
    /// (second) component, the 4-point cross stencil for the mixed derivatives.
    void add_navier_lame(Assembler& a, int i, int j, double mu, double lambda)
    {
      const double k = lambda + mu;
      for (int c = 0; c < 2; ++c)
        {
          a.laplacian(structure, i, j, c, mu);
          const int di = c == 0 ? 1 : 0, dj = 1 - di; // the direction of d_c's own derivative
          a.add(structure, i, j, c, structure, i, j, c, 2 * k);
          a.add(structure, i, j, c, structure, i + di, j + dj, c, -k);
          a.add(structure, i, j, c, structure, i - di, j - dj, c, -k);
          for (int si : {-1, 1})
            for (int sj : {-1, 1})
              a.add(structure, i, j, c, structure, i + si, j + sj, 1 - c, -k * si * sj / 4.0);
        }
    }

    /// [sigma I + nu Lap, G; G^T, -(eps Lap + delta I)]: G_(u_ij, p_i+1,j) = 1/2,
    /// G_(u_ij, p_i-1,j) = -1/2 (and along y for v); G^T added in the same loop.
    void add_stokes(Assembler& a, int i, int j)
    {
      const double sigma = 0.5, nu = 1.0, eps = 0.5, delta = 0.01;
      for (int c = 0; c < 2; ++c)
        {
          a.laplacian(fluid, i, j, c, nu);
          a.add(fluid, i, j, c, fluid, i, j, c, sigma);
          const int di = c == 0 ? 1 : 0, dj = 1 - di;
          for (int s : {-1, 1})
            {
              a.add(fluid, i, j, c, fluid, i + s * di, j + s * dj, 2, 0.5 * s);
              a.add(fluid, i + s * di, j + s * dj, 2, fluid, i, j, c, 0.5 * s);
            }
        }
      a.laplacian(fluid, i, j, 2, -eps);
      a.add(fluid, i, j, 2, fluid, i, j, 2, -delta);
    }

    /// The interface couplings at grid row j (structure node (m-1, j), fluid/ALE node (0, j)).
    void add_interface(Assembler& a, int m, int j, bool lower_triangular)
    {
      const int s = m - 1;
      for (int c = 0; c < 2; ++c)
        {
          a.add(fluid, 0, j, c, structure, s, j, c, -1.0); // kinematic, tau = 1
          a.add(ale, 0, j, c, structure, s, j, c, -1.0);
          if (lower_triangular)
            continue;
          a.add(structure, s, j, c, fluid, 0, j, c, -0.5);
          a.add(structure, s, j, c, ale, 0, j, c, -0.1);
          a.add(fluid, 0, j, c, ale, 0, j, c, -0.1);
        }
      if (!lower_triangular)
        a.add(structure, s, j, 0, fluid, 0, j, 2, -0.25);
    }
  } // namespace

  BlockSystem coupled_fields_2d(RCP<const Comm> comm, const CoupledFieldsOptions& o)
  {
    if (o.level < 0 || o.level > 5)
      throw InputError("coupled-fields-2d: level " + std::to_string(o.level) +
                       " out of range, expected 0..5");
    const Layout layout{8 * (1 << o.level) + 1};
    const int    m = layout.m, rank = comm->getRank(), size = comm->getSize();

    // Ownership: every field's nodes in contiguous chunks.
    std::vector<std::vector<GO>> owned(3);
    std::set<GO>                 owned_rows, identity_rows;
    std::array<GO, 3>            first_node{};
    for (int f = 0; f < 3; ++f)
      {
        const GO lo = layout.nodes() * rank / size, hi = layout.nodes() * (rank + 1) / size;
        first_node[f] = lo;
        for (GO n = lo; n < hi; ++n)
          for (int c = 0; c < dofs_per_node[f]; ++c)
            owned[f].push_back(layout.offset(f) + n * dofs_per_node[f] + c);
        owned_rows.insert(owned[f].begin(), owned[f].end());
      }
    for (int j = 0; j < m; ++j)
      for (int c = 0; c < 2; ++c)
        {
          identity_rows.insert(layout.dof(structure, 0, j, c)); // clamped at x = 0
          identity_rows.insert(layout.dof(ale, m - 1, j, c));   // mesh fixed at x = 2
        }

    Assembler a(layout, owned_rows, identity_rows);
    for (int j = 0; j < m; ++j)
      for (int i = 0; i < m; ++i)
        {
          add_navier_lame(a, i, j, 1.0, 1.0);
          add_stokes(a, i, j);
          for (int c = 0; c < 2; ++c)
            a.laplacian(ale, i, j, c, 1.0);
        }
    for (int j = 0; j < m; ++j)
      add_interface(a, m, j, o.lower_triangular);
    for (GO r : identity_rows)
      if (owned_rows.count(r) > 0)
        a.rows[r][r] = 1.0;

    std::vector<GO> all;
    for (const auto& f : owned)
      all.insert(all.end(), f.begin(), f.end());
    auto        row_map = Xpetra::MapFactory<LO, GO, NO>::Build(Xpetra::UseTpetra, layout.offset(3),
                                                                Teuchos::ArrayView<const GO>(all), 0, comm);
    RCP<Matrix> A       = Xpetra::MatrixFactory<SC, LO, GO, NO>::Build(row_map, 30);
    for (const auto& [r, entries] : a.rows)
      {
        std::vector<GO> cols;
        std::vector<SC> vals;
        for (const auto& [c, v] : entries)
          {
            cols.push_back(c);
            vals.push_back(v);
          }
        A->insertGlobalValues(r, cols, vals);
      }
    A->fillComplete();
    auto rhs = Xpetra::MultiVectorFactory<SC, LO, GO, NO>::Build(row_map, 1, true);
    {
      auto data = rhs->getDataNonConst(0);
      for (std::size_t i = 0; i < all.size(); ++i)
        data[i] = identity_rows.count(all[i]) > 0 ? 0.0 : 1.0;
    }

    static const std::array<const char*, 3> names = {"structure", "fluid", "ale"};
    std::vector<BlockInfo>                  blocks(3);
    for (int f = 0; f < 3; ++f)
      {
        blocks[f].name          = names[f];
        blocks[f].dofs_per_node = dofs_per_node[f];
        blocks[f].global_size   = dofs_per_node[f] * layout.nodes();
      }
    BlockSystem system = BlockSystem::from_merged(comm, blocks, owned, A, rhs);

    // Coordinates (structure on [0,1]^2, fluid and ALE on [1,2] x [0,1]) and near-nullspaces.
    std::vector<double> structure_xy;
    for (int f = 0; f < 3; ++f)
      {
        const GO            n_owned = static_cast<GO>(owned[f].size()) / dofs_per_node[f];
        std::vector<double> xy;
        for (GO n = first_node[f]; n < first_node[f] + n_owned; ++n)
          xy.insert(xy.end(), {(f == structure ? 0.0 : 1.0) + static_cast<double>(n % m) / (m - 1),
                               static_cast<double>(n / m) / (m - 1)});
        set_node_coordinates(system.block(f), 2, xy);
        if (f == structure)
          structure_xy = xy;
      }
    system.block(structure).nullspace = rigid_body_modes(system.block(structure).map, 2, structure_xy);
    system.block(fluid).nullspace     = translation_modes(system.block(fluid).map, 3);
    system.block(ale).nullspace       = translation_modes(system.block(ale).map, 2);
    system.validate("coupled-fields-2d");
    return system;
  }
} // namespace multigrid
