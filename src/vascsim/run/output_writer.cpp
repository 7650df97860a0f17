#include "vascsim/run/output_writer.hpp"

#include <fmt/format.h>

#include "vascsim/core/atomic_file.hpp"
#include "vascsim/core/error.hpp"

namespace vascsim {

namespace fs = std::filesystem;

CsvTable::CsvTable(fs::path file, const std::vector<std::string>& columns, const std::string& comment)
    : file_(std::move(file)), out_(file_) {
  if (!out_) throw InputError(fmt::format("{}: cannot write", file_.string()));
  if (!comment.empty()) out_ << "# " << comment << "\n";
  for (std::size_t i = 0; i < columns.size(); ++i) out_ << (i ? "," : "") << columns[i];
  out_ << "\n" << std::flush;
  if (!out_) throw InputError(fmt::format("{}: cannot write", file_.string()));
}

void CsvTable::add_row(const std::string& row) {
  out_ << row << "\n" << std::flush;
  if (!out_) throw InputError(fmt::format("{}: cannot write (disk full?)", file_.string()));
}

VtkSeries::VtkSeries(fs::path vtk_dir, std::string name) : dir_(std::move(vtk_dir)), name_(std::move(name)) {}

void VtkSeries::index(double stamp, const std::string& file_name) {
  entries_.push_back({stamp, file_name});
  write_pvd(dir_ / (name_ + ".pvd"), entries_);
}

void VtkSeries::add_nodes(double stamp, const std::string& file_name, const Vec3Array& X, const Vec3Array& x,
                          const std::vector<Tet>& tets) {
  std::error_code ec;
  fs::create_directories(dir_, ec);
  write_vtu(dir_ / file_name, X, x, tets);
  index(stamp, file_name);
}

void VtkSeries::add_surface(double stamp, const std::string& file_name, const SurfaceFrame& frame,
                            const RenderSurface& surface) {
  std::error_code ec;
  fs::create_directories(dir_, ec);
  write_surface_vtu(dir_ / file_name, {&frame.positions, &frame.displacements, &frame.normals, &surface.uv,
                                       &surface.triangles, &surface.outer});
  index(stamp, file_name);
}

OutputWriter::OutputWriter(fs::path dir) : dir_(std::move(dir)) {
  std::error_code ec;
  fs::create_directories(dir_, ec);
  if (ec)
    throw InputError(fmt::format("{}: cannot create the output folder: {}", dir_.string(), ec.message()));
}

void OutputWriter::write_json(const std::string& name, const nlohmann::json& content) const {
  // Text that is not UTF-8 (a scene path in another encoding) is written with U+FFFD, never an exception.
  write_text(name, content.dump(2, ' ', false, nlohmann::json::error_handler_t::replace) + "\n");
}

void OutputWriter::write_text(const std::string& name, const std::string& content) const {
  write_file_atomically(path(name), content);
}

}  // namespace vascsim
