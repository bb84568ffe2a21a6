#pragma once
// The heap bytes containers hold (their capacity, not their size): what World::memory_use adds
// up by part. A list of lists counts the outer array and every inner one.

#include <cstddef>
#include <vector>

#include "hail/aligned_array.h"

namespace hail {

template <class T, class A>
[[nodiscard]] std::size_t heap_bytes_of(const std::vector<T, A>& v) {
  return v.capacity() * sizeof(T);
}
template <class T, class A, class B>
[[nodiscard]] std::size_t heap_bytes_of(const std::vector<std::vector<T, A>, B>& lists) {
  std::size_t bytes = lists.capacity() * sizeof(std::vector<T, A>);
  for (const std::vector<T, A>& list : lists) bytes += heap_bytes_of(list);
  return bytes;
}
template <class T>
[[nodiscard]] std::size_t heap_bytes_of(const AlignedArray<T>& v) {
  return v.capacity() * sizeof(T);
}
/// The sum over several containers.
template <class First, class Second, class... Rest>
[[nodiscard]] std::size_t heap_bytes_of(const First& first, const Second& second, const Rest&... rest) {
  return heap_bytes_of(first) + heap_bytes_of(second, rest...);
}

}  // namespace hail
