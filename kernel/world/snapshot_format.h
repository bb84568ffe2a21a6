#pragma once
// The snapshot byte layout (docs/snapshot_format.md), shared by the writer
// (kernel/world/snapshot_writer.cpp), the reader (snapshot_reader.cpp) and the reader's fuzzer
// (tests/fuzz/fuzz_snapshot.cpp):
//
//   header   magic "HAILSNAP" (8 bytes), u32 version, u32 0, u64 payload bytes, u64 FNV-1a 64
//            of the payload
//   payload  sections in a fixed order, each u32 tag (4 ASCII), u32 0, u64 length, then that
//            many bytes: WRLD (settings, step count, ...), PLNS, SPHR, CACH, EVNT
//
// Little-endian, no padding, no alignment: every value is copied byte by byte. Each list of
// fields is written and read by one function over the fields (for_each_setting,
// SphereSoA::for_each_array), so that the two sides cannot disagree.

#include <bit>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <span>
#include <string>
#include <type_traits>
#include <vector>

#include "hail/errors.h"
#include "hail/settings_table.h"
#include "hail/snapshot.h"
#include "hail/world_settings.h"
#include "kernel/world/fnv1a.h"

namespace hail {
struct MeshCollider;  // kernel/mesh/mesh_collider.h
}  // namespace hail

namespace hail::snapshot {

static_assert(std::endian::native == std::endian::little, "snapshots are written little-endian, byte for byte");

inline constexpr std::size_t kHeaderBytes = 32;
inline constexpr std::size_t kPayloadBytesAt = 16;  ///< where the header keeps the payload length
inline constexpr std::size_t kChecksumAt = 24;      ///< where the header keeps the payload's FNV-1a 64
inline constexpr std::size_t kSectionHeaderBytes = 16;
inline constexpr char kWorldTag[4] = {'W', 'R', 'L', 'D'};
inline constexpr char kPlanesTag[4] = {'P', 'L', 'N', 'S'};
inline constexpr char kSpheresTag[4] = {'S', 'P', 'H', 'R'};
inline constexpr char kCacheTag[4] = {'C', 'A', 'C', 'H'};
inline constexpr char kEventsTag[4] = {'E', 'V', 'N', 'T'};
/// Version 9, only when the world has meshes: their count and each one's mesh_hash.
inline constexpr char kMeshesTag[4] = {'M', 'E', 'S', 'H'};

using hail::fnv1a;  // kernel/world/fnv1a.h, shared with World::state_hash

/// Appends values to a byte buffer.
class Writer {
 public:
  explicit Writer(std::vector<std::byte>& out) : out_(out) {}
  template <class T>
  void value(const T& v) {
    static_assert(std::is_trivially_copyable_v<T>);
    bytes(&v, sizeof v);
  }
  void bytes(const void* data, std::size_t n) {
    const auto* p = static_cast<const std::byte*>(data);
    out_.insert(out_.end(), p, p + n);
  }
  /// Starts a section; end_section writes its length.
  void begin_section(const char (&tag)[4]) {
    bytes(tag, 4);
    value(std::uint32_t{0});
    section_at_ = out_.size();
    value(std::uint64_t{0});
  }
  void end_section() {
    const std::uint64_t length = out_.size() - section_at_ - sizeof(std::uint64_t);
    std::memcpy(out_.data() + section_at_, &length, sizeof length);
  }

 private:
  std::vector<std::byte>& out_;
  std::size_t section_at_ = 0;
};

/// Reads values from a byte range; every read past its end, and every value out of its
/// domain, throws InvalidArgument("hail: snapshot: ..."), naming what was being read (the
/// recording reader, kernel/world/recording_reader.cpp, passes format "recording").
class Reader {
 public:
  explicit Reader(std::span<const std::byte> bytes, std::string where, const char* format = "snapshot")
      : bytes_(bytes), where_(std::move(where)), format_(format) {}

  [[noreturn]] void refuse(const std::string& problem) const {
    throw InvalidArgument(std::string("hail: ") + format_ + ": " + where_ + ": " + problem);
  }
  template <class T>
  T value(const char* what) {
    static_assert(std::is_trivially_copyable_v<T>);
    T v;
    std::memcpy(&v, take(sizeof v, what).data(), sizeof v);
    return v;
  }
  /// A count of items of `item_bytes` each that must fit in what is left (so that nothing is
  /// allocated for a count the bytes cannot hold).
  std::size_t count(const char* what, std::size_t item_bytes) {
    const auto n = value<std::uint64_t>(what);
    if (item_bytes > 0 && n > left() / item_bytes)
      refuse(std::string(what) + " is " + std::to_string(n) + ", more than the " + std::to_string(left()) +
             " bytes left hold (truncated or corrupt)");
    return static_cast<std::size_t>(n);
  }
  bool flag(const char* what) {
    const auto b = value<std::uint8_t>(what);
    if (b > 1) refuse(std::string(what) + " must be 0 or 1, got " + std::to_string(b));
    return b == 1;
  }
  std::span<const std::byte> take(std::size_t n, const char* what) {
    if (n > left())
      refuse(std::string("truncated: ") + what + " needs " + std::to_string(n) + " bytes, " + std::to_string(left()) +
             " left");
    const std::span<const std::byte> part = bytes_.subspan(at_, n);
    at_ += n;
    return part;
  }
  /// The next section, which must have this tag; a Reader over its bytes.
  Reader section(const char (&tag)[4]) {
    const std::string name(tag, 4);
    const std::span<const std::byte> found = take(4, ("the tag of section " + name).c_str());
    if (std::memcmp(found.data(), tag, 4) != 0)
      refuse("expected section " + name + ", found '" + printable(found) + "'");
    if (value<std::uint32_t>("a section's reserved word") != 0) refuse("section " + name + "'s reserved word is not 0");
    const auto length = value<std::uint64_t>("a section length");
    if (length > left())
      refuse("truncated: section " + name + " says " + std::to_string(length) + " bytes, " + std::to_string(left()) +
             " left");
    return Reader(take(static_cast<std::size_t>(length), "a section"), "section " + name, format_);
  }
  /// Refuses bytes left over (a section longer than its fields: another layout).
  void finish() const {
    if (left() != 0) refuse(std::to_string(left()) + " bytes left over after its last field");
  }
  [[nodiscard]] std::size_t left() const { return bytes_.size() - at_; }

 private:
  static std::string printable(std::span<const std::byte> b) {
    std::string s;
    for (std::byte c : b) s += (c >= std::byte{32} && c < std::byte{127}) ? static_cast<char>(c) : '?';
    return s;
  }
  std::span<const std::byte> bytes_;
  std::size_t at_ = 0;
  std::string where_;
  const char* format_;
};

/// terrain_content_hash with FNV-1a started from `basis` (kLegacyFnvOffsetBasis: the hash a
/// version 4 snapshot holds).
[[nodiscard]] std::uint64_t terrain_hash(const Terrain& terrain, std::uint64_t basis);
/// FNV-1a 64 over everything that decides how spheres meet a mesh's collider: its triangles
/// (world coordinates, normals, internal edges), its BVH (nodes and triangle order, which number
/// the triangles warm starting remembers), whether it is a shell, its material and where its
/// triangles start among the world's. Equal hashes: the same mesh where it was, to a step.
[[nodiscard]] std::uint64_t mesh_hash(const MeshCollider& mesh);

/// Calls f(field, spec) for every WorldSettings field that a snapshot keeps, in the settings
/// table's order (include/hail/settings_table.h): all but threads (a restored world keeps its
/// own threads or arena; the result does not depend on them).
template <class Settings, class F>
void for_each_setting(Settings& s, F&& f) {
  hail::for_each_setting(s, [&](auto& field, const SettingSpec& spec) {
    if (spec.snapshot) f(field, spec);
  });
}

}  // namespace hail::snapshot
