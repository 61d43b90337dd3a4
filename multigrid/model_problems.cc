#include "model_problems.h"

#include "coupled_fields.h"

#include <Xpetra_CrsMatrixWrap.hpp>
#include <Xpetra_MapFactory.hpp>
#include <Xpetra_MatrixFactory.hpp>
#include <Xpetra_MultiVectorFactory.hpp>

#include <array>
#include <cmath>
#include <map>

namespace multigrid
{
  namespace
  {
    /// A structured grid of bilinear quadrilaterals on [x0, x0 + w] x [y0, y0 + h].
    struct Grid
    {
      int    nx, ny;
      double x0, y0, w, h;
      GO     first_node;
      GO     node(int i, int j) const { return first_node + static_cast<GO>(j) * (nx + 1) + i; }
      GO     n_nodes() const { return static_cast<GO>(nx + 1) * (ny + 1); }
      std::array<double, 2> x(int i, int j) const { return {x0 + w * i / nx, y0 + h * j / ny}; }
    };

    /// Plane-strain stiffness of a rectangular bilinear element (2 x 2 Gauss), DOFs node-major in
    /// the order (0,0), (1,0), (1,1), (0,1).
    std::array<std::array<double, 8>, 8> element_stiffness(double hx, double hy, double E, double nu)
    {
      const double lambda = E * nu / ((1 + nu) * (1 - 2 * nu)), mu = E / (2 * (1 + nu));
      const double C[3][3] = {{lambda + 2 * mu, lambda, 0}, {lambda, lambda + 2 * mu, 0}, {0, 0, mu}};
      const double xi_n[4] = {-1, 1, 1, -1}, eta_n[4] = {-1, -1, 1, 1};
      const double g = 1.0 / std::sqrt(3.0);
      std::array<std::array<double, 8>, 8> K{};
      for (double xi : {-g, g})
        for (double eta : {-g, g})
          {
            double B[3][8] = {};
            for (int a = 0; a < 4; ++a)
              {
                const double dNdx = 0.25 * xi_n[a] * (1 + eta * eta_n[a]) * 2.0 / hx;
                const double dNdy = 0.25 * eta_n[a] * (1 + xi * xi_n[a]) * 2.0 / hy;
                B[0][2 * a]       = dNdx;
                B[1][2 * a + 1]   = dNdy;
                B[2][2 * a]       = dNdy;
                B[2][2 * a + 1]   = dNdx;
              }
            const double detJw = hx * hy / 4.0;
            for (int i = 0; i < 8; ++i)
              for (int j = 0; j < 8; ++j)
                {
                  double v = 0;
                  for (int p = 0; p < 3; ++p)
                    for (int q = 0; q < 3; ++q)
                      v += B[p][i] * C[p][q] * B[q][j];
                  K[i][j] += v * detJw;
                }
          }
      return K;
    }

    using Rows = std::map<GO, std::map<GO, double>>;
  } // namespace

  BlockSystem tied_blocks_2d(RCP<const Comm> comm, const TiedBlocksOptions& o)
  {
    if (o.level < 0 || o.level > 6)
      throw InputError("tied-blocks-2d: level " + std::to_string(o.level) + " out of range, expected 0..6");
    if (!(o.youngs_modulus > 0) || !(o.poisson_ratio > -1 && o.poisson_ratio < 0.5))
      throw InputError("tied-blocks-2d: expected E > 0 and -1 < nu < 0.5");
    const int  m = 8 << o.level;
    const Grid master{2 * m, m, 0.0, 0.0, 1.0, 0.5, 0};
    const Grid slave{3 * m, 3 * m / 2, 0.0, 0.5, 1.0, 0.5, master.n_nodes()};
    const GO   n_primal_nodes = master.n_nodes() + slave.n_nodes();
    const GO   n_primal       = 2 * n_primal_nodes;
    const GO   n_dual_nodes   = slave.nx + 1;

    // Ownership: contiguous chunks of primal nodes; a multiplier node lives with its slave node.
    const int                    rank = comm->getRank(), size = comm->getSize();
    const GO                     lo = n_primal_nodes * rank / size, hi = n_primal_nodes * (rank + 1) / size;
    std::vector<std::vector<GO>> owned(2);
    std::vector<double>          coordinates;
    auto                         coordinate_of = [&](GO node) {
      const Grid& g = node < master.n_nodes() ? master : slave;
      const GO    l = node - g.first_node;
      return g.x(static_cast<int>(l % (g.nx + 1)), static_cast<int>(l / (g.nx + 1)));
    };
    for (GO n = lo; n < hi; ++n)
      {
        owned[0].push_back(2 * n);
        owned[0].push_back(2 * n + 1);
        const auto x = coordinate_of(n);
        coordinates.insert(coordinates.end(), x.begin(), x.end());
      }
    std::map<LO, LO> dual_to_primal;
    for (GO j = 0; j < n_dual_nodes; ++j)
      {
        const GO p = slave.node(static_cast<int>(j), 0);
        if (p >= lo && p < hi)
          {
            dual_to_primal[static_cast<LO>(owned[1].size() / 2)] = static_cast<LO>(p - lo);
            owned[1].push_back(n_primal + 2 * j);
            owned[1].push_back(n_primal + 2 * j + 1);
          }
      }
    auto is_owned = [&](GO dof) {
      if (dof < n_primal)
        return dof / 2 >= lo && dof / 2 < hi;
      const GO p = slave.node(static_cast<int>((dof - n_primal) / 2), 0);
      return p >= lo && p < hi;
    };
    // Dirichlet data: body 1 clamped at y = 0; the top face of body 2 pushed by a prescribed
    // displacement (0.01, -0.02) (the two-block benchmark's loading), so both bodies are supported
    // and the primal block is nonsingular, as in a quasi-static contact step.
    const double pushed[2]  = {0.01, -0.02};
    auto         is_clamped = [&](GO dof) {
      const GO node = dof / 2;
      return (node < master.nx + 1) ||
             (node >= slave.node(0, slave.ny) && node < slave.n_nodes() + slave.first_node);
    };
    auto                 prescribed = [&](GO dof) { return dof / 2 < master.nx + 1 ? 0.0 : pushed[dof % 2]; };
    std::map<GO, double> lifted; // rhs contributions -K_rc g_c of the prescribed values

    Rows rows;
    auto add = [&](GO i, GO j, double v) {
      if (is_owned(i))
        rows[i][j] += v;
    };

    // Elasticity of both bodies; clamped DOFs become identity rows (eliminated symmetrically).
    for (const Grid* g : {&master, &slave})
      {
        const auto K = element_stiffness(g->w / g->nx, g->h / g->ny, o.youngs_modulus, o.poisson_ratio);
        for (int j = 0; j < g->ny; ++j)
          for (int i = 0; i < g->nx; ++i)
            {
              const GO nodes[4] = {g->node(i, j), g->node(i + 1, j), g->node(i + 1, j + 1),
                                   g->node(i, j + 1)};
              for (int a = 0; a < 8; ++a)
                for (int b = 0; b < 8; ++b)
                  {
                    const GO r = 2 * nodes[a / 2] + a % 2, c = 2 * nodes[b / 2] + b % 2;
                    if (!is_clamped(r) && !is_clamped(c))
                      add(r, c, K[a][b]);
                    else if (!is_clamped(r) && is_owned(r))
                      lifted[r] -= K[a][b] * prescribed(c);
                  }
            }
      }
    for (const Grid* g : {&master, &slave})
      for (int i = 0; i <= g->nx; ++i)
        for (int d = 0; d < 2; ++d)
          {
            const GO dof = 2 * g->node(i, g == &master ? 0 : g->ny) + d;
            add(dof, dof, 1.0);
          }

    // Mortar coupling on y = 0.5: integrate on the segments cut by both meshes' nodes, two Gauss
    // points each (exact for the products of linear functions).
    const double g = 1.0 / std::sqrt(3.0);
    for (int e = 0; e < slave.nx; ++e)
      {
        const double xa = static_cast<double>(e) / slave.nx, xb = static_cast<double>(e + 1) / slave.nx;
        std::vector<double> cuts{xa};
        for (int k = 0; k <= master.nx; ++k)
          {
            const double xm = static_cast<double>(k) / master.nx;
            if (xm > xa + 1e-14 && xm < xb - 1e-14)
              cuts.push_back(xm);
          }
        cuts.push_back(xb);
        for (std::size_t s = 0; s + 1 < cuts.size(); ++s)
          for (double q : {-g, g})
            {
              const double x      = 0.5 * (cuts[s] + cuts[s + 1]) + 0.5 * q * (cuts[s + 1] - cuts[s]);
              const double w      = 0.5 * (cuts[s + 1] - cuts[s]);
              const double t      = (x - xa) / (xb - xa);
              const double Ns[2]  = {1 - t, t};
              const double Phi[2] = {o.dual_multipliers ? 2 * Ns[0] - Ns[1] : Ns[0],
                                     o.dual_multipliers ? 2 * Ns[1] - Ns[0] : Ns[1]};
              const int    l     = std::min(static_cast<int>(x * master.nx), master.nx - 1);
              const double tm    = x * master.nx - l;
              const double Nm[2] = {1 - tm, tm};
              for (int a = 0; a < 2; ++a)
                {
                  const GO lambda = n_primal + 2 * (e + a);
                  for (int b = 0; b < 2; ++b)
                    {
                      const GO     us = 2 * slave.node(e + b, 0), um = 2 * master.node(l + b, master.ny);
                      const double Dv = w * Phi[a] * Ns[b], Mv = w * Phi[a] * Nm[b];
                      for (int d = 0; d < 2; ++d)
                        {
                          add(lambda + d, us + d, Dv); // B = [-M  D]
                          add(us + d, lambda + d, Dv); // D^T
                          add(lambda + d, um + d, -Mv);
                          add(um + d, lambda + d, -Mv); // -M^T
                        }
                    }
                }
            }
      }

    // Assemble into Tpetra in the block distribution.
    std::vector<GO> all(owned[0]);
    all.insert(all.end(), owned[1].begin(), owned[1].end());
    const GO       n_total = n_primal + 2 * n_dual_nodes;
    RCP<const Map> row_map = Xpetra::MapFactory<LO, GO, NO>::Build(
        Xpetra::UseTpetra, n_total, Teuchos::ArrayView<const GO>(all), 0, comm);
    std::size_t max_row = 1;
    for (const auto& [r, entries] : rows)
      max_row = std::max(max_row, entries.size());
    RCP<Matrix> A = Xpetra::MatrixFactory<SC, LO, GO, NO>::Build(row_map, max_row);
    for (GO r : all)
      {
        std::vector<GO> cols;
        std::vector<SC> vals;
        for (const auto& [c, v] : rows[r])
          {
            cols.push_back(c);
            vals.push_back(v);
          }
        A->insertGlobalValues(r, cols, vals);
      }
    A->fillComplete();

    // Right-hand side: prescribed values on Dirichlet rows, their lifting elsewhere.
    auto rhs = Xpetra::MultiVectorFactory<SC, LO, GO, NO>::Build(row_map, 1, true);
    {
      auto data = rhs->getDataNonConst(0);
      for (GO dof : owned[0])
        if (is_clamped(dof))
          data[row_map->getLocalElement(dof)] = prescribed(dof);
      for (const auto& [dof, value] : lifted)
        data[row_map->getLocalElement(dof)] += value;
    }

    std::vector<BlockInfo> blocks(2);
    blocks[0].name            = "displacement";
    blocks[0].dofs_per_node   = 2;
    blocks[0].global_size     = n_primal;
    blocks[1].name            = "lagrange multiplier";
    blocks[1].dofs_per_node   = 2;
    blocks[1].global_size     = 2 * n_dual_nodes;
    BlockSystem system        = BlockSystem::from_merged(comm, blocks, owned, A, rhs);
    system.block(0).nullspace = rigid_body_modes(system.block(0).map, 2, coordinates);
    // Nodal coordinates of the displacement block (x, y per node), e.g. for aggregate output.
    set_node_coordinates(system.block(0), 2, coordinates);

    InterfaceInfo info;
    info.dual_to_primal_node = dual_to_primal;
    std::vector<GO> interface_dofs, slave_body;
    for (const auto& [d, p] : dual_to_primal)
      {
        interface_dofs.push_back(2 * (lo + p));
        interface_dofs.push_back(2 * (lo + p) + 1);
      }
    for (GO dof : owned[0])
      if (dof >= 2 * slave.first_node)
        slave_body.push_back(dof);
    const auto invalid         = Teuchos::OrdinalTraits<Xpetra::global_size_t>::invalid();
    info.primal_interface_dofs = Xpetra::MapFactory<LO, GO, NO>::Build(
        Xpetra::UseTpetra, invalid, Teuchos::ArrayView<const GO>(interface_dofs), 0, comm);
    info.segregation_dofs = Xpetra::MapFactory<LO, GO, NO>::Build(
        Xpetra::UseTpetra, invalid, Teuchos::ArrayView<const GO>(slave_body), 0, comm);
    std::vector<GO> master_body;
    for (GO dof : owned[0])
      if (dof < 2 * slave.first_node)
        master_body.push_back(dof);
    info.slave_dofs  = info.segregation_dofs;
    info.master_dofs = Xpetra::MapFactory<LO, GO, NO>::Build(
        Xpetra::UseTpetra, invalid, Teuchos::ArrayView<const GO>(master_body), 0, comm);
    system.set_interface(std::move(info));
    system.validate("tied-blocks-2d");
    return system;
  }

  BlockSystem builtin_system(const std::string& spec, RCP<const Comm> comm)
  {
    const auto colon = spec.find(':');
    const std::string name = spec.substr(0, colon);
    if (name != "tied-blocks-2d" && name != "coupled-fields-2d")
      throw InputError("--builtin '" + spec +
                       "': unknown system (expected tied-blocks-2d:LEVEL or coupled-fields-2d:LEVEL)");
    int level = 0;
    try
      {
        if (colon == std::string::npos)
          throw std::invalid_argument("no level");
        std::size_t used = 0;
        level            = std::stoi(spec.substr(colon + 1), &used);
        if (used != spec.size() - colon - 1)
          throw std::invalid_argument("trailing");
      }
    catch (const std::exception&)
      {
        throw InputError("--builtin '" + spec + "': expected " + name + ":LEVEL with an integer LEVEL");
      }
    if (name == "coupled-fields-2d")
      return coupled_fields_2d(comm, {level, false});
    TiedBlocksOptions o;
    o.level = level;
    return tied_blocks_2d(comm, o);
  }
} // namespace multigrid
