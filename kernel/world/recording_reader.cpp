// Recordings read (kernel/world/recording_format.h). The constructor checks everything but the
// frames' contents: the header (magic, version, flags, checksum, each field's domain) and the
// size of what follows, which must be whole frames and the end marker counting them (a run
// killed mid-way leaves a file without one: "truncated"). frame(k) checks that frame's checksum.
// Nothing is allocated for a count the bytes cannot hold.

#include <cmath>
#include <cstring>

#include "kernel/files/regular_file.h"
#include "kernel/world/recording_format.h"
#include "kernel/world/world_checks.h"

namespace hail {
namespace {

constexpr const char* kFormat = "recording";

[[noreturn]] void refuse(const std::string& problem) { throw InvalidArgument("hail: recording: " + problem); }

RecordingHeader parse_payload(std::span<const std::byte> bytes, bool velocities) {
  snapshot::Reader r(bytes, "header", kFormat);
  RecordingHeader h;
  h.velocities = velocities;
  const auto name_bytes = r.count("the scene name's length", 1);
  if (name_bytes > kRecordingMaxSceneName)
    r.refuse("the scene name's length " + std::to_string(name_bytes) + " is over kRecordingMaxSceneName");
  const std::span<const std::byte> name = r.take(name_bytes, "the scene name");
  h.scene.assign(reinterpret_cast<const char*>(name.data()), name.size());
  h.has_terrain = r.flag("has terrain");
  h.terrain_hash = r.value<std::uint64_t>("the terrain hash");
  if (!h.has_terrain && h.terrain_hash != 0) r.refuse("a terrain hash without a terrain");
  h.dt = r.value<float>("dt");
  if (!(std::isfinite(h.dt) && h.dt > 0.0f)) r.refuse("dt " + checks::number(h.dt) + " is not finite and > 0");
  h.every = r.value<std::uint32_t>("every");
  if (h.every < 1) r.refuse("every is 0 (steps between frames must be >= 1)");
  const std::size_t n = r.count("the sphere count", recording::kHeaderBytesPerSphere);
  h.radii.resize(n);
  for (float& radius : h.radii) {
    radius = r.value<float>("a radius");
    if (!(std::isfinite(radius) && radius > 0.0f))
      r.refuse("radius " + checks::number(radius) + " is not finite and > 0");
  }
  h.handles.resize(n);
  for (SphereId& id : h.handles)
    id.index = r.value<std::uint32_t>("a handle"), id.generation = r.value<std::uint32_t>("a handle");
  r.finish();
  return h;
}

}  // namespace

RecordingReader::RecordingReader(std::vector<std::byte> bytes) : bytes_(std::move(bytes)) { parse(bytes_.size()); }

RecordingReader RecordingReader::open_file(const std::string& path) {
  RecordingReader reader;
  reader.path_ = path;
  // A FIFO, a device or a folder is refused before it is opened (kernel/files/); the size the
  // file had then bounds every frame read (parse checks the frames against it).
  const std::uint64_t size = files::regular_file_size(path, "recording: ", "a recording file");
  reader.file_.open(path, std::ios::binary);
  if (!reader.file_) throw FileError("hail: recording: cannot open '" + path + "'");
  try {
    reader.parse(size);
  } catch (const InvalidArgument& e) {
    throw InvalidArgument(std::string(e.what()) + " (file '" + path + "')");
  }
  return reader;
}

void RecordingReader::read_at(std::uint64_t offset, std::span<std::byte> out) const {
  if (out.empty()) return;  // (an empty header payload: memcpy from an empty vector's null data is undefined)
  if (!file_.is_open()) {
    std::memcpy(out.data(), bytes_.data() + offset, out.size());  // parse checked the range
    return;
  }
  file_.clear();
  file_.seekg(static_cast<std::streamoff>(offset));
  file_.read(reinterpret_cast<char*>(out.data()), static_cast<std::streamsize>(out.size()));
  if (!file_)
    throw FileError("hail: recording: cannot read " + std::to_string(out.size()) + " bytes at " +
                    std::to_string(offset) + " of '" + path_ + "'");
}

void RecordingReader::parse(std::uint64_t total) {
  std::byte fixed[recording::kHeaderBytes];
  if (total < recording::kHeaderBytes)
    refuse("truncated: " + std::to_string(total) + " bytes, shorter than the " +
           std::to_string(recording::kHeaderBytes) + "-byte header");
  read_at(0, fixed);
  snapshot::Reader r(fixed, "header", kFormat);
  if (std::memcmp(r.take(8, "the magic").data(), kRecordingMagic, 8) != 0)
    refuse("not a hail recording (the first 8 bytes are not \"HAILRECD\")");
  const auto version = r.value<std::uint32_t>("the version");
  if (version == 0 || version > kRecordingVersion)
    refuse("version " + std::to_string(version) +
           (version == 0 ? " is not a version" : " is newer than this hail reads") + " (it reads version " +
           std::to_string(kRecordingVersion) + ")");
  const auto flags = r.value<std::uint32_t>("the flags");
  if ((flags & ~recording::kFlagVelocities) != 0) refuse("unknown flags " + std::to_string(flags));
  const auto payload_bytes = r.value<std::uint64_t>("the header length");
  const auto checksum = r.value<std::uint64_t>("the header checksum");
  if (payload_bytes > total - recording::kHeaderBytes)
    refuse("truncated: the header says " + std::to_string(payload_bytes) + " bytes follow it, the file has " +
           std::to_string(total - recording::kHeaderBytes));
  std::vector<std::byte> payload(static_cast<std::size_t>(payload_bytes));
  read_at(recording::kHeaderBytes, payload);
  checksum_basis_ = version == 1 ? kLegacyFnvOffsetBasis : kFnvOffsetBasis;
  if (fnv1a(payload, checksum_basis_) != checksum) refuse("corrupt: the header's checksum does not match its bytes");
  header_ = parse_payload(payload, (flags & recording::kFlagVelocities) != 0);

  frames_at_ = recording::kHeaderBytes + payload_bytes;
  const std::uint64_t rest = total - frames_at_;
  const std::uint64_t frame_bytes = recording::frame_bytes(header_.handles.size(), header_.velocities);
  if (rest < recording::kEndBytes)
    refuse("truncated: no end marker after " + std::to_string(rest) + " bytes of frames");
  std::byte end[recording::kEndBytes];
  read_at(total - recording::kEndBytes, end);
  snapshot::Reader e(end, "end marker", kFormat);
  if (std::memcmp(e.take(8, "the end marker").data(), kRecordingEndMagic, 8) != 0)
    refuse(
        "truncated: no end marker (\"HAILEND.\") in the last 16 bytes: the run that wrote it did not finish, or "
        "the file was cut");
  const auto counted = e.value<std::uint64_t>("the frame count");
  const std::uint64_t frames_bytes = rest - recording::kEndBytes;
  if (frames_bytes % frame_bytes != 0 || frames_bytes / frame_bytes != counted)
    refuse("truncated or corrupt: the end marker counts " + std::to_string(counted) + " frames of " +
           std::to_string(frame_bytes) + " bytes, there are " + std::to_string(frames_bytes) + " bytes of frames");
  frame_bytes_ = static_cast<std::size_t>(frame_bytes);
  frame_count_ = static_cast<std::size_t>(counted);
}

void RecordingReader::read_frame(std::size_t k, RecordingFrame& frame) const {
  if (k >= frame_count_)
    throw InvalidArgument("hail: recording: frame " + std::to_string(k) + " of " + std::to_string(frame_count_));
  scratch_.resize(frame_bytes_);
  read_at(frames_at_ + std::uint64_t{k} * frame_bytes_, scratch_);
  const std::span<const std::byte> bytes(scratch_);
  std::uint64_t checksum = 0;
  std::memcpy(&checksum, bytes.data() + frame_bytes_ - sizeof checksum, sizeof checksum);
  if (fnv1a(bytes.first(frame_bytes_ - sizeof checksum), checksum_basis_) != checksum)
    refuse("corrupt: frame " + std::to_string(k) + "'s checksum does not match its bytes");
  const std::size_t values = 3 * header_.handles.size();
  std::memcpy(&frame.step, bytes.data(), sizeof frame.step);
  frame.positions.resize(values);
  std::memcpy(frame.positions.data(), bytes.data() + sizeof frame.step, values * sizeof(float));
  frame.velocities.resize(header_.velocities ? values : 0);
  if (header_.velocities)
    std::memcpy(frame.velocities.data(), bytes.data() + sizeof frame.step + values * sizeof(float),
                values * sizeof(float));
}

RecordingFrame RecordingReader::frame(std::size_t k) const {
  RecordingFrame frame;
  read_frame(k, frame);
  return frame;
}

}  // namespace hail
