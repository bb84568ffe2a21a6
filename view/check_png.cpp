// hail-view-check-png FILE.png WIDTH HEIGHT [RRGGBB:PERCENT ...]: the headless test's judge
// (view/CMakeLists.txt). Loads the picture (stb_image) and checks its size and that its pixels
// show what the renderer draws (view/renderer.h): sphere pixels (less green than red or blue),
// terrain pixels (more green than red and blue) and sky, each in a plausible share. A broken
// shader, an empty framebuffer or a camera that misses the scene fails it. Each RRGGBB:PERCENT
// (hex colour) asks that at least PERCENT % of the pixels be that colour, each channel within
// 12 of it: the debug lines' pure hues (view/debug_lines.h), which nothing else is drawn in.
// Exit status 0 when it passes.

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

#define STB_IMAGE_STATIC
#define STB_IMAGE_IMPLEMENTATION
#include <stb/stb_image.h>

int main(int argc, char** argv) {
  if (argc < 4) {
    std::fprintf(stderr, "usage: hail-view-check-png FILE.png WIDTH HEIGHT [RRGGBB:PERCENT ...]\n");
    return 2;
  }
  struct Wanted {
    int r, g, b;
    double percent;
    long count = 0;
  };
  std::vector<Wanted> wanted;
  for (int a = 4; a < argc; ++a) {
    unsigned rgb = 0;
    double percent = 0;
    if (std::sscanf(argv[a], "%6x:%lf", &rgb, &percent) != 2) {
      std::fprintf(stderr, "check-png: '%s' is not RRGGBB:PERCENT\n", argv[a]);
      return 2;
    }
    wanted.push_back({int(rgb >> 16), int((rgb >> 8) & 255), int(rgb & 255), percent});
  }
  int width = 0, height = 0, channels = 0;
  unsigned char* pixels = stbi_load(argv[1], &width, &height, &channels, 3);
  if (!pixels) {
    std::fprintf(stderr, "check-png: cannot read '%s': %s\n", argv[1], stbi_failure_reason());
    return 1;
  }
  const int want_w = std::atoi(argv[2]), want_h = std::atoi(argv[3]);
  long sphere = 0, terrain = 0, other = 0;
  for (long k = 0; k < long(width) * height; ++k) {
    const int r = pixels[3 * k], g = pixels[3 * k + 1], b = pixels[3 * k + 2];
    for (Wanted& w : wanted)
      if (std::abs(r - w.r) <= 12 && std::abs(g - w.g) <= 12 && std::abs(b - w.b) <= 12) ++w.count;
    if (g * 10 < std::max(r, b) * 8)
      ++sphere;
    else if (g * 10 > r * 12 && g * 10 > b * 12)
      ++terrain;
    else
      ++other;
  }
  stbi_image_free(pixels);
  const double total = double(width) * height;
  const double s = sphere / total, t = terrain / total;
  std::printf("check-png: %s %dx%d: spheres %.1f%%, terrain %.1f%%, other (sky, planes, panel) %.1f%%\n", argv[1],
              width, height, 100 * s, 100 * t, 100.0 * other / total);
  bool ok = true;
  if (width != want_w || height != want_h) {
    std::fprintf(stderr, "check-png: the picture is %dx%d, not %dx%d\n", width, height, want_w, want_h);
    ok = false;
  }
  // terrain-rain after a few dozen steps, framed from above: the terrain fills a large part,
  // the spheres a visible but smaller one.
  if (!(s >= 0.005 && s <= 0.6))
    std::fprintf(stderr, "check-png: sphere pixels %.2f%% not in [0.5%%, 60%%]\n", 100 * s), ok = false;
  if (!(t >= 0.10 && t <= 0.95))
    std::fprintf(stderr, "check-png: terrain pixels %.2f%% not in [10%%, 95%%]\n", 100 * t), ok = false;
  for (const Wanted& w : wanted) {
    const double share = 100.0 * double(w.count) / total;
    std::printf("check-png: colour %02x%02x%02x: %.2f%% of the pixels\n", w.r, w.g, w.b, share);
    if (!(share >= w.percent))
      std::fprintf(stderr, "check-png: colour %02x%02x%02x on %.2f%% of the pixels, below %.2f%%\n", w.r, w.g, w.b,
                   share, w.percent),
          ok = false;
  }
  return ok ? 0 : 1;
}
