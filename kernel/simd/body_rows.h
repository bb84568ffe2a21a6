#pragma once
// Loads and stores of SolverBody velocities for a batch of contacts, by transposition instead
// of gathers. A SolverBody starts with two groups of four floats, {v[0..2], inv_mass} and
// {w[0..2], inv_inertia}; the contact passes want them the other way round, one register per
// float with one lane per contact. Each 4-float group of W bodies is loaded with W plain
// 16-byte loads and turned into four W-lane registers by a 4x4 transpose inside each 128-bit
// lane (unpack + shuffle); stores run the same transpose backwards. That replaces 6 (12 with
// rotation) element gathers per side of a contact: xsimd 8's AVX-512 gather is a chain of
// element inserts, and even hardware gathers cost one cache access per element.
// Pure data movement, so the passes' results are bitwise those of the gather version.
//
// Lane l of a W-lane register holds body idx[l]; for W = 8 and W = 16 the transpose's rows
// are r_j = [body j | body 4+j | body 8+j | body 12+j] (128-bit lanes), which the in-lane
// transpose turns into the lane order 0..W-1. Included only by kernel/simd/ translation units.

#include <cstdint>

#include "kernel/dispatch/simd_arch.h"
#include "kernel/solver/solver_body.h"

namespace hail {
inline namespace HAIL_SIMD_NS {

using body_batch = xsimd::batch<float, simd_arch>;
constexpr std::size_t kBodyLanes = body_batch::size;

/// Float offset in SolverBody of the group {v, inv_mass} (0) and of {w, inv_inertia} (4).
constexpr std::size_t kLinearGroup = 0;
constexpr std::size_t kAngularGroup = 4;
static_assert(offsetof(SolverBody, v) == 0 && offsetof(SolverBody, inv_mass) == 12);
static_assert(offsetof(SolverBody, w) == 16 && offsetof(SolverBody, inv_inertia) == 28);

namespace body_rows_detail {

/// In-lane 4x4 transpose of four registers (each 128-bit lane holds one 4x4 block).
template <class R, class Unpacklo, class Unpackhi, class Shuffle>
[[gnu::always_inline]] inline void transpose4(R r[4], Unpacklo unpacklo, Unpackhi unpackhi, Shuffle shuffle) {
  const R t0 = unpacklo(r[0], r[1]), t1 = unpackhi(r[0], r[1]);
  const R t2 = unpacklo(r[2], r[3]), t3 = unpackhi(r[2], r[3]);
  r[0] = shuffle.template operator()<0x44>(t0, t2);  // _MM_SHUFFLE(1, 0, 1, 0)
  r[1] = shuffle.template operator()<0xEE>(t0, t2);  // _MM_SHUFFLE(3, 2, 3, 2)
  r[2] = shuffle.template operator()<0x44>(t1, t3);
  r[3] = shuffle.template operator()<0xEE>(t1, t3);
}

inline float* group(SolverBody* body, std::size_t offset) { return reinterpret_cast<float*>(body) + offset; }

}  // namespace body_rows_detail

/// out[k] lane l = float `offset + k` of *body[l], k < 4. The bodies are named by pointer,
/// computed once per batch: slots read from the staged batch would be re-read after every
/// store to a body (the compiler cannot tell that the stores do not change them).
[[gnu::always_inline]] inline void load_body_group(SolverBody* const* body, std::size_t offset, body_batch out[4]) {
  using namespace body_rows_detail;
#if defined(HAIL_SIMD_PATH_AVX512)
  __m512 r[4];
  for (int j = 0; j < 4; ++j) {
    const __m256 lo = _mm256_insertf128_ps(_mm256_castps128_ps256(_mm_load_ps(group(body[j], offset))),
                                           _mm_load_ps(group(body[4 + j], offset)), 1);
    const __m256 hi = _mm256_insertf128_ps(_mm256_castps128_ps256(_mm_load_ps(group(body[8 + j], offset))),
                                           _mm_load_ps(group(body[12 + j], offset)), 1);
    r[j] = _mm512_insertf32x8(_mm512_castps256_ps512(lo), hi, 1);
  }
  transpose4(
      r, [](__m512 a, __m512 b) { return _mm512_unpacklo_ps(a, b); },
      [](__m512 a, __m512 b) { return _mm512_unpackhi_ps(a, b); },
      []<int S>(__m512 a, __m512 b) { return _mm512_shuffle_ps(a, b, S); });
  for (int k = 0; k < 4; ++k) out[k] = body_batch(r[k]);
#elif defined(HAIL_SIMD_PATH_AVX2)
  __m256 r[4];
  for (int j = 0; j < 4; ++j)
    r[j] = _mm256_insertf128_ps(_mm256_castps128_ps256(_mm_load_ps(group(body[j], offset))),
                                _mm_load_ps(group(body[4 + j], offset)), 1);
  transpose4(
      r, [](__m256 a, __m256 b) { return _mm256_unpacklo_ps(a, b); },
      [](__m256 a, __m256 b) { return _mm256_unpackhi_ps(a, b); },
      []<int S>(__m256 a, __m256 b) { return _mm256_shuffle_ps(a, b, S); });
  for (int k = 0; k < 4; ++k) out[k] = body_batch(r[k]);
#elif defined(HAIL_SIMD_PATH_SSE4_2)
  __m128 r[4];
  for (int j = 0; j < 4; ++j) r[j] = _mm_load_ps(group(body[j], offset));
  transpose4(
      r, [](__m128 a, __m128 b) { return _mm_unpacklo_ps(a, b); },
      [](__m128 a, __m128 b) { return _mm_unpackhi_ps(a, b); },
      []<int S>(__m128 a, __m128 b) { return _mm_shuffle_ps(a, b, S); });
  for (int k = 0; k < 4; ++k) out[k] = body_batch(r[k]);
#else
  // Reference (and any other instruction set): element by element, the same values.
  alignas(64) float lanes[4][kBodyLanes];
  for (std::size_t l = 0; l < kBodyLanes; ++l)
    for (int k = 0; k < 4; ++k) lanes[k][l] = group(body[l], offset)[k];
  for (int k = 0; k < 4; ++k) out[k] = body_batch::load_aligned(lanes[k]);
#endif
}

/// The inverse of load_body_group: float `offset + k` of *body[l] = in[k] lane l, for every
/// lane l whose body is not `skip` (the shared static body, which many lanes of a batch may
/// name and none may write; nullptr: no lane is skipped).
[[gnu::always_inline]] inline void store_body_group(SolverBody* const* body, const SolverBody* skip, std::size_t offset,
                                                    const body_batch in[4]) {
  using namespace body_rows_detail;
#if defined(HAIL_SIMD_PATH_AVX512)
  __m512 r[4] = {in[0], in[1], in[2], in[3]};
  transpose4(
      r, [](__m512 a, __m512 b) { return _mm512_unpacklo_ps(a, b); },
      [](__m512 a, __m512 b) { return _mm512_unpackhi_ps(a, b); },
      []<int S>(__m512 a, __m512 b) { return _mm512_shuffle_ps(a, b, S); });
  for (int j = 0; j < 4; ++j) {
    const __m128 q[4] = {_mm512_extractf32x4_ps(r[j], 0), _mm512_extractf32x4_ps(r[j], 1),
                         _mm512_extractf32x4_ps(r[j], 2), _mm512_extractf32x4_ps(r[j], 3)};
    for (int h = 0; h < 4; ++h)
      if (body[4 * h + j] != skip) _mm_store_ps(group(body[4 * h + j], offset), q[h]);
  }
#elif defined(HAIL_SIMD_PATH_AVX2)
  __m256 r[4] = {in[0], in[1], in[2], in[3]};
  transpose4(
      r, [](__m256 a, __m256 b) { return _mm256_unpacklo_ps(a, b); },
      [](__m256 a, __m256 b) { return _mm256_unpackhi_ps(a, b); },
      []<int S>(__m256 a, __m256 b) { return _mm256_shuffle_ps(a, b, S); });
  for (int j = 0; j < 4; ++j) {
    if (body[j] != skip) _mm_store_ps(group(body[j], offset), _mm256_castps256_ps128(r[j]));
    if (body[4 + j] != skip) _mm_store_ps(group(body[4 + j], offset), _mm256_extractf128_ps(r[j], 1));
  }
#elif defined(HAIL_SIMD_PATH_SSE4_2)
  __m128 r[4] = {in[0], in[1], in[2], in[3]};
  transpose4(
      r, [](__m128 a, __m128 b) { return _mm_unpacklo_ps(a, b); },
      [](__m128 a, __m128 b) { return _mm_unpackhi_ps(a, b); },
      []<int S>(__m128 a, __m128 b) { return _mm_shuffle_ps(a, b, S); });
  for (int j = 0; j < 4; ++j)
    if (body[j] != skip) _mm_store_ps(group(body[j], offset), r[j]);
#else
  alignas(64) float lanes[4][kBodyLanes];
  for (int k = 0; k < 4; ++k) in[k].store_aligned(lanes[k]);
  for (std::size_t l = 0; l < kBodyLanes; ++l)
    if (body[l] != skip)
      for (int k = 0; k < 4; ++k) group(body[l], offset)[k] = lanes[k][l];
#endif
}

/// SolverBody::changed_in_pass of bodies[idx[l]] in lane l (the collision pass's skip test).
inline xsimd::batch<std::int32_t, simd_arch> load_body_stamps(const SolverBody* bodies, const std::int32_t* idx) {
  using index_batch = xsimd::batch<std::int32_t, simd_arch>;
#if defined(HAIL_SIMD_PATH_AVX512) || defined(HAIL_SIMD_PATH_AVX2)
  // Hardware gathers of one int per 64-byte body.
  const auto* base = reinterpret_cast<const int*>(&bodies[0].changed_in_pass);
  constexpr int kStride = sizeof(SolverBody) / sizeof(int);
#endif
#if defined(HAIL_SIMD_PATH_AVX512)
  const __m512i slots = _mm512_mullo_epi32(_mm512_load_si512(idx), _mm512_set1_epi32(kStride));
  return index_batch(_mm512_i32gather_epi32(slots, base, 4));
#elif defined(HAIL_SIMD_PATH_AVX2)
  const __m256i slots =
      _mm256_mullo_epi32(_mm256_load_si256(reinterpret_cast<const __m256i*>(idx)), _mm256_set1_epi32(kStride));
  return index_batch(_mm256_i32gather_epi32(base, slots, 4));
#else
  alignas(64) std::int32_t lanes[kBodyLanes];
  for (std::size_t l = 0; l < kBodyLanes; ++l) lanes[l] = static_cast<std::int32_t>(bodies[idx[l]].changed_in_pass);
  return index_batch::load_aligned(lanes);
#endif
}

}  // namespace HAIL_SIMD_NS
}  // namespace hail
