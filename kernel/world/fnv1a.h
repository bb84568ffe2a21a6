#pragma once
// FNV-1a 64 over bytes: World::state_hash (the state's fingerprint) and the snapshot checksum
// (kernel/world/snapshot_format.h) share it.

#include <cstddef>
#include <cstdint>
#include <span>

namespace hail {

inline constexpr std::uint64_t kFnvOffsetBasis = 1469598103934665603ull;

/// FNV-1a 64, continued from `h` (kFnvOffsetBasis to start).
inline std::uint64_t fnv1a(std::span<const std::byte> bytes, std::uint64_t h = kFnvOffsetBasis) {
  for (std::byte b : bytes) {
    h ^= static_cast<std::uint64_t>(b);
    h *= 1099511628211ull;
  }
  return h;
}

}  // namespace hail
