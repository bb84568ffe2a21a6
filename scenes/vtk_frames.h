#pragma once
// ParaView frames of a World: one VTK XML file per frame (the spheres as points, with their
// radius, velocity, speed, angular velocity, sleep state and handle as point data) and a .pvd
// time index that ParaView opens as one animation. `hail-bench run --vtk DIR --vtk-every K`
// and the Python module (hail.VtkFrames) write them.
//
// The format is VTK's XML (https://docs.vtk.org/en/latest/design_documents/VTKFileFormats.html):
// PolyData (.vtp, the points as vertices, the default) or UnstructuredGrid (.vtu, the points as
// VTK_VERTEX cells: the same data for readers that take only unstructured grids, e.g.
// meshio), with the arrays raw-appended in little-endian binary (header_type UInt64): a frame
// costs about 50 bytes a sphere and no encoding. Glyph by "radius" (Scale Array) in ParaView.

#include <cstddef>
#include <ostream>
#include <string>
#include <utility>
#include <vector>

#include "hail/world.h"

namespace hail::bench {

enum class VtkFormat {
  PolyData,          ///< .vtp
  UnstructuredGrid,  ///< .vtu
};

/// One frame of `world`'s spheres, in slot order, as a whole VTK XML file.
void write_vtk_frame(std::ostream& out, const World& world, VtkFormat format);

/// A folder of frames, name_000000.vtp, name_000001.vtp, ..., and name.pvd listing each with its
/// time. Each file is written beside its target and renamed over it (scenes/output_file.h), and
/// the .pvd is rewritten after every frame, so a run cut short leaves an index of the frames
/// it wrote. Failures are hail::FileError naming the path.
class VtkFrames {
 public:
  /// Creates `dir` if missing (FileError if it cannot be, or no file can be made in it).
  explicit VtkFrames(std::string dir, VtkFormat format = VtkFormat::PolyData, std::string name = "frame");
  /// Writes the next frame, at simulated time `time` (s), and the index; returns the frame's path.
  std::string write(const World& world, double time);
  [[nodiscard]] std::size_t frame_count() const { return frames_.size(); }
  [[nodiscard]] std::string index_path() const;
  [[nodiscard]] const std::string& dir() const { return dir_; }

 private:
  std::string dir_, name_;
  VtkFormat format_;
  std::vector<std::pair<double, std::string>> frames_;  ///< time, file name (relative to dir_)
};

}  // namespace hail::bench
