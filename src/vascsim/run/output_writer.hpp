#pragma once
// One writer for everything a run leaves in its output folder: the folder itself, summary.json, the CSV
// tables (probes.csv, force_history.csv, an experiment's curve) and the VTK series (the node cloud and the
// MLS-mapped surface under vtk/). Every driver writes through it, so files are named and checked the same
// way: a file that cannot be written is an InputError naming it, never a silent loss.

#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "vascsim/geometry/vessel_body.hpp"
#include "vascsim/io/vtk_writer.hpp"

namespace vascsim {

/// A CSV table written row by row and flushed as it goes, so a run that stops early leaves what it had.
class CsvTable {
 public:
  /// Creates the file with an optional "# comment" line and the header. Throws InputError if it cannot.
  CsvTable(std::filesystem::path file, const std::vector<std::string>& columns,
           const std::string& comment = "");
  /// Appends one row (no newline) and flushes. Throws InputError if the write fails.
  void add_row(const std::string& row);
  const std::filesystem::path& file() const { return file_; }

 private:
  std::filesystem::path file_;
  std::ofstream out_;
};

/// A ParaView time series under <folder>/vtk/: one .vtu file per frame and <name>.pvd listing them, rewritten
/// after every frame so the series is readable while the run goes on.
class VtkSeries {
 public:
  VtkSeries(std::filesystem::path vtk_dir, std::string name);
  /// The node cloud at one frame (positions x, rest positions X, tets as cells).
  void add_nodes(double stamp, const std::string& file_name, const Vec3Array& X, const Vec3Array& x,
                 const std::vector<Tet>& tets);
  /// The MLS-mapped surface at one frame.
  void add_surface(double stamp, const std::string& file_name, const SurfaceFrame& frame,
                   const RenderSurface& surface);
  /// "vtk/<name>.pvd", relative to the output folder.
  std::string pvd_relative() const { return "vtk/" + name_ + ".pvd"; }

 private:
  void index(double stamp, const std::string& file_name);
  std::filesystem::path dir_;
  std::string name_;
  std::vector<PvdEntry> entries_;
};

class OutputWriter {
 public:
  /// Creates the folder (and its parents). Throws InputError naming it if that fails.
  explicit OutputWriter(std::filesystem::path dir);
  const std::filesystem::path& dir() const { return dir_; }
  std::filesystem::path path(const std::string& name) const { return dir_ / name; }

  /// Writes a JSON document (2-space indent, final newline). Throws InputError naming the file if it fails.
  void write_json(const std::string& name, const nlohmann::json& content) const;
  /// Writes a text file. Throws InputError naming the file if it fails.
  void write_text(const std::string& name, const std::string& content) const;
  /// summary.json.
  void write_summary(const nlohmann::json& summary) const { write_json("summary.json", summary); }
  /// A CSV table in the folder.
  CsvTable table(const std::string& name, const std::vector<std::string>& columns,
                 const std::string& comment = "") const {
    return CsvTable(path(name), columns, comment);
  }
  /// A VTK series under vtk/ (the folder is made on the first frame).
  VtkSeries series(const std::string& name) const { return VtkSeries(dir_ / "vtk", name); }

 private:
  std::filesystem::path dir_;
};

}  // namespace vascsim
