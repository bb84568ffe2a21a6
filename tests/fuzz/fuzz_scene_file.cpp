// libFuzzer target: the JSON scene parser (bench/scene_file.h) on arbitrary text. A bad document
// must end in std::invalid_argument naming the field, never a crash, a hang or a sanitizer
// report. Documents asking for more than 300 of anything (spheres, heightmap vertices per side)
// are skipped so that each input builds in milliseconds; the parser's own limits on huge counts
// are tested in tests/test_scene_file.cpp. Run through scripts/fuzz.sh.

#include <cctype>
#include <cstdint>
#include <stdexcept>
#include <string_view>

#include "bench/scene_file.h"
#include "kernel/errors.h"

namespace {

/// True when the text holds an integer part above 300 (the quick way to keep worlds small).
bool asks_for_a_lot(std::string_view text) {
  long value = 0;
  bool in_number = false, after_point = false;
  for (char c : text) {
    if (std::isdigit(static_cast<unsigned char>(c))) {
      if (!after_point) value = in_number ? value * 10 + (c - '0') : c - '0';
      in_number = true;
      if (!after_point && value > 300) return true;
    } else {
      if (in_number && (c == 'e' || c == 'E')) return true;  // 1e9 and the like
      after_point = in_number && c == '.';
      in_number = false, value = 0;
    }
  }
  return false;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string_view text(reinterpret_cast<const char*>(data), size);
  if (size > 4096 || asks_for_a_lot(text)) return 0;
  try {
    (void)hail::bench::parse_scene_text(text, "fuzz.json", {}, "/nonexistent");
  } catch (const std::invalid_argument&) {  // the parser's own refusal, naming the field
  } catch (const hail::FileError&) {          // a heightmap file named in the document
  }
  return 0;
}
