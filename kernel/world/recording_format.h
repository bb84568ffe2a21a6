#pragma once
// The recording byte layout (docs/recording_format.md), shared by the writer
// (kernel/world/recording_writer.cpp), the reader (recording_reader.cpp) and the reader's fuzzer
// (tests/fuzz/fuzz_recording.cpp):
//
//   header   magic "HAILRECD" (8 bytes), u32 version, u32 flags (bit 0: velocities), u64 header
//            payload bytes, u64 FNV-1a 64 of the header payload
//   payload  u64 scene name bytes, the name; u8 has terrain, u64 terrain content hash; f32 dt,
//            u32 every; u64 sphere count N; N f32 radii; N handles (u32 index, u32 generation)
//   frames   each: u64 step, 3N f32 positions (x, y, z per sphere), [3N f32 velocities],
//            u64 FNV-1a 64 of the frame's bytes before it
//   end      "HAILEND." (8 bytes), u64 frame count
//
// Little-endian, no padding, values copied byte by byte (snapshot::Writer / Reader).

#include <cstddef>
#include <cstdint>

#include "hail/recording.h"
#include "kernel/world/snapshot_format.h"

namespace hail::recording {

inline constexpr std::size_t kHeaderBytes = 32;
inline constexpr std::size_t kPayloadBytesAt = 16;
inline constexpr std::size_t kChecksumAt = 24;
inline constexpr std::size_t kEndBytes = 16;
inline constexpr std::uint32_t kFlagVelocities = 1u;
/// Bytes a sphere takes in the header payload: its radius and handle.
inline constexpr std::size_t kHeaderBytesPerSphere = sizeof(float) + 2 * sizeof(std::uint32_t);

/// Bytes of one frame of `spheres` spheres: step, positions, velocities if any, checksum.
constexpr std::uint64_t frame_bytes(std::uint64_t spheres, bool velocities) {
  return sizeof(std::uint64_t) + spheres * 3 * sizeof(float) * (velocities ? 2 : 1) + sizeof(std::uint64_t);
}

}  // namespace hail::recording
