#pragma once
// Recordings: a run's sphere positions (and, if asked, velocities) every K steps, written to a
// compact, versioned, checksummed file, so that a run too large to watch live can be watched
// afterwards (`hail-bench run ... --record FILE`, `hail-view --replay FILE`). Unlike a snapshot
// (hail/snapshot.h) a recording cannot restart a run: it keeps what is drawn, not what decides
// the future. The byte layout: docs/recording_format.md.
//
// The terrain is named by its content hash (terrain_content_hash), not embedded, as in a
// snapshot. Frames have a fixed size, so a reader finds frame k without reading those before it;
// each carries its own checksum, and the file ends with a marker that counts them, so that a
// truncated file (a run killed mid-way) is told apart from a corrupt one.

#include <cstdint>
#include <fstream>
#include <iosfwd>
#include <span>
#include <string>
#include <vector>

#include "hail/sphere_soa.h"

namespace hail {

class World;

/// The first 8 bytes of every recording.
inline constexpr char kRecordingMagic[8] = {'H', 'A', 'I', 'L', 'R', 'E', 'C', 'D'};
/// The last 16 bytes start with this: the end marker, then the frame count (u64).
inline constexpr char kRecordingEndMagic[8] = {'H', 'A', 'I', 'L', 'E', 'N', 'D', '.'};
/// The format this hail writes; RecordingReader refuses a newer one, naming both.
/// Version 2 checksums with FNV-1a's published offset basis; version 1, the same layout with a
/// basis a digit short, is still read (its terrain hash, made with that basis, matches no
/// terrain_content_hash now: a viewer draws such a replay without its terrain).
inline constexpr std::uint32_t kRecordingVersion = 2;
/// Longest scene name a header holds (a path, usually).
inline constexpr std::size_t kRecordingMaxSceneName = 4096;

/// What a recording holds besides its frames.
struct RecordingHeader {
  std::string scene;               ///< the run's scene: a built-in scene's name or a scene file's path
  bool has_terrain = false;        ///< the run had a terrain
  std::uint64_t terrain_hash = 0;  ///< its terrain_content_hash (0 without one)
  float dt = 0.0f;                 ///< s per step, > 0
  std::uint32_t every = 1;         ///< steps between frames, >= 1
  bool velocities = false;         ///< frames carry velocities too
  std::vector<SphereId> handles;   ///< the spheres recorded, in the order of every frame's arrays
  std::vector<float> radii;        ///< their radii, m (one per handle, > 0 and finite)
  friend bool operator==(const RecordingHeader&, const RecordingHeader&) = default;
};

/// One frame: the state after `step` steps (0: before the first).
struct RecordingFrame {
  std::uint64_t step = 0;
  std::vector<float> positions;   ///< x, y, z per handle, in the header's order (3 floats each)
  std::vector<float> velocities;  ///< the same for velocities when RecordingHeader::velocities, else empty
  friend bool operator==(const RecordingFrame&, const RecordingFrame&) = default;
};

/// A header for the spheres `handles` of `world` (empty: every sphere it has now, in its current
/// slot order), which keep their order for the whole recording, whatever the world re-sorts.
/// terrain_hash is computed here: O(terrain size), once. Throws InvalidArgument naming a stale handle.
[[nodiscard]] RecordingHeader recording_header(const World& world, std::span<const SphereId> handles, std::string scene,
                                               float dt, std::uint32_t every, bool velocities);
/// The frame of `world` now, for `header`'s spheres. Throws InvalidArgument naming the handle if
/// one of them has been removed.
[[nodiscard]] RecordingFrame recording_frame(const World& world, const RecordingHeader& header, std::uint64_t step);
/// The same into `frame`, reusing its arrays (no allocation once they have the size).
void recording_frame(const World& world, const RecordingHeader& header, std::uint64_t step, RecordingFrame& frame);

/// Writes a recording to a binary stream: the header now, frames as they come, the end marker
/// on finish(). Throws InvalidArgument for a header out of its domain (names the field) or a
/// frame of the wrong size, FileError when the stream fails.
class RecordingWriter {
 public:
  RecordingWriter(std::ostream& out, RecordingHeader header);
  void write_frame(const RecordingFrame& frame);
  /// Writes the end marker and flushes; no frame may follow. A recording without it is read as
  /// truncated.
  void finish();
  [[nodiscard]] const RecordingHeader& header() const { return header_; }
  [[nodiscard]] std::uint64_t frames_written() const { return frames_; }

 private:
  std::ostream& out_;
  RecordingHeader header_;
  std::uint64_t frames_ = 0;
  bool finished_ = false;
  std::vector<std::byte> buffer_;  // one frame's bytes, reused
};

/// Reads a recording, from bytes or a file. The constructor reads and checks the header and the
/// file's size against it (truncation, the end marker); frame(k) reads one frame and checks its
/// checksum. Every refusal is an InvalidArgument ("hail: recording: ...") naming the problem
/// (bad magic, a version newer than kRecordingVersion, a checksum, truncation and where);
/// a file that cannot be opened or read is a FileError.
class RecordingReader {
 public:
  explicit RecordingReader(std::vector<std::byte> bytes);
  /// Keeps the file open and reads frames from it on demand (a recording may be larger than memory).
  static RecordingReader open_file(const std::string& path);

  [[nodiscard]] const RecordingHeader& header() const { return header_; }
  [[nodiscard]] std::size_t frame_count() const { return frame_count_; }
  [[nodiscard]] std::size_t frame_bytes() const { return frame_bytes_; }
  /// Frame k < frame_count(); InvalidArgument if k is out of range or its checksum is wrong.
  [[nodiscard]] RecordingFrame frame(std::size_t k) const;
  /// The same into `frame`, reusing its arrays.
  void read_frame(std::size_t k, RecordingFrame& frame) const;

  RecordingReader(RecordingReader&&) = default;
  RecordingReader& operator=(RecordingReader&&) = default;

 private:
  RecordingReader() = default;
  void read_at(std::uint64_t offset, std::span<std::byte> out) const;
  void parse(std::uint64_t total_bytes);

  std::vector<std::byte> bytes_;  // the whole recording, when read from bytes
  mutable std::ifstream file_;    // or the file it is read from
  std::string path_;
  RecordingHeader header_;
  std::uint64_t frames_at_ = 0;  // where frame 0 starts
  std::size_t frame_bytes_ = 0;
  std::size_t frame_count_ = 0;
  mutable std::vector<std::byte> scratch_;
  std::uint64_t checksum_basis_ = 0;  // FNV-1a's offset basis for the file's version
};

}  // namespace hail
