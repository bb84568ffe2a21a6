#pragma once
// soa/ holds hail's structure-of-arrays storage: aligned, SIMD-padded buffers of plain data and
// nothing of physics. Hot loops read these as spans; nothing here knows what a contact is.

#include <cstddef>
#include <cstdint>
#include <cstring>
#include <new>
#include <span>
#include <stdexcept>
#include <string>
#include <utility>

namespace hail {

/// Cache-line (64-byte) alignment of every SoA array: one SIMD load never straddles a line,
/// and two arrays written by different threads never share one.
inline constexpr std::size_t kSoaAlignment = 64;

/// A growable array of trivially copyable T on 64-byte aligned storage. Unlike std::vector it
/// never value-initialises on reserve and exposes capacity growth explicitly, so a steady-state
/// step (size <= capacity) never allocates.
template <class T>
class AlignedArray {
  static_assert(std::is_trivially_copyable_v<T>);

 public:
  using value_type = T;
  AlignedArray() = default;
  explicit AlignedArray(std::size_t n, T fill = T{}) { resize(n, fill); }
  AlignedArray(const AlignedArray& other) { *this = other; }
  AlignedArray(AlignedArray&& other) noexcept { swap(other); }
  AlignedArray& operator=(const AlignedArray& other) {
    if (this != &other) {
      AlignedArray copy;
      copy.reserve(other.size_);
      if (other.size_) std::memcpy(copy.data_, other.data_, other.size_ * sizeof(T));
      copy.size_ = other.size_;
      swap(copy);
    }
    return *this;
  }
  AlignedArray& operator=(AlignedArray&& other) noexcept {
    AlignedArray moved(std::move(other));
    swap(moved);
    return *this;
  }
  ~AlignedArray() { release(); }

  void swap(AlignedArray& other) noexcept {
    std::swap(data_, other.data_);
    std::swap(size_, other.size_);
    std::swap(capacity_, other.capacity_);
  }

  /// The most elements an array can hold: their bytes must fit a ptrdiff_t.
  static constexpr std::size_t max_size() noexcept { return std::size_t(PTRDIFF_MAX) / sizeof(T); }

  /// Grows capacity to at least n elements (allocates only when n > capacity()). Throws
  /// std::length_error for n > max_size() (n * sizeof(T) would wrap, and a small block would
  /// be taken for a huge one) and std::bad_alloc when memory runs out; either way the array is
  /// left as it was.
  void reserve(std::size_t n) {
    if (n <= capacity_) return;
    if (n > max_size())
      throw std::length_error("hail::AlignedArray: " + std::to_string(n) + " elements of " + std::to_string(sizeof(T)) +
                              " bytes are more than memory can address");
    T* fresh = static_cast<T*>(::operator new[](n * sizeof(T), std::align_val_t{kSoaAlignment}));
    if (size_) std::memcpy(fresh, data_, size_ * sizeof(T));
    release();
    data_ = fresh;
    capacity_ = n;
  }
  /// Sets the size; new elements take `fill`. Allocates only when n > capacity().
  void resize(std::size_t n, T fill = T{}) {
    if (n > capacity_) reserve(n > 2 * capacity_ ? n : 2 * capacity_);  // capacity_ <= max_size(): no wrap
    for (std::size_t i = size_; i < n; ++i) data_[i] = fill;
    size_ = n;
  }
  void clear() noexcept { size_ = 0; }

  [[nodiscard]] std::size_t size() const noexcept { return size_; }
  [[nodiscard]] std::size_t capacity() const noexcept { return capacity_; }
  [[nodiscard]] T* data() noexcept { return data_; }
  [[nodiscard]] const T* data() const noexcept { return data_; }
  T& operator[](std::size_t i) noexcept { return data_[i]; }
  const T& operator[](std::size_t i) const noexcept { return data_[i]; }
  [[nodiscard]] std::span<T> span() noexcept { return {data_, size_}; }
  [[nodiscard]] std::span<const T> span() const noexcept { return {data_, size_}; }

 private:
  void release() noexcept {
    if (data_) ::operator delete[](data_, std::align_val_t{kSoaAlignment});
    data_ = nullptr;
    capacity_ = 0;
  }
  T* data_ = nullptr;
  std::size_t size_ = 0;
  std::size_t capacity_ = 0;
};

}  // namespace hail
