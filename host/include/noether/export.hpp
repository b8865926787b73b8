#pragma once
// Export: a run's bodies as files other tools read — ParaView's time series of VTK XML
// unstructured grids (a .pvd collection and one .vtu per frame), so that ParaView, VisIt,
// PyVista or meshio show the shapes moving (docs/visualisation.md, "ParaView").
#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

namespace noether {

struct ExportOptions {
  // At most this many frames (≥ 2), evenly spaced by index, the first and last among them.
  std::size_t max_frames = 200;
  // An ellipsoid's or a sphere's surface: the icosahedron subdivided this many times (20·4^level
  // triangles), 0–6.
  int tessellation = 4;
  bool force = false;  // replace an earlier export at the same place
};

struct ExportReport {
  std::size_t frames_in_file = 0, frames_written = 0;
  std::filesystem::path collection, folder;  // PVD file and the folder of its .vtu files
  std::uintmax_t bytes = 0;                  // all files written
  std::vector<std::string> notes;            // as view_html's (decimation, a killed run, …)
};

// Writes `collection` (a .pvd file) and, beside it, a folder of its stem holding one .vtu per
// frame: every body's surface in the scene's frame and length unit (a point mass as a vertex),
// point and cell data `body` (the body's index, in scene order) and the frame's time as field
// data TimeValue. Nothing is half-written: the folder and the collection are made under hidden
// names and renamed into place. OutputError when they exist (unless force; a folder holding
// other files than frame-*.vtu is never replaced), for a file that is not a run, or when writing
// fails; SceneError for bad options.
ExportReport export_vtk(const std::filesystem::path& run_file, const std::filesystem::path& collection,
                        const ExportOptions& options = {});

}  // namespace noether
