#include "scenes/vtk_frames.h"

#include <bit>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <stdexcept>

#include "hail/errors.h"
#include "scenes/output_file.h"

namespace hail::bench {
namespace {

/// The arrays of a frame, each written as one appended block: UInt64 byte count, then the bytes.
struct Block {
  std::vector<char> bytes;
  template <class T>
  void put(T v) {
    const char* p = reinterpret_cast<const char*>(&v);
    bytes.insert(bytes.end(), p, p + sizeof v);
  }
};

struct Array {
  const char* name;
  const char* type;  // VTK's type name
  int components;
  Block data;
};

void write_array_header(std::ostream& out, const Array& a, std::uint64_t& offset, const char* indent) {
  out << indent << "<DataArray type=\"" << a.type << "\" Name=\"" << a.name << "\" NumberOfComponents=\""
      << a.components << "\" format=\"appended\" offset=\"" << offset << "\"/>\n";
  offset += sizeof(std::uint64_t) + a.data.bytes.size();
}

[[noreturn]] void file_error(const std::string& what) { throw FileError("hail: " + what); }

}  // namespace

void write_vtk_frame(std::ostream& out, const World& world, VtkFormat format) {
  static_assert(std::endian::native == std::endian::little, "the files say LittleEndian");
  const SphereSoA& s = world.soa();
  const std::size_t n = world.sphere_count();
  Array points{"Points", "Float32", 3, {}}, radius{"radius", "Float32", 1, {}}, velocity{"velocity", "Float32", 3, {}},
      speed{"speed", "Float32", 1, {}}, spin{"angular_velocity", "Float32", 3, {}},
      sleeping{"sleeping", "UInt8", 1, {}}, handle{"handle", "UInt64", 1, {}};
  Array connectivity{"connectivity", "Int64", 1, {}}, offsets{"offsets", "Int64", 1, {}}, types{"types", "UInt8", 1, {}};
  for (std::size_t k = 0; k < n; ++k) {
    points.data.put(s.px[k]), points.data.put(s.py[k]), points.data.put(s.pz[k]);
    radius.data.put(s.radius[k]);
    velocity.data.put(s.vx[k]), velocity.data.put(s.vy[k]), velocity.data.put(s.vz[k]);
    speed.data.put(std::sqrt(s.vx[k] * s.vx[k] + s.vy[k] * s.vy[k] + s.vz[k] * s.vz[k]));
    spin.data.put(s.wx[k]), spin.data.put(s.wy[k]), spin.data.put(s.wz[k]);
    sleeping.data.put(static_cast<std::uint8_t>((s.flags[k] & kSphereFlagSleeping) != 0));
    const SphereId id = world.id_at(k);
    handle.data.put(std::uint64_t{id.index} | (std::uint64_t{id.generation} << 32));
    connectivity.data.put(static_cast<std::int64_t>(k));
    offsets.data.put(static_cast<std::int64_t>(k + 1));
    types.data.put(std::uint8_t{1});  // VTK_VERTEX
  }
  const bool poly = format == VtkFormat::PolyData;
  const char* type = poly ? "PolyData" : "UnstructuredGrid";
  std::uint64_t offset = 0;
  out << "<?xml version=\"1.0\"?>\n<VTKFile type=\"" << type
      << "\" version=\"1.0\" byte_order=\"LittleEndian\" header_type=\"UInt64\">\n  <" << type << ">\n";
  if (poly)
    out << "    <Piece NumberOfPoints=\"" << n << "\" NumberOfVerts=\"" << n
        << "\" NumberOfLines=\"0\" NumberOfStrips=\"0\" NumberOfPolys=\"0\">\n";
  else
    out << "    <Piece NumberOfPoints=\"" << n << "\" NumberOfCells=\"" << n << "\">\n";
  out << "      <PointData Scalars=\"radius\" Vectors=\"velocity\">\n";
  std::vector<const Array*> order;
  for (const Array* a : {&radius, &velocity, &speed, &spin, &sleeping, &handle}) {
    write_array_header(out, *a, offset, "        ");
    order.push_back(a);
  }
  out << "      </PointData>\n      <Points>\n";
  write_array_header(out, points, offset, "        ");
  order.push_back(&points);
  out << "      </Points>\n      <" << (poly ? "Verts" : "Cells") << ">\n";
  write_array_header(out, connectivity, offset, "        ");
  write_array_header(out, offsets, offset, "        ");
  order.push_back(&connectivity);
  order.push_back(&offsets);
  if (!poly) {
    write_array_header(out, types, offset, "        ");
    order.push_back(&types);
  }
  out << "      </" << (poly ? "Verts" : "Cells") << ">\n    </Piece>\n  </" << type << ">\n";
  out << "  <AppendedData encoding=\"raw\">\n   _";
  for (const Array* a : order) {
    const std::uint64_t size = a->data.bytes.size();
    out.write(reinterpret_cast<const char*>(&size), sizeof size);
    out.write(a->data.bytes.data(), static_cast<std::streamsize>(size));
  }
  out << "\n  </AppendedData>\n</VTKFile>\n";
}

VtkFrames::VtkFrames(std::string dir, VtkFormat format, std::string name)
    : dir_(std::move(dir)), name_(std::move(name)), format_(format) {
  if (name_.empty() || name_.find('/') != std::string::npos)
    throw InvalidArgument("hail: VTK frame name must be a non-empty file name without '/', got '" + name_ + "'");
  try {
    prepare_output_dir(dir_);
  } catch (const std::exception& e) {
    file_error(e.what());
  }
}

std::string VtkFrames::index_path() const { return (std::filesystem::path(dir_) / (name_ + ".pvd")).string(); }

std::string VtkFrames::write(const World& world, double time) {
  if (!std::isfinite(time)) throw InvalidArgument("hail: VTK frame time must be finite, got " + std::to_string(time));
  char file[64];
  std::snprintf(file, sizeof file, "_%06zu.%s", frames_.size(), format_ == VtkFormat::PolyData ? "vtp" : "vtu");
  const std::string file_name = name_ + file;
  const std::string path = (std::filesystem::path(dir_) / file_name).string();
  try {
    write_file_atomically(path, [&](std::ostream& out) { write_vtk_frame(out, world, format_); });
    frames_.emplace_back(time, file_name);
    write_file_atomically(index_path(), [&](std::ostream& out) {
      out << "<?xml version=\"1.0\"?>\n<VTKFile type=\"Collection\" version=\"0.1\" byte_order=\"LittleEndian\">\n"
          << "  <Collection>\n";
      char step[32];
      for (const auto& [t, f] : frames_) {
        std::snprintf(step, sizeof step, "%.9g", t);
        out << "    <DataSet timestep=\"" << step << "\" group=\"\" part=\"0\" file=\"" << f << "\"/>\n";
      }
      out << "  </Collection>\n</VTKFile>\n";
    });
  } catch (const FileError&) {
    throw;
  } catch (const std::exception& e) {
    file_error(e.what());
  }
  return path;
}

}  // namespace hail::bench
