#include "view/png_file.h"

#include <ostream>
#include <stdexcept>

#include "scenes/output_file.h"

#define STB_IMAGE_WRITE_STATIC
#define STB_IMAGE_WRITE_IMPLEMENTATION
#include <stb/stb_image_write.h>

namespace hail::view {
namespace {

/// stb_image_write's sink: the encoded bytes go to the stream of an AtomicOutputFile, which
/// reports a failed write (a full disk) when it is committed.
void append_to_stream(void* stream, void* bytes, int size) {
  static_cast<std::ostream*>(stream)->write(static_cast<const char*>(bytes), size);
}

}  // namespace

void write_png(const std::string& path, int width, int height, const std::vector<unsigned char>& rgb) {
  // Through a temporary beside `path`, renamed over it once written whole: a failed write is an
  // error naming the path, and the picture already there stays as it was.
  bench::AtomicOutputFile file(path);
  if (!stbi_write_png_to_func(append_to_stream, &file.stream(), width, height, 3, rgb.data(), width * 3))
    throw std::runtime_error("cannot write the picture " + path + ": encoding it as a PNG failed");
  file.commit();
}

}  // namespace hail::view
