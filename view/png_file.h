#pragma once
// PNG pictures (stb_image_write, from Debian's libstb-dev).

#include <string>
#include <vector>

namespace hail::view {

/// Writes RGB pixels (top row first) to `path`, atomically (bench::AtomicOutputFile): throws
/// std::runtime_error naming the path if it cannot, leaving a picture already there unchanged.
void write_png(const std::string& path, int width, int height, const std::vector<unsigned char>& rgb);

}  // namespace hail::view
