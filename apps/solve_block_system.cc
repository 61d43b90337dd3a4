// solve_block_system: solve a saddle-point, n x n (FSI) or single-field block system with any of
// the seeds' preconditioners, inside GMRES, and report what it took.
//
// The system comes from files (a directory written by our apps with --export-system, or another
// code's single-matrix export such as tests/data/peer/meshtying2D_small) or from a built-in model
// problem. This is where preconditioners are compared on identical matrices.
//
// Sample runs:
//   solve_block_system --builtin tied-blocks-2d:3 --preset "emin(cheapsimple)"
//   mpirun -np 2 solve_block_system --system tests/data/peer/meshtying2D_small
//       --xml tests/data/peer_meshtying2D.xml --tol 1e-4 --per-block --json report.json
//   solve_block_system --builtin tied-blocks-2d:1 --preset "cheapsimple(sa-amg)"
//       --set "primal solver/max levels=2"
//   mpirun -np 2 solve_block_system --builtin coupled-fields-2d:3 --preset "fully-coupled-sa-amg(bgs)"
//       --set "coarse: max size=500"
//   solve_block_system --list-presets
#include "block_preconditioner.h"
#include "block_system_io.h"
#include "fully_coupled_amg.h"
#include "krylov_solver.h"
#include "model_problems.h"
#include "presets.h"
#include "trilinos_scope.h"

#include <Teuchos_CommHelpers.hpp>
#include <Teuchos_DefaultComm.hpp>
#include <Teuchos_ParameterListExceptions.hpp>
#include <Teuchos_XMLParameterListHelpers.hpp>
#include <Tpetra_Core.hpp>
#include <Xpetra_MultiVectorFactory.hpp>

#include <iostream>
#include <sstream>
#include <string>
#include <vector>

namespace
{
  const char* usage =
      R"(usage: solve_block_system (--system PATH | --builtin NAME) (--preset NAME | --xml FILE) [options]

Solves A x = b with right-preconditioned restarted GMRES (Belos) and a block preconditioner.

System (one of):
  --system PATH        a directory with manifest.txt (the project's format), or a prefix P of
                       another code's single-matrix export (P_matrix.mm, P_rhs.mm,
                       P_nullspace1.mm, P_interface_dof_map_MPI1.mm)
  --builtin NAME       a built-in model problem: tied-blocks-2d:LEVEL (two elastic blocks tied
                       by dual mortar multipliers; DOFs grow 4x per level) or
                       coupled-fields-2d:LEVEL (structure, Stokes-like fluid and ALE blocks
                       coupled through an interface, the FSI block layout; 4x per level)
  --dofs-per-node N    DOFs per node of a single-matrix export (default 2)

Preconditioner (one of):
  --preset NAME        a shipped preset (see --list-presets)
  --xml FILE           your own preset file, or a complete MueLu XML for a 2 x 2 system
  --set PATH=VALUE     override one preset parameter (repeatable), e.g.
                       --set "template parameters/MAX_LEVELS=2" or --set "sweeps=3"

Krylov method:
  --tol T              relative residual tolerance (default 1e-8)
  --per-block          apply the tolerance to every block's residual separately as well
  --max-iterations N   (default 500)
  --restart N          GMRES restart length (default 100)

Output:
  --json FILE          write the solve report as JSON (atomically)
  --export-system DIR  write the system in the project's format (manifest + Matrix Market)
  --write-solution FILE  write x as a Matrix Market array in the row order of the system's matrix
  --export-aggregates P  write every field's AMG aggregates on every coarse level as a VTK point
                       set P.pvtu (+ one .vtu per rank; blocked MueLu presets only) and print,
                       for contact systems, the aggregates that contain nodes of two bodies
  --print-xml          print the MueLu XML of a saddle-point or fully coupled preset and exit
  --list-presets       list the shipped presets with their descriptions and exit
  --help               this text

Exit status: 0 converged, 1 not converged, 2 bad input.
)";

  struct Options
  {
    std::string              system, builtin, preset, xml, json, export_dir, solution, aggregates;
    std::vector<std::string> overrides;
    multigrid::SolveOptions  solve;
    multigrid::ReadOptions   read;
    bool                     list = false, print_xml = false, help = false;
  };

  template <typename T>
  T parse_number(const std::string& option, const std::string& value)
  {
    std::istringstream s(value);
    T                  v{};
    if (!(s >> v) || !s.eof())
      throw multigrid::InputError(option + ": '" + value + "' is not a valid number");
    return v;
  }

  Options parse(int argc, char** argv)
  {
    Options o;
    for (int i = 1; i < argc; ++i)
      {
        const std::string a     = argv[i];
        auto              value = [&]() -> std::string {
          if (i + 1 >= argc)
            throw multigrid::InputError(a + ": missing value");
          return argv[++i];
        };
        if (a == "--system")
          o.system = value();
        else if (a == "--builtin")
          o.builtin = value();
        else if (a == "--preset")
          o.preset = value();
        else if (a == "--xml")
          o.xml = value();
        else if (a == "--set")
          o.overrides.push_back(value());
        else if (a == "--json")
          o.json = value();
        else if (a == "--export-system")
          o.export_dir = value();
        else if (a == "--write-solution")
          o.solution = value();
        else if (a == "--export-aggregates")
          o.aggregates = value();
        else if (a == "--tol")
          o.solve.tolerance = parse_number<double>(a, value());
        else if (a == "--max-iterations")
          o.solve.max_iterations = parse_number<int>(a, value());
        else if (a == "--restart")
          o.solve.restart = parse_number<int>(a, value());
        else if (a == "--dofs-per-node")
          o.read.dofs_per_node = parse_number<int>(a, value());
        else if (a == "--per-block")
          o.solve.per_block = true;
        else if (a == "--list-presets")
          o.list = true;
        else if (a == "--print-xml")
          o.print_xml = true;
        else if (a == "--help" || a == "-h")
          o.help = true;
        else
          throw multigrid::InputError("unknown option '" + a + "' (see --help)");
      }
    if (o.help || o.list)
      return o;
    if (o.system.empty() == o.builtin.empty())
      throw multigrid::InputError("give exactly one of --system PATH and --builtin NAME (see --help)");
    if (o.preset.empty() == o.xml.empty())
      throw multigrid::InputError("give exactly one of --preset NAME and --xml FILE (see --help)");
    if (!(o.solve.tolerance > 0 && o.solve.tolerance < 1))
      throw multigrid::InputError("--tol: expected 0 < T < 1");
    if (o.solve.max_iterations < 1 || o.solve.restart < 1)
      throw multigrid::InputError("--max-iterations and --restart: expected positive integers");
    if (o.read.dofs_per_node < 1)
      throw multigrid::InputError("--dofs-per-node: expected a positive integer");
    return o;
  }

  /// The aggregates as a VTK point set and, where the primal block carries body labels, the
  /// number of aggregates per level that span two bodies (0 where segregation works).
  void export_aggregates(const multigrid::BlockSystem&         system,
                         const multigrid::BlockPreconditioner& preconditioner, const std::string& path,
                         bool root)
  {
    const auto& fields = preconditioner.aggregates();
    multigrid::write_aggregates(system, fields, path);
    if (!root)
      std::cout.setstate(std::ios::failbit); // the counts below are collective; rank 0 prints
    std::cout << "aggregates written to " << path << ".pvtu\n";
    for (const auto& field : fields)
      {
        std::cout << "  block " << field.block << " (" << system.block(field.block).name
                  << "): aggregates per level";
        for (const auto& level : field.levels)
          {
            long long mine = 0, all = 0;
            for (const auto id : level)
              mine = std::max<long long>(mine, id + 1);
            Teuchos::reduceAll(*system.comm(), Teuchos::REDUCE_MAX, 1, &mine, &all);
            std::cout << " " << all;
          }
        std::cout << "\n";
      }
    if (system.has_interface() && !fields.empty())
      for (std::size_t l = 1; l <= fields.front().levels.size(); ++l)
        {
          const auto n = multigrid::aggregates_crossing_bodies(system, fields.front(), static_cast<int>(l));
          std::cout << "  level " << l << ": " << n << " primal aggregates contain nodes of two bodies\n";
        }
    std::cout.clear();
  }
} // namespace

int main(int argc, char** argv)
{
  multigrid::TrilinosScope mpi(argv);
  auto                     comm = Tpetra::getDefaultComm();
  const bool               root = comm->getRank() == 0;
  try
    {
      const Options o = parse(argc, argv);
      if (o.help)
        {
          if (root)
            std::cout << usage;
          return 0;
        }
      if (o.list)
        {
          if (root)
            for (const auto& name : multigrid::available_presets())
              std::cout << name << "\n    "
                        << multigrid::load_preset(name).parameters.get<std::string>("description", "")
                        << "\n";
          return 0;
        }

      // 1. The system.
      multigrid::BlockSystem system = o.builtin.empty() ? multigrid::read_block_system(o.system, comm, o.read)
                                                        : multigrid::builtin_system(o.builtin, comm);
      if (!o.export_dir.empty())
        multigrid::write_block_system(system, o.export_dir);

      // 2. The preset, with the user's overrides.
      multigrid::Preset preset =
          o.preset.empty() ? multigrid::load_preset_file(o.xml) : multigrid::load_preset(o.preset);
      multigrid::apply_overrides(preset, o.overrides);
      if (o.print_xml)
        {
          if (preset.kind != "saddle-point-amg" && preset.kind != "fully-coupled-amg")
            throw multigrid::InputError("--print-xml: preset '" + preset.name + "' is of kind '" + preset.kind +
                                        "', only saddle-point-amg and fully-coupled-amg presets are MueLu XML");
          if (root && preset.kind == "fully-coupled-amg")
            Teuchos::writeParameterListToXmlOStream(multigrid::fully_coupled_muelu_list(preset, system),
                                                    std::cout);
          else if (root)
            std::cout << multigrid::expand_template(preset, system.block(0).dofs_per_node,
                                                    system.n_blocks() > 1 ? system.block(1).dofs_per_node
                                                                          : 1);
          return 0;
        }

      // 3. Set up the preconditioner, 4. solve, 5. report.
      multigrid::SetupOptions setup;
      setup.keep_aggregates = !o.aggregates.empty();
      multigrid::BlockPreconditioner preconditioner(system, preset, setup);
      if (!o.aggregates.empty())
        export_aggregates(system, preconditioner, o.aggregates, root);
      auto x = Xpetra::MultiVectorFactory<multigrid::SC, multigrid::LO, multigrid::GO, multigrid::NO>::Build(
          system.full_map(), 1, true);
      const auto report = multigrid::solve(system, preconditioner, *x, o.solve);
      if (!o.solution.empty())
        multigrid::write_in_global_order(*x, o.solution);
      if (root)
        {
          multigrid::print_report(std::cout, report);
          if (!o.json.empty())
            multigrid::write_json_atomically(o.json, multigrid::to_json(report));
        }
      return report.converged ? 0 : 1;
    }
  catch (const multigrid::InputError& e)
    {
      if (root)
        std::cerr << "solve_block_system: error: " << e.what() << std::endl;
      return 2;
    }
  catch (const Teuchos::Exceptions::InvalidParameter& e) // a parameter of the preset MueLu refuses
    {
      if (root)
        std::cerr << "solve_block_system: error: " << multigrid::one_line_message(e.what()) << std::endl;
      return 2;
    }
  catch (const std::exception& e)
    {
      if (root)
        std::cerr << "solve_block_system: internal error: " << multigrid::one_line_message(e.what())
                  << std::endl;
      return 3;
    }
}
