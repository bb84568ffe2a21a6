#pragma once
// The text of a scene file too large to build, for timing the scene reader alone: one "list" of
// `count` small spheres, then a key the reader refuses right after the parse, so that the parse
// is nearly all the work. hail-micro times it (bench/micro/micro_scene_file.cpp); the scene-file
// tests check that its reading grows linearly (tests/test_scene_file.cpp).

#include <cstddef>
#include <string>

namespace hail::bench {

inline std::string scene_of_many_spheres(std::size_t count) {
  std::string text = R"({"format": "hail-scene", "version": 1, "spheres": [{"list": [)";
  text.reserve(text.size() + 26 * count + 40);
  for (std::size_t k = 0; k < count; ++k)
    text += k == 0 ? R"({"position": [1, 2, 3]})" : R"(, {"position": [1, 2, 3]})";
  return text + R"(]}], "refused_after_the_parse": 1})";
}

}  // namespace hail::bench
