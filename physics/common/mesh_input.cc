#include "common/mesh_input.h"

#include "temporary_files.h"

#include <deal.II/base/exceptions.h>
#include <deal.II/base/mpi.h>
#include <deal.II/grid/grid_in.h>

#include <algorithm>
#include <algorithm>
#include <cctype>
#include <cerrno>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>
#include <memory>
#include <sstream>
#include <stdexcept>

namespace physics
{
  namespace
  {
    namespace fs = std::filesystem;

    std::string quoted(const std::string& s)
    {
      std::string r = "'";
      for (char c : s)
        r += (c == '\'') ? std::string("'\\''") : std::string(1, c);
      return r + "'";
    }

    /// Rank 0's `text` on every rank (sent in pieces: MPI counts are int).
    void broadcast(std::string& text, MPI_Comm comm)
    {
      unsigned long long size = text.size();
      MPI_Bcast(&size, 1, MPI_UNSIGNED_LONG_LONG, 0, comm);
      text.resize(size);
      constexpr unsigned long long piece = std::numeric_limits<int>::max();
      for (unsigned long long begin = 0; begin < size; begin += piece)
        MPI_Bcast(text.data() + begin, static_cast<int>(std::min(piece, size - begin)), MPI_CHAR, 0, comm);
    }

    std::string read_whole_file(const std::string& file)
    {
      std::ifstream      in(file, std::ios::binary);
      std::ostringstream text;
      text << in.rdbuf();
      return text.str();
    }

    /// Rank 0 only: meshes `geo` with gmsh in a fresh temporary directory under `work_directory`
    /// and returns the mesh text. The directory is removed, except, when gmsh fails, its log
    /// (named in the message of the std::invalid_argument thrown then).
    std::string run_gmsh(const std::string& geo, int dimension, const GmshSource& source,
                         const std::string& work_directory)
    {
      source.check_variables_in(geo, read_whole_file(geo));
      const int       refinement = source.refinement;
      std::error_code ec;
      fs::create_directories(work_directory, ec);
      const std::string stem = fs::path(geo).stem().string();
      std::string       name =
          (fs::path(work_directory) / ("gmsh-" + stem + "-refine" + std::to_string(refinement) + "-XXXXXX"))
              .string();
      if (::mkdtemp(name.data()) == nullptr)
        throw std::invalid_argument(geo + ": cannot create a temporary directory for gmsh in " +
                                    work_directory + " (" + std::strerror(errno) + ")");
      const std::string msh = name + "/mesh.msh", log = name + "/gmsh.log";
      const std::string cmd = "gmsh -" + std::to_string(dimension) + source.setnumbers() + " -format msh22 " +
                              quoted(geo) + " -o " + quoted(msh) + " > " + quoted(log) + " 2>&1";
      if (std::system(cmd.c_str()) != 0 || !fs::is_regular_file(msh))
        {
          fs::remove(msh, ec);
          throw std::invalid_argument(geo + ": gmsh could not mesh it (log: " + log + ")");
        }
      std::string text = read_whole_file(msh);
      fs::remove_all(name, ec);
      return text;
    }

    /// The text of the mesh gmsh makes of `geo` on rank 0, on every rank; an error on rank 0 is
    /// thrown on every rank.
    std::string gmsh_mesh_text(const std::string& geo, int dimension, const GmshSource& source,
                               const std::string& work_directory, MPI_Comm comm)
    {
      std::string text, error;
      if (dealii::Utilities::MPI::this_mpi_process(comm) == 0)
        {
          try
            {
              text = run_gmsh(geo, dimension, source, work_directory);
            }
          catch (const std::invalid_argument& e)
            {
              error = e.what();
            }
        }
      broadcast(error, comm);
      if (!error.empty())
        throw std::invalid_argument(error);
      broadcast(text, comm);
      return text;
    }

    bool is_gmsh_source(const std::string& file)
    {
      return fs::path(file).extension() == ".geo";
    }
  } // namespace

  std::string GmshSource::setnumbers() const
  {
    std::ostringstream s;
    s.precision(17);
    s << " -setnumber refine " << refinement;
    for (const auto& [name, value] : variables)
      s << " -setnumber " << name << " " << value;
    return s.str();
  }

  std::string GmshSource::describe() const
  {
    std::ostringstream s;
    s << "refine " << refinement;
    for (const auto& [name, value] : variables)
      s << ", " << name << " " << value;
    return s.str();
  }

  namespace
  {
    /// The .geo text with its comments (// to the line's end, /* ... */) and string literals
    /// blanked: what the code itself says. A blank keeps the words on either side apart.
    std::string geo_code(const std::string& geo)
    {
      std::string code = geo;
      for (std::size_t i = 0; i < code.size(); ++i)
        {
          std::size_t end = i;
          if (code.compare(i, 2, "//") == 0)
            end = std::min(code.find('\n', i), code.size());
          else if (code.compare(i, 2, "/*") == 0)
            end = std::min(code.find("*/", i + 2), code.size() - 2) + 2;
          else if (code[i] == '"')
            end = std::min(code.find('"', i + 1), code.size() - 1) + 1;
          else
            continue;
          std::fill(code.begin() + i, code.begin() + end, ' ');
          i = end - 1;
        }
      return code;
    }
  } // namespace

  void GmshSource::check_variables_in(const std::string& file, const std::string& geo_text) const
  {
    // A whole word of the code: not a part of a longer name, not in a comment or a string.
    const auto is_name_char = [](char c) { return std::isalnum(static_cast<unsigned char>(c)) || c == '_'; };
    const std::string geo   = geo_code(geo_text);
    for (const auto& [name, value] : variables)
      {
        bool found = false;
        for (auto at = geo.find(name); at != std::string::npos && !found; at = geo.find(name, at + 1))
          found = (at == 0 || !is_name_char(geo[at - 1])) &&
                  (at + name.size() == geo.size() || !is_name_char(geo[at + name.size()]));
        if (!found)
          throw std::invalid_argument("parameter 'Gmsh variables' (Mesh): " + file + " has no variable '" + name +
                                      "'");
      }
  }

  MeshFile::MeshFile(std::string path, bool temporary)
      : path_(std::move(path))
      , temporary_(temporary)
  {
  }

  MeshFile::MeshFile(MeshFile&& other) noexcept
      : path_(std::move(other.path_))
      , temporary_(other.temporary_)
  {
    other.temporary_ = false;
  }

  MeshFile::~MeshFile()
  {
    if (temporary_)
      {
        std::error_code ec;
        fs::remove(path_, ec);
      }
  }

  MeshFile gmsh_mesh(const std::string& file, int dimension, const GmshSource& source,
                     const std::string& work_directory, MPI_Comm comm)
  {
    if (!fs::is_regular_file(file))
      throw std::invalid_argument(file + ": mesh file not found");
    if (!is_gmsh_source(file))
      return MeshFile(file, false);
    const std::string text = gmsh_mesh_text(file, dimension, source, work_directory, comm);
    // Every rank its own copy: none waits for another before removing it.
    const std::string copy = multigrid::unique_temporary_name(
        (fs::path(work_directory) / (fs::path(file).stem().string() + "-refine" + std::to_string(source.refinement)))
            .string(),
        "msh");
    MeshFile      mesh(copy, true);
    std::ofstream out(copy, std::ios::binary);
    out << text;
    if (!out.flush())
      throw std::invalid_argument(file + ": cannot write its gmsh mesh to " + copy);
    return mesh;
  }

  template <int dim>
  void read_mesh(const std::string& file, const GmshSource& source, const std::string& work_directory,
                 dealii::Triangulation<dim>& tria, MPI_Comm comm)
  {
    if (!fs::is_regular_file(file))
      throw std::invalid_argument(file + ": mesh file not found (parameter 'Mesh file')");
    const bool                    geo = is_gmsh_source(file);
    std::unique_ptr<std::istream> in;
    if (geo)
      in = std::make_unique<std::istringstream>(gmsh_mesh_text(file, dim, source, work_directory, comm));
    else
      {
        in = std::make_unique<std::ifstream>(file);
        if (!*in)
          throw std::invalid_argument(file + ": cannot open the mesh");
      }
    const std::string origin = geo ? file + " (meshed by gmsh, " + source.describe() + ")" : file;
    dealii::GridIn<dim> grid_in;
    grid_in.attach_triangulation(tria);
    try
      {
        grid_in.read_msh(*in);
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
        throw std::invalid_argument(origin + ": cannot read the mesh as a " + std::to_string(dim) +
                                    "D quadrilateral/hexahedral mesh: " + what.substr(0, 200));
      }
  }

  template void read_mesh<2>(const std::string&, const GmshSource&, const std::string&, dealii::Triangulation<2>&,
                             MPI_Comm);
  template void read_mesh<3>(const std::string&, const GmshSource&, const std::string&, dealii::Triangulation<3>&,
                             MPI_Comm);
} // namespace physics
