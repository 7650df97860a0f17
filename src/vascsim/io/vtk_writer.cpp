#include "vascsim/io/vtk_writer.hpp"

#include <fmt/format.h>
#include <fmt/os.h>

#include "vascsim/core/error.hpp"

namespace vascsim {

namespace {
void write_vectors(fmt::ostream& out, const std::string& name, const Vec3Array& v) {
  out.print("        <DataArray type=\"Float64\" Name=\"{}\" NumberOfComponents=\"3\" format=\"ascii\">\n", name);
  for (const auto& p : v) out.print("{:.10g} {:.10g} {:.10g}\n", p.x(), p.y(), p.z());
  out.print("        </DataArray>\n");
}
}  // namespace

void write_vtu(const std::filesystem::path& file, const Vec3Array& X, const Vec3Array& x, const std::vector<Tet>& tets,
               const std::vector<std::pair<std::string, const Vec3Array*>>& extra) {
  try {
    auto out = fmt::output_file(file.string());
    out.print("<?xml version=\"1.0\"?>\n<VTKFile type=\"UnstructuredGrid\" version=\"1.0\" byte_order=\"LittleEndian\">\n");
    out.print("  <UnstructuredGrid>\n    <Piece NumberOfPoints=\"{}\" NumberOfCells=\"{}\">\n", x.size(), tets.size());
    out.print("      <PointData Vectors=\"displacement\">\n");
    Vec3Array u(x.size());
    for (std::size_t i = 0; i < x.size(); ++i) u[i] = x[i] - X[i];
    write_vectors(out, "displacement", u);
    for (const auto& [name, values] : extra) write_vectors(out, name, *values);
    out.print("      </PointData>\n      <Points>\n");
    write_vectors(out, "Points", x);
    out.print("      </Points>\n      <Cells>\n");
    out.print("        <DataArray type=\"Int32\" Name=\"connectivity\" format=\"ascii\">\n");
    for (const Tet& t : tets) out.print("{} {} {} {}\n", t[0], t[1], t[2], t[3]);
    out.print("        </DataArray>\n        <DataArray type=\"Int32\" Name=\"offsets\" format=\"ascii\">\n");
    for (std::size_t c = 0; c < tets.size(); ++c) out.print("{}\n", 4 * (c + 1));
    out.print("        </DataArray>\n        <DataArray type=\"UInt8\" Name=\"types\" format=\"ascii\">\n");
    for (std::size_t c = 0; c < tets.size(); ++c) out.print("10\n");  // VTK_TETRA
    out.print("        </DataArray>\n      </Cells>\n    </Piece>\n  </UnstructuredGrid>\n</VTKFile>\n");
  } catch (const std::system_error& e) {
    throw InputError(fmt::format("{}: cannot write: {}", file.string(), e.what()));
  }
}

void write_pvd(const std::filesystem::path& file, const std::vector<PvdEntry>& entries) {
  try {
    auto out = fmt::output_file(file.string());
    out.print("<?xml version=\"1.0\"?>\n<VTKFile type=\"Collection\" version=\"0.1\">\n  <Collection>\n");
    for (const auto& e : entries)
      out.print("    <DataSet timestep=\"{:.10g}\" part=\"0\" file=\"{}\"/>\n", e.time, e.file);
    out.print("  </Collection>\n</VTKFile>\n");
  } catch (const std::system_error& e) {
    throw InputError(fmt::format("{}: cannot write: {}", file.string(), e.what()));
  }
}

}  // namespace vascsim
