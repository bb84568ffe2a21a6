#include "run_program.h"

#include <spawn.h>
#include <sys/wait.h>

#include <cerrno>
#include <cstring>

extern char** environ;

namespace hail::bench {

ProgramOutcome run_program(const std::vector<std::string>& argv, const std::string& working_dir) {
  ProgramOutcome outcome;
  if (argv.empty()) return outcome.error = "no program named", outcome;
  std::vector<char*> c_argv;
  for (const std::string& a : argv)
    c_argv.push_back(const_cast<char*>(a.c_str()));  // posix_spawn's signature; not written
  c_argv.push_back(nullptr);
  posix_spawn_file_actions_t actions;
  posix_spawn_file_actions_init(&actions);
  // The child changes folder itself (glibc 2.29+, musl, macOS 10.15+): no `cd DIR &&` to quote.
  posix_spawn_file_actions_addchdir_np(&actions, working_dir.c_str());
  pid_t pid = 0;
  const int spawn_error = posix_spawnp(&pid, c_argv[0], &actions, nullptr, c_argv.data(), environ);
  posix_spawn_file_actions_destroy(&actions);
  if (spawn_error != 0) return outcome.error = argv[0] + ": " + std::strerror(spawn_error), outcome;
  int status = 0;
  while (waitpid(pid, &status, 0) < 0)
    if (errno != EINTR)
      return outcome.error = std::string("waiting for ") + argv[0] + ": " + std::strerror(errno), outcome;
  outcome.started = true;
  outcome.exit_status = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  return outcome;
}

std::string shell_quoted(const std::string& text) {
  std::string quoted = "'";
  for (const char c : text) quoted += c == '\'' ? std::string("'\\''") : std::string(1, c);
  return quoted + "'";
}

}  // namespace hail::bench
