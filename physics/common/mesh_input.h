// Meshes from gmsh: a .geo source is meshed by the gmsh executable (on rank 0, with
// `-setnumber refine N` and the variables of GmshSource), a .msh file is read directly. Physical volumes (2D: surfaces) become
// deal.II material ids, physical surfaces (2D: lines) boundary ids.
//
// gmsh works in a temporary directory of its own (mkdtemp in the work directory), removed once the
// mesh is read: two runs at once, even in the same output directory, never share a file. Only when
// gmsh fails is its log kept there (the error names it).
#pragma once

#include <deal.II/grid/tria.h>

#include <mpi.h>

#include <string>
#include <utility>
#include <vector>

namespace physics
{
  /// What gmsh is given for a .geo source: `-setnumber refine N` and further `-setnumber NAME
  /// VALUE` for the .geo's other variables (e.g. the tube's `length`, see meshes/). Converts from
  /// a refinement alone.
  struct GmshSource
  {
    GmshSource(int refinement = 1) // NOLINT(google-explicit-constructor): a refinement is a source
        : refinement(refinement)
    {
    }
    int                                         refinement;
    std::vector<std::pair<std::string, double>> variables;
    /// " -setnumber refine N -setnumber NAME VALUE ..."
    std::string setnumbers() const;
    /// "refine N, NAME VALUE, ..." (messages, file names)
    std::string describe() const;
    /// Throws std::invalid_argument naming the parameter 'Gmsh variables' if the code of the .geo
    /// text `geo` (file `file`; comments and strings do not count) does not mention a variable
    /// (gmsh would define it silently, unused).
    void check_variables_in(const std::string& file, const std::string& geo) const;
  };

  /// A mesh file to read: the user's .msh file itself, or this rank's temporary copy of the mesh
  /// gmsh made of a .geo source (a name no other run or rank uses, removed when this goes).
  class MeshFile
  {
  public:
    MeshFile(std::string path, bool temporary);
    MeshFile(MeshFile&& other) noexcept;
    MeshFile(const MeshFile&)            = delete;
    MeshFile& operator=(const MeshFile&) = delete;
    MeshFile& operator=(MeshFile&&)      = delete;
    ~MeshFile();

    const std::string& path() const { return path_; }

    /// Where a file name is expected: `read_beam_mesh(gmsh_mesh(...))` reads the copy before it goes.
    operator const std::string&() const { return path_; }

  private:
    std::string path_;
    bool        temporary_;
  };

  /// The .msh file to read for `file`: `file` itself, or for a .geo source the mesh gmsh makes of
  /// it on rank 0 (`-<dimension> -setnumber refine N -format msh22`), given to every rank as a
  /// temporary file in `work_directory`. Throws std::invalid_argument naming the file if it is
  /// missing or gmsh fails (then naming gmsh's log).
  MeshFile gmsh_mesh(const std::string& file, int dimension, const GmshSource& source,
                     const std::string& work_directory, MPI_Comm comm);

  /// Fills `tria` (empty) from `file`. Throws std::invalid_argument with a one-line message
  /// naming the file for a missing file, a gmsh failure or a mesh deal.II cannot read
  /// (quadrilaterals/hexahedra expected). A .geo source is meshed on rank 0 of `comm` and its
  /// text sent to every rank of `comm` (for a distributed mesh: the group roots only, see
  /// common/distributed_mesh.h): no mesh file is left behind.
  template <int dim>
  void read_mesh(const std::string& file, const GmshSource& source, const std::string& work_directory,
                 dealii::Triangulation<dim>& tria, MPI_Comm comm);
} // namespace physics
