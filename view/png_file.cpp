#include "view/png_file.h"

#include <stdexcept>

#define STB_IMAGE_WRITE_STATIC
#define STB_IMAGE_WRITE_IMPLEMENTATION
#include <stb/stb_image_write.h>

namespace hail::view {

void write_png(const std::string& path, int width, int height, const std::vector<unsigned char>& rgb) {
  if (!stbi_write_png(path.c_str(), width, height, 3, rgb.data(), width * 3))
    throw std::runtime_error("cannot write the picture '" + path + "'");
}

}  // namespace hail::view
