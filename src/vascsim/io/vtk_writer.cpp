#include "vascsim/io/vtk_writer.hpp"

#include <fmt/format.h>
#include <iterator>

#include "vascsim/core/atomic_file.hpp"

namespace vascsim {

namespace {

// A file's text, built in memory and written at once (write_file_atomically): a frame is complete or absent.
struct Text {
  fmt::memory_buffer buffer;
  template <class... Args>
  void print(fmt::format_string<Args...> format, Args&&... args) {
    fmt::format_to(std::back_inserter(buffer), format, std::forward<Args>(args)...);
  }
  void write(const std::filesystem::path& file) const {
    write_file_atomically(file, {buffer.data(), buffer.size()});
  }
};

void write_vectors(Text& out, const std::string& name, const Vec3Array& v) {
  out.print("        <DataArray type=\"Float64\" Name=\"{}\" NumberOfComponents=\"3\" format=\"ascii\">\n",
            name);
  for (const auto& p : v) out.print("{:.10g} {:.10g} {:.10g}\n", p.x(), p.y(), p.z());
  out.print("        </DataArray>\n");
}
}  // namespace

namespace {

// The grid of one file: points, point data, cells (connectivity of `corners` nodes each, one VTK type).
template <std::size_t Corners, class WritePointData, class WriteCellData>
void write_grid(const std::filesystem::path& file, const Vec3Array& points,
                const std::vector<std::array<Index, Corners>>& cells, int vtk_type, const char* point_vectors,
                WritePointData&& point_data, WriteCellData&& cell_data) {
  Text out;
  {
    out.print(
        "<?xml version=\"1.0\"?>\n<VTKFile type=\"UnstructuredGrid\" version=\"1.0\" "
        "byte_order=\"LittleEndian\">\n");
    out.print("  <UnstructuredGrid>\n    <Piece NumberOfPoints=\"{}\" NumberOfCells=\"{}\">\n", points.size(),
              cells.size());
    out.print("      <PointData Vectors=\"{}\">\n", point_vectors);
    point_data(out);
    out.print("      </PointData>\n      <CellData>\n");
    cell_data(out);
    out.print("      </CellData>\n      <Points>\n");
    write_vectors(out, "Points", points);
    out.print("      </Points>\n      <Cells>\n");
    out.print("        <DataArray type=\"Int32\" Name=\"connectivity\" format=\"ascii\">\n");
    for (const auto& c : cells) {
      for (std::size_t k = 0; k < Corners; ++k) out.print("{}{}", k ? " " : "", c[k]);
      out.print("\n");
    }
    out.print("        </DataArray>\n        <DataArray type=\"Int32\" Name=\"offsets\" format=\"ascii\">\n");
    for (std::size_t c = 0; c < cells.size(); ++c) out.print("{}\n", Corners * (c + 1));
    out.print("        </DataArray>\n        <DataArray type=\"UInt8\" Name=\"types\" format=\"ascii\">\n");
    for (std::size_t c = 0; c < cells.size(); ++c) out.print("{}\n", vtk_type);
    out.print("        </DataArray>\n      </Cells>\n    </Piece>\n  </UnstructuredGrid>\n</VTKFile>\n");
  }
  out.write(file);
}

}  // namespace

void write_vtu(const std::filesystem::path& file, const Vec3Array& X, const Vec3Array& x,
               const std::vector<Tet>& tets,
               const std::vector<std::pair<std::string, const Vec3Array*>>& extra) {
  Vec3Array u(x.size());
  for (std::size_t i = 0; i < x.size(); ++i) u[i] = x[i] - X[i];
  write_grid(
      file, x, tets, 10 /* VTK_TETRA */, "displacement",
      [&](Text& out) {
        write_vectors(out, "displacement", u);
        for (const auto& [name, values] : extra) write_vectors(out, name, *values);
      },
      [](Text&) {});
}

void write_surface_vtu(const std::filesystem::path& file, const SurfaceVtu& s) {
  write_grid(
      file, *s.positions, *s.triangles, 5 /* VTK_TRIANGLE */, "displacement",
      [&](Text& out) {
        write_vectors(out, "displacement", *s.displacements);
        if (s.normals) write_vectors(out, "normal", *s.normals);
        if (s.uv && !s.uv->empty()) {
          out.print(
              "        <DataArray type=\"Float64\" Name=\"uv\" NumberOfComponents=\"2\" format=\"ascii\">\n");
          for (const auto& t : *s.uv) out.print("{:.10g} {:.10g}\n", t.x(), t.y());
          out.print("        </DataArray>\n");
        }
      },
      [&](Text& out) {
        if (!s.outer) return;
        out.print("        <DataArray type=\"UInt8\" Name=\"outer\" format=\"ascii\">\n");
        for (char o : *s.outer) out.print("{}\n", o ? 1 : 0);
        out.print("        </DataArray>\n");
      });
}

void write_pvd(const std::filesystem::path& file, const std::vector<PvdEntry>& entries) {
  Text out;
  {
    out.print("<?xml version=\"1.0\"?>\n<VTKFile type=\"Collection\" version=\"0.1\">\n  <Collection>\n");
    for (const auto& e : entries)
      out.print("    <DataSet timestep=\"{:.10g}\" part=\"0\" file=\"{}\"/>\n", e.time, e.file);
    out.print("  </Collection>\n</VTKFile>\n");
  }
  out.write(file);
}

}  // namespace vascsim
