#include "scenes/memory_use.h"

#include <cstdio>
#include <fstream>
#include <sstream>
#include <string>

#include <unistd.h>
#if defined(__GLIBC__)
#include <malloc.h>
#endif

// GCC names the sanitizers with macros, Clang with __has_feature.
#if defined(__SANITIZE_ADDRESS__) || defined(__SANITIZE_THREAD__)
#define HAIL_BENCH_SANITIZED 1
#elif defined(__has_feature)
#if __has_feature(address_sanitizer) || __has_feature(thread_sanitizer)
#define HAIL_BENCH_SANITIZED 1
#endif
#endif

namespace hail::bench {

std::optional<std::size_t> heap_bytes_in_use() {
#if defined(HAIL_BENCH_SANITIZED)
  // The sanitizers' allocators replace malloc; glibc's counters then say nothing (0).
  return std::nullopt;
#elif defined(__GLIBC__) && (__GLIBC__ > 2 || (__GLIBC__ == 2 && __GLIBC_MINOR__ >= 33))
  const struct mallinfo2 info = mallinfo2();
  // uordblks: bytes in use in the arenas; hblkhd: bytes in blocks mmap'd on their own (large
  // arrays: most of a World's memory).
  return info.uordblks + info.hblkhd;
#else
  return std::nullopt;
#endif
}

std::optional<std::size_t> available_memory_bytes() {
  std::ifstream meminfo("/proc/meminfo");
  for (std::string line; std::getline(meminfo, line);) {
    std::istringstream fields(line);
    std::string key;
    std::size_t kb = 0;
    if (fields >> key >> kb && key == "MemAvailable:") return kb * 1024;
  }
  const long pages = sysconf(_SC_AVPHYS_PAGES), page = sysconf(_SC_PAGESIZE);
  if (pages > 0 && page > 0) return static_cast<std::size_t>(pages) * static_cast<std::size_t>(page);
  return std::nullopt;
}

std::string format_bytes(double bytes) {
  const char* units[] = {"B", "kB", "MB", "GB", "TB"};
  int u = 0;
  while (bytes >= 1000.0 && u < 4) bytes /= 1000.0, ++u;
  char text[32];
  std::snprintf(text, sizeof text,
                bytes >= 100.0 || u == 0 ? "%.0f %s"
                : bytes >= 10.0          ? "%.1f %s"
                                         : "%.2f %s",
                bytes, units[u]);
  return text;
}

double memory_limit_bytes(double gb) {
  if (gb >= 0.0) return gb * 1e9;
  const std::optional<std::size_t> available = available_memory_bytes();
  return available ? 0.8 * double(*available) : 0.0;
}

std::string describe_memory_limit(double gb, double limit_bytes) {
  if (limit_bytes <= 0.0) return gb == 0.0 ? "none (--memory-limit 0)" : "none (the memory available is unknown)";
  return format_bytes(limit_bytes) + (gb < 0.0 ? " (80% of the memory available now)" : " (--memory-limit)");
}

MemoryLimit memory_limit(double gb) {
  const double bytes = memory_limit_bytes(gb);
  return {bytes, describe_memory_limit(gb, bytes)};
}

std::string over_memory_limit(double estimate_bytes, const std::string& why, const MemoryLimit& limit) {
  return "needs about " + format_bytes(estimate_bytes) + " (" + why + "), over the memory limit of " +
         limit.description + "; --memory-limit GB sets it, 0 turns the check off";
}

}  // namespace hail::bench
