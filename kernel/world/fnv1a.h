#pragma once
// FNV-1a 64 over bytes: World::state_hash (the state's fingerprint) and the snapshot checksum
// (kernel/world/snapshot_format.h) share it.

#include <cstddef>
#include <cstdint>
#include <span>

namespace hail {

/// FNV-1a 64's offset basis, as published (tests/test_snapshot.cpp checks the test vectors).
inline constexpr std::uint64_t kFnvOffsetBasis = 14695981039346656037ull;
/// The basis with its last digit lost, which snapshots up to version 4 and recordings of
/// version 1 were checksummed with: used only to read those files.
inline constexpr std::uint64_t kLegacyFnvOffsetBasis = 1469598103934665603ull;

/// FNV-1a 64, continued from `h` (kFnvOffsetBasis to start).
inline std::uint64_t fnv1a(std::span<const std::byte> bytes, std::uint64_t h = kFnvOffsetBasis) {
  for (std::byte b : bytes) {
    h ^= static_cast<std::uint64_t>(b);
    h *= 1099511628211ull;
  }
  return h;
}

}  // namespace hail
