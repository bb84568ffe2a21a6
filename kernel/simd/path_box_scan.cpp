// The SIMD path-box scan of continuous collision (scan_path_boxes_simd, kernel/ccd/path_box_scan.h),
// compiled once per SIMD path (kernel/dispatch/simd_arch.h). The slots go to the caller a buffer at a time.

#include "kernel/dispatch/simd_arch.h"  // first: the path's namespace

#include "kernel/ccd/path_box_scan.h"
#include "kernel/simd/kernels.h"

namespace hail {
inline namespace HAIL_SIMD_NS {

void scan_path_boxes(const SphereSoA& s, const PathBox& box, float t0, float t1, SlotSink sink) {
  constexpr std::size_t kBuffer = 64;
  std::uint32_t found[kBuffer];
  std::size_t count = 0;
  scan_path_boxes_simd(s, box, t0, t1, [&](std::uint32_t j) {
    if (count == kBuffer) sink.fn(sink.context, found, count), count = 0;
    found[count++] = j;
  });
  if (count > 0) sink.fn(sink.context, found, count);
}

}  // namespace HAIL_SIMD_NS
}  // namespace hail
