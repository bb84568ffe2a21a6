#include "view/gl_program.h"

#include <stdexcept>
#include <string>

namespace hail::view {
namespace {

GLuint compile(GLenum kind, const char* source) {
  const GLuint shader = glCreateShader(kind);
  glShaderSource(shader, 1, &source, nullptr);
  glCompileShader(shader);
  GLint ok = 0;
  glGetShaderiv(shader, GL_COMPILE_STATUS, &ok);
  if (!ok) {
    char log[2048];
    glGetShaderInfoLog(shader, sizeof log, nullptr, log);
    throw std::runtime_error(std::string("hail-view: shader does not compile: ") + log);
  }
  return shader;
}

}  // namespace

GLuint link_program(const char* vertex_source, const char* fragment_source) {
  const GLuint vs = compile(GL_VERTEX_SHADER, vertex_source), fs = compile(GL_FRAGMENT_SHADER, fragment_source);
  const GLuint program = glCreateProgram();
  glAttachShader(program, vs);
  glAttachShader(program, fs);
  glLinkProgram(program);
  glDeleteShader(vs);
  glDeleteShader(fs);
  GLint ok = 0;
  glGetProgramiv(program, GL_LINK_STATUS, &ok);
  if (!ok) {
    char log[2048];
    glGetProgramInfoLog(program, sizeof log, nullptr, log);
    throw std::runtime_error(std::string("hail-view: shaders do not link: ") + log);
  }
  return program;
}

void set_uniform(GLuint program, const char* name, const Eigen::Matrix4f& m) {
  glUniformMatrix4fv(glGetUniformLocation(program, name), 1, GL_FALSE, m.data());  // Eigen is column-major, as GL
}
void set_uniform(GLuint program, const char* name, const Eigen::Vector3f& v) {
  glUniform3f(glGetUniformLocation(program, name), v.x(), v.y(), v.z());
}
void set_uniform(GLuint program, const char* name, float v) { glUniform1f(glGetUniformLocation(program, name), v); }

}  // namespace hail::view
