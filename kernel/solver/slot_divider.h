#pragma once
// slot / d for a fixed d by one multiplication and one shift instead of a division (a 64-bit
// division costs tens of cycles; the contact colouring divides twice per contact to find tiles).
// Granlund & Montgomery, "Division by invariant integers using multiplication" (1994),
// Theorem 4.2 with N = 31: for l = ceil(log2 d) and m = floor(2^(31 + l) / d) + 1,
// 2^(31 + l) < m d <= 2^(31 + l) + 2^l, so floor(n m / 2^(31 + l)) = floor(n / d) for every
// 0 <= n < 2^31. m <= 2^32 + 1, so n m < 2^64: plain 64-bit arithmetic. Slots at or above 2^31
// (never in a World in practice) fall back to the division.

#include <bit>
#include <cstdint>

namespace hail {

class SlotDivider {
 public:
  /// d >= 1.
  explicit SlotDivider(std::uint32_t d)
      : d_(d),
        shift_(31 + static_cast<unsigned>(std::bit_width(d - 1))),
        magic_((std::uint64_t{1} << shift_) / d + 1) {}

  [[nodiscard]] std::uint32_t operator()(std::uint32_t slot) const {
    if (slot >= (std::uint32_t{1} << 31)) return slot / d_;
    return static_cast<std::uint32_t>((static_cast<std::uint64_t>(slot) * magic_) >> shift_);
  }

 private:
  std::uint32_t d_;
  unsigned shift_;
  std::uint64_t magic_;
};

}  // namespace hail
