// Recordings written (kernel/world/recording_format.h): the header once, then fixed-size frames
// each with its own checksum, then the end marker. Frames are taken from a World by handle, so a
// Morton re-sort of its slots does not change which sphere is row k.

#include <cmath>
#include <ostream>

#include "hail/world.h"
#include "kernel/world/recording_format.h"
#include "kernel/world/world_checks.h"

namespace hail {
namespace {

/// The header's values out of their domain, named (the reader refuses the same).
void check_header(const RecordingHeader& h) {
  auto refuse = [](const std::string& what) { throw InvalidArgument("hail: RecordingWriter: " + what); };
  if (h.scene.size() > kRecordingMaxSceneName)
    refuse("scene name of " + std::to_string(h.scene.size()) + " bytes is longer than kRecordingMaxSceneName");
  if (!(std::isfinite(h.dt) && h.dt > 0.0f)) refuse("dt " + checks::number(h.dt) + " is not finite and > 0");
  if (h.every < 1) refuse("every is 0 (steps between frames must be >= 1)");
  if (h.radii.size() != h.handles.size())
    refuse(std::to_string(h.radii.size()) + " radii for " + std::to_string(h.handles.size()) + " handles");
  for (float r : h.radii)
    if (!(std::isfinite(r) && r > 0.0f)) refuse("radius " + checks::number(r) + " is not finite and > 0");
  if (!h.has_terrain && h.terrain_hash != 0) refuse("a terrain hash without a terrain");
}

void write_bytes(std::ostream& out, const std::vector<std::byte>& bytes) {
  out.write(reinterpret_cast<const char*>(bytes.data()), static_cast<std::streamsize>(bytes.size()));
  if (!out) throw FileError("hail: RecordingWriter: the stream failed (disk full, or closed?)");
}

/// "sphere 12/0 was removed since ..." for a stale handle.
[[noreturn]] void refuse_stale(const char* where, SphereId id, const char* since) {
  throw InvalidArgument(std::string("hail: ") + where + ": sphere " + std::to_string(id.index) + "/" +
                        std::to_string(id.generation) + " " + since);
}

}  // namespace

RecordingHeader recording_header(const World& world, std::span<const SphereId> handles, std::string scene, float dt,
                                 std::uint32_t every, bool velocities) {
  RecordingHeader h;
  h.scene = std::move(scene);
  h.has_terrain = world.terrain() != nullptr;
  h.terrain_hash = h.has_terrain ? terrain_content_hash(*world.terrain()) : 0;
  h.dt = dt;
  h.every = every;
  h.velocities = velocities;
  if (handles.empty()) handles = world.handles();
  h.handles.assign(handles.begin(), handles.end());
  const std::span<const float> radius = world.spheres().radius;
  for (const SphereId id : handles) {
    const std::int64_t slot = world.slot_of(id);
    if (slot < 0) refuse_stale("recording_header", id, "is not in the world");
    h.radii.push_back(radius[static_cast<std::size_t>(slot)]);
  }
  return h;
}

void recording_frame(const World& world, const RecordingHeader& header, std::uint64_t step, RecordingFrame& frame) {
  const std::size_t n = header.handles.size();
  frame.step = step;
  frame.positions.resize(3 * n);
  frame.velocities.resize(header.velocities ? 3 * n : 0);
  const SphereState s = world.spheres();
  for (std::size_t k = 0; k < n; ++k) {
    const SphereId id = header.handles[k];
    const std::int64_t slot = world.slot_of(id);
    if (slot < 0) refuse_stale("recording_frame", id, "was removed since the recording began");
    const auto i = static_cast<std::size_t>(slot);
    frame.positions[3 * k] = s.px[i], frame.positions[3 * k + 1] = s.py[i], frame.positions[3 * k + 2] = s.pz[i];
    if (header.velocities)
      frame.velocities[3 * k] = s.vx[i], frame.velocities[3 * k + 1] = s.vy[i], frame.velocities[3 * k + 2] = s.vz[i];
  }
}

RecordingFrame recording_frame(const World& world, const RecordingHeader& header, std::uint64_t step) {
  RecordingFrame frame;
  recording_frame(world, header, step, frame);
  return frame;
}

RecordingWriter::RecordingWriter(std::ostream& out, RecordingHeader header) : out_(out), header_(std::move(header)) {
  check_header(header_);
  std::vector<std::byte> payload;
  payload.reserve(64 + header_.scene.size() + header_.handles.size() * recording::kHeaderBytesPerSphere);
  snapshot::Writer p(payload);
  p.value(std::uint64_t{header_.scene.size()});
  p.bytes(header_.scene.data(), header_.scene.size());
  p.value(std::uint8_t{header_.has_terrain});
  p.value(header_.terrain_hash);
  p.value(header_.dt);
  p.value(header_.every);
  p.value(std::uint64_t{header_.handles.size()});
  p.bytes(header_.radii.data(), header_.radii.size() * sizeof(float));
  for (const SphereId id : header_.handles) p.value(id.index), p.value(id.generation);

  std::vector<std::byte> bytes;
  bytes.reserve(recording::kHeaderBytes + payload.size());  // (and GCC 12 warns, wrongly, without it)
  snapshot::Writer w(bytes);
  w.bytes(kRecordingMagic, sizeof kRecordingMagic);
  w.value(kRecordingVersion);
  w.value(header_.velocities ? recording::kFlagVelocities : 0u);
  w.value(std::uint64_t{payload.size()});
  w.value(fnv1a(payload));
  w.bytes(payload.data(), payload.size());
  write_bytes(out_, bytes);
}

void RecordingWriter::write_frame(const RecordingFrame& frame) {
  if (finished_) throw InvalidArgument("hail: RecordingWriter::write_frame: the recording is finished");
  const std::size_t values = 3 * header_.handles.size();
  if (frame.positions.size() != values || frame.velocities.size() != (header_.velocities ? values : 0))
    throw InvalidArgument("hail: RecordingWriter::write_frame: " + std::to_string(frame.positions.size()) +
                          " position and " + std::to_string(frame.velocities.size()) + " velocity values, expected " +
                          std::to_string(values) + (header_.velocities ? " of each" : " and none"));
  buffer_.clear();
  snapshot::Writer w(buffer_);
  w.value(frame.step);
  w.bytes(frame.positions.data(), frame.positions.size() * sizeof(float));
  w.bytes(frame.velocities.data(), frame.velocities.size() * sizeof(float));
  w.value(fnv1a(buffer_));
  write_bytes(out_, buffer_);
  ++frames_;
}

void RecordingWriter::finish() {
  if (finished_) return;
  std::vector<std::byte> end;
  end.reserve(recording::kEndBytes);  // (GCC 12 warns, wrongly, on the appends to an empty vector without it)
  snapshot::Writer w(end);
  w.bytes(kRecordingEndMagic, sizeof kRecordingEndMagic);
  w.value(frames_);
  write_bytes(out_, end);
  out_.flush();
  if (!out_) throw FileError("hail: RecordingWriter::finish: the stream failed");
  finished_ = true;
}

}  // namespace hail
