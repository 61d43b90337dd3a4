#include "common/mesh_input.h"

#include <deal.II/base/exceptions.h>
#include <deal.II/base/mpi.h>
#include <deal.II/grid/grid_in.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>

namespace physics
{
  namespace
  {
    std::string quoted(const std::string& s)
    {
      std::string r = "'";
      for (char c : s)
        r += (c == '\'') ? std::string("'\\''") : std::string(1, c);
      return r + "'";
    }
  } // namespace

  std::string gmsh_mesh(const std::string& file, int dimension, int refinement, const std::string& work_directory,
                        MPI_Comm comm)
  {
    namespace fs = std::filesystem;
    if (!fs::is_regular_file(file))
      throw std::invalid_argument(file + ": mesh file not found");
    if (fs::path(file).extension() != ".geo")
      return file;
    // Rank 0 meshes; everybody learns whether it worked.
    const std::string msh =
        work_directory + "/" + fs::path(file).stem().string() + "-refine" + std::to_string(refinement) + ".msh";
    const std::string log = msh + ".log";
    int               ok  = 1;
    if (dealii::Utilities::MPI::this_mpi_process(comm) == 0)
      {
        const std::string tmp = msh + ".partial";
        const std::string cmd = "gmsh -" + std::to_string(dimension) + " -setnumber refine " +
                                std::to_string(refinement) + " -format msh22 " + quoted(file) + " -o " + quoted(tmp) +
                                " > " + quoted(log) + " 2>&1";
        ok = std::system(cmd.c_str()) == 0 && fs::is_regular_file(tmp);
        if (ok)
          fs::rename(tmp, msh);
      }
    MPI_Bcast(&ok, 1, MPI_INT, 0, comm);
    if (!ok)
      throw std::invalid_argument(file + ": gmsh could not mesh it (log: " + log + ")");
    return msh;
  }

  template <int dim>
  void read_mesh(const std::string& file, int refinement, const std::string& work_directory,
                 dealii::Triangulation<dim>& tria, MPI_Comm comm)
  {
    if (!std::filesystem::is_regular_file(file))
      throw std::invalid_argument(file + ": mesh file not found (parameter 'Mesh file')");
    const std::string msh = gmsh_mesh(file, dim, refinement, work_directory, comm);
    std::ifstream in(msh);
    if (!in)
      throw std::invalid_argument(msh + ": cannot open the mesh");
    dealii::GridIn<dim> grid_in;
    grid_in.attach_triangulation(tria);
    try
      {
        grid_in.read_msh(in);
      }
    catch (const dealii::ExceptionBase& e)
      {
        std::string what = e.what();
        // deal.II's messages span many lines: keep the one that says what went wrong.
        const auto pos = what.find("Additional information:");
        what           = pos == std::string::npos ? "unreadable mesh" : what.substr(pos + 24);
        for (auto& c : what)
          if (c == '\n')
            c = ' ';
        throw std::invalid_argument(msh + ": cannot read the mesh as a " + std::to_string(dim) +
                                    "D quadrilateral/hexahedral mesh: " + what.substr(0, 200));
      }
  }

  template void read_mesh<2>(const std::string&, int, const std::string&, dealii::Triangulation<2>&, MPI_Comm);
  template void read_mesh<3>(const std::string&, int, const std::string&, dealii::Triangulation<3>&, MPI_Comm);
} // namespace physics
