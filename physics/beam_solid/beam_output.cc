#include "beam_solid/beam_output.h"

#include "common/run_output.h"

#include <cstdio>
#include <fstream>
#include <ostream>
#include <stdexcept>

namespace physics::beam_solid
{
  namespace
  {
    const char* point_arrays[] = {"displacement", "coupling_line_load"};
  } // namespace

  void write_beam_vtu(const BeamMesh& beam, const std::vector<double>& dofs,
                      const std::vector<std::array<double, 3>>& line_load, const std::string& file, int subdivisions)
  {
    std::vector<std::array<double, 3>> points, displacement, load;
    for (std::size_t e = 0; e < beam.elements.size(); ++e)
      {
        const auto&  nodes = beam.elements[e];
        const double l     = beam.element_length(e);
        for (int s = 0; s <= subdivisions; ++s)
          {
            const double xi = -1 + 2.0 * s / subdivisions;
            const auto   w  = centreline_weights(xi, l);
            std::array<double, 3> x{}, u{}, f{};
            for (int c = 0; c < 3; ++c)
              {
                for (int k = 0; k < 4; ++k)
                  {
                    const int    node      = nodes[k / 2];
                    const double reference = k % 2 == 0 ? beam.nodes[node][c] : beam.tangents[node][c];
                    x[c] += w[k] * (reference + dofs[6 * node + 3 * (k % 2) + c]);
                    u[c] += w[k] * dofs[6 * node + 3 * (k % 2) + c];
                  }
                f[c] = 0.5 * (1 - xi) * line_load[nodes[0]][c] + 0.5 * (1 + xi) * line_load[nodes[1]][c];
              }
            points.push_back(x);
            displacement.push_back(u);
            load.push_back(f);
          }
      }
    const std::size_t per_element = subdivisions + 1;
    write_atomically(file, [&](std::ostream& out) {
      out.precision(12);
      out << "<?xml version=\"1.0\"?>\n<VTKFile type=\"UnstructuredGrid\" version=\"0.1\" byte_order=\"LittleEndian\">\n"
          << "<UnstructuredGrid>\n<Piece NumberOfPoints=\"" << points.size() << "\" NumberOfCells=\""
          << beam.elements.size() << "\">\n<Points>\n<DataArray type=\"Float64\" NumberOfComponents=\"3\" format=\"ascii\">\n";
      for (const auto& x : points)
        out << x[0] << " " << x[1] << " " << x[2] << "\n";
      out << "</DataArray>\n</Points>\n<Cells>\n<DataArray type=\"Int64\" Name=\"connectivity\" format=\"ascii\">\n";
      for (std::size_t e = 0; e < beam.elements.size(); ++e)
        {
          for (std::size_t s = 0; s < per_element; ++s)
            out << e * per_element + s << " ";
          out << "\n";
        }
      out << "</DataArray>\n<DataArray type=\"Int64\" Name=\"offsets\" format=\"ascii\">\n";
      for (std::size_t e = 0; e < beam.elements.size(); ++e)
        out << (e + 1) * per_element << "\n";
      out << "</DataArray>\n<DataArray type=\"UInt8\" Name=\"types\" format=\"ascii\">\n";
      for (std::size_t e = 0; e < beam.elements.size(); ++e)
        out << "4\n"; // VTK_POLY_LINE
      out << "</DataArray>\n</Cells>\n<PointData Vectors=\"displacement\">\n";
      const std::array<const std::vector<std::array<double, 3>>*, 2> values{{&displacement, &load}};
      for (std::size_t a = 0; a < values.size(); ++a)
        {
          out << "<DataArray type=\"Float64\" Name=\"" << point_arrays[a] << "\" NumberOfComponents=\"3\" format=\"ascii\">\n";
          for (const auto& v : *values[a])
            out << v[0] << " " << v[1] << " " << v[2] << "\n";
          out << "</DataArray>\n";
        }
      out << "</PointData>\n</Piece>\n</UnstructuredGrid>\n</VTKFile>\n";
    });
  }

  void write_beam_pvtu(const std::vector<std::string>& pieces, const std::string& file)
  {
    write_atomically(file, [&](std::ostream& out) {
      out.precision(12);
      out << "<?xml version=\"1.0\"?>\n<VTKFile type=\"PUnstructuredGrid\" version=\"0.1\" byte_order=\"LittleEndian\">\n"
          << "<PUnstructuredGrid GhostLevel=\"0\">\n<PPointData Vectors=\"displacement\">\n";
      for (const char* name : point_arrays)
        out << "<PDataArray type=\"Float64\" Name=\"" << name << "\" NumberOfComponents=\"3\" format=\"ascii\"/>\n";
      out << "</PPointData>\n<PPoints>\n<PDataArray type=\"Float64\" NumberOfComponents=\"3\" format=\"ascii\"/>\n"
          << "</PPoints>\n";
      for (const auto& piece : pieces)
        out << "<Piece Source=\"" << piece << "\"/>\n";
      out << "</PUnstructuredGrid>\n</VTKFile>\n";
    });
  }
} // namespace physics::beam_solid
