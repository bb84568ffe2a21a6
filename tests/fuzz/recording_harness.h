#pragma once
// What the recording reader's fuzzer (tests/fuzz/fuzz_recording.cpp) does with one input, shared
// with the normal build's tests (tests/test_recording.cpp replays the seed corpus through it and
// writes that corpus): RecordingReader over the bytes, then every frame read; a recording is
// either refused with InvalidArgument or read, and then RecordingWriter given its header and
// frames writes exactly its bytes back (the format has one spelling of each recording, so a
// reader that accepted something it misread shows here). Each input is tried as it is and with
// its checksums made right, so that the mutations reach the fields behind them.

#include <cstring>
#include <optional>
#include <span>
#include <sstream>
#include <vector>

#include "hail/errors.h"
#include "hail/recording.h"
#include "kernel/world/recording_format.h"

namespace hail::fuzz {

enum class RecordingOutcome { Refused, Read, Misread };

/// Reads the recording whole; Misread when it was accepted and writing it again differs.
inline RecordingOutcome read_and_compare(std::span<const std::byte> bytes) {
  std::vector<RecordingFrame> frames;
  std::optional<RecordingReader> reader;
  try {
    reader.emplace(std::vector<std::byte>(bytes.begin(), bytes.end()));
    frames.resize(reader->frame_count());
    for (std::size_t k = 0; k < frames.size(); ++k) reader->read_frame(k, frames[k]);
  } catch (const InvalidArgument&) {
    return RecordingOutcome::Refused;
  }
  // Accepted: the writer must take it back without complaint (an exception here is a finding too).
  std::ostringstream out;
  RecordingWriter writer(out, reader->header());
  for (const RecordingFrame& frame : frames) writer.write_frame(frame);
  writer.finish();
  const std::string again = out.str();
  const bool same = again.size() == bytes.size() && std::memcmp(again.data(), bytes.data(), bytes.size()) == 0;
  return same ? RecordingOutcome::Read : RecordingOutcome::Misread;
}

/// The input with the header's checksum, and each whole frame's before the end marker, made
/// right (where the header says how long it is; the frame size is taken from its sphere count
/// and flags, read where the layout puts them, and the rest left as it is if they do not fit).
inline std::vector<std::byte> with_right_checksums(std::span<const std::byte> raw) {
  std::vector<std::byte> b(raw.begin(), raw.end());
  if (b.size() < recording::kHeaderBytes) return b;
  std::uint64_t payload = 0;
  std::memcpy(&payload, b.data() + recording::kPayloadBytesAt, sizeof payload);
  if (payload > b.size() - recording::kHeaderBytes) return b;
  const std::span<const std::byte> header(b.data() + recording::kHeaderBytes, static_cast<std::size_t>(payload));
  const std::uint64_t sum = fnv1a(header);
  std::memcpy(b.data() + recording::kChecksumAt, &sum, sizeof sum);
  // The sphere count follows the name (u64 length + bytes), has terrain (u8), the terrain hash,
  // dt and every (u64 + u8 + u64 + f32 + u32).
  std::uint64_t name = 0, spheres = 0;
  if (payload < 8) return b;
  std::memcpy(&name, header.data(), sizeof name);
  if (name > payload || payload - name < 8 + 1 + 8 + 4 + 4 + 8) return b;
  std::memcpy(&spheres, header.data() + 8 + name + 1 + 8 + 4 + 4, sizeof spheres);
  std::uint32_t flags = 0;
  std::memcpy(&flags, b.data() + 12, sizeof flags);
  if (spheres > b.size()) return b;
  const std::uint64_t frame = recording::frame_bytes(spheres, (flags & recording::kFlagVelocities) != 0);
  const std::uint64_t frames_at = recording::kHeaderBytes + payload;
  for (std::uint64_t at = frames_at; at + frame + recording::kEndBytes <= b.size(); at += frame) {
    const std::span<const std::byte> body(b.data() + at, static_cast<std::size_t>(frame - 8));
    const std::uint64_t frame_sum = fnv1a(body);
    std::memcpy(b.data() + at + frame - 8, &frame_sum, sizeof frame_sum);
  }
  return b;
}

}  // namespace hail::fuzz
