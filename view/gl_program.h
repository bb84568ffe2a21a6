#pragma once
// OpenGL 3.3 core shader programs (through libepoxy): compile, link, set uniforms. Errors (a
// shader the driver refuses) throw std::runtime_error with the driver's log.

#include <epoxy/gl.h>

#include <Eigen/Core>

namespace hail::view {

/// Links a vertex and a fragment shader; throws std::runtime_error with the log on failure.
GLuint link_program(const char* vertex_source, const char* fragment_source);

void set_uniform(GLuint program, const char* name, const Eigen::Matrix4f& m);
void set_uniform(GLuint program, const char* name, const Eigen::Vector3f& v);
void set_uniform(GLuint program, const char* name, float v);

}  // namespace hail::view
