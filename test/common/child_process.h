// A program that a test runs: stdin from a file or a descriptor, stdout and stderr into files
// (out_base + ".out" and ".err"), killed at the end of the test if it still runs.
#pragma once

#include <signal.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <fcntl.h>
#include <string>
#include <vector>

#include "test_files.h"

extern char** environ;

namespace wmra {
namespace test {

// argv: the program, then its options
inline std::vector<std::string> argv_of(const std::string& program, std::vector<std::string> options) {
  options.insert(options.begin(), program);
  return options;
}

struct ChildProcess {
  pid_t pid = 0;  // 0: not started, or ended and waited for
  std::string out_path, err_path;
  std::chrono::steady_clock::time_point started = std::chrono::steady_clock::now();

  // argv[0] is the program's path; stdin_fd >= 0 is used instead of stdin_path
  ChildProcess(std::vector<std::string> argv, const std::string& out_base, const std::string& stdin_path = "/dev/null",
               int stdin_fd = -1)
      : out_path(out_base + ".out"), err_path(out_base + ".err") {
    posix_spawn_file_actions_t files;
    posix_spawn_file_actions_init(&files);
    if (stdin_fd >= 0) {
      posix_spawn_file_actions_adddup2(&files, stdin_fd, 0);
    } else {
      posix_spawn_file_actions_addopen(&files, 0, stdin_path.c_str(), O_RDONLY, 0);
    }
    posix_spawn_file_actions_addopen(&files, 1, out_path.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
    posix_spawn_file_actions_addopen(&files, 2, err_path.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
    std::vector<char*> args;
    for (auto& a : argv) args.push_back(&a[0]);
    args.push_back(nullptr);
    if (posix_spawn(&pid, args[0], &files, nullptr, args.data(), environ) != 0) pid = 0;
    posix_spawn_file_actions_destroy(&files);
  }
  ChildProcess(const ChildProcess&) = delete;
  ChildProcess& operator=(const ChildProcess&) = delete;

  // its exit status (a signal: 128 + its number) once it has ended; with wait false, -1 while it runs
  int exit_status(bool wait) {
    int status = 0;
    if (pid <= 0 || waitpid(pid, &status, wait ? 0 : WNOHANG) != pid) return -1;
    pid = 0;
    return WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
  }
  // the same, waiting at most max_s; -1 if it still runs then
  int wait_s(double max_s) {
    const auto start = std::chrono::steady_clock::now();
    do {
      const int status = exit_status(false);
      if (status >= 0) return status;
      usleep(5000);
    } while (std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count() < max_s);
    return -1;
  }
  std::string out() const { return read_file(out_path); }
  std::string err() const { return read_file(err_path); }
  ~ChildProcess() {
    if (pid > 0) {
      kill(pid, SIGKILL);
      waitpid(pid, nullptr, 0);
    }
  }
};

}  // namespace test
}  // namespace wmra
