// VTK output of beams: every element drawn as a polyline through points of its Hermite
// centreline (current configuration), with the displacement and the coupling line load
// (interpolated linearly from the beam nodes) as point data. The beams are distributed
// (beam_partition.h): every rank writes its own elements as one .vtu piece, and a .pvtu record
// names the pieces, as for the solid (common/vtk_output.h).
#pragma once

#include "beam_solid/kirchhoff_beam.h"

#include <array>
#include <string>
#include <vector>

namespace physics::beam_solid
{
  /// Writes the elements of `beam` to `file` atomically (a temporary file renamed into place).
  /// `dofs`: 6 per node of `beam` (position and tangent displacements); `line_load`: one vector
  /// per node. Throws std::runtime_error naming the file if it cannot be written.
  void write_beam_vtu(const BeamMesh& beam, const std::vector<double>& dofs,
                      const std::vector<std::array<double, 3>>& line_load, const std::string& file,
                      int subdivisions = 4);

  /// Writes the .pvtu record `file` naming the .vtu `pieces` write_beam_vtu() wrote (file
  /// names relative to the record), atomically.
  void write_beam_pvtu(const std::vector<std::string>& pieces, const std::string& file);
} // namespace physics::beam_solid
