#pragma once
// How per-step scratch vectors grow. A step sizes its buffers to this step's counts (contacts,
// pairs, colours, levels, spheres); std::vector grows geometrically only when it is full:
// resize, assign and insert past capacity allocate size() + max(size(), added) (libstdc++) or
// exactly n (assign), so a buffer whose count fell below its capacity and rises again gets
// exactly the new count, and a count that rises a little every step (a pile forming, spheres
// added one per step) reallocated every step, by a few bytes each time. These grow the capacity
// to at least twice what it was, and a quarter beyond what is asked: a rising count reallocates
// O(log n) times, a steady one never (tests/allocation/).

#include <algorithm>
#include <cstddef>
#include <vector>

namespace hail {

/// Makes room for n elements: when n exceeds the capacity, the new capacity is
/// max(n + n / 4, 2 * capacity).
template <class T, class A>
void reserve_geometric(std::vector<T, A>& v, std::size_t n) {
  if (n > v.capacity()) v.reserve(std::max(n + n / 4, 2 * v.capacity()));
}

/// v.resize(n), growing geometrically (reserve_geometric).
template <class T, class A>
void resize_geometric(std::vector<T, A>& v, std::size_t n) {
  reserve_geometric(v, n);
  v.resize(n);
}

/// v.assign(n, value), growing geometrically (reserve_geometric).
template <class T, class A>
void assign_geometric(std::vector<T, A>& v, std::size_t n, const T& value) {
  reserve_geometric(v, n);
  v.assign(n, value);
}

/// Makes `lists` (one list per block of work, cleared and refilled every step) at least
/// `blocks` long. A block added when the world grows starts with the largest capacity of the
/// blocks before it, so that it does not grow from nothing through every size they went through.
template <class T, class A, class B>
void grow_block_lists(std::vector<std::vector<T, A>, B>& lists, std::size_t blocks) {
  if (lists.size() >= blocks) return;
  std::size_t capacity = 0;
  for (const std::vector<T, A>& list : lists) capacity = std::max(capacity, list.capacity());
  const std::size_t first_new = lists.size();
  lists.resize(blocks);
  for (std::size_t b = first_new; b < blocks; ++b) lists[b].reserve(capacity);
}

}  // namespace hail
