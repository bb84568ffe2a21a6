// libFuzzer target: the recording reader (RecordingReader, kernel/world/recording_reader.cpp) on
// arbitrary bytes, as they come and with their checksums made right (tests/fuzz/recording_harness.h).
// A bad recording must end in InvalidArgument, never a crash, a hang or a sanitizer report; one
// the reader accepts must write back to the same bytes. Seeds: tests/fuzz/corpus/recording/,
// small recordings written by tests/test_recording.cpp ("[.write-recording-corpus]").

#include <cstdint>
#include <cstdlib>

#include "recording_harness.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace hail::fuzz;
  const std::span<const std::byte> raw(reinterpret_cast<const std::byte*>(data), size);
  const std::vector<std::byte> fixed = with_right_checksums(raw);
  for (std::span<const std::byte> bytes : {raw, std::span<const std::byte>(fixed)})
    if (read_and_compare(bytes) == RecordingOutcome::Misread) std::abort();
  return 0;
}
