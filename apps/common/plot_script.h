// SPDX-License-Identifier: MIT
/// @file plot_script.h
/// Figures by matplotlib: a benchmark writes its CSV, then runs the small script that draws that
/// figure (apps/plots/<script>.py) with the Python the project was configured with. Where Python or
/// matplotlib is missing it says so and carries on: the CSV is the result, the picture a view of it.
#pragma once

#include <cerrno>
#include <fcntl.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <string>
#include <system_error>
#include <vector>

extern char** environ;

namespace cellrelief::app {

namespace detail {

/// Runs argv[0] with argv (no shell, so paths need no quoting); its exit status, or -1.
inline int runProgram(const std::vector<std::string>& args, bool quiet = false) {
  std::vector<char*> argv;
  for (const std::string& a : args) argv.push_back(const_cast<char*>(a.c_str()));
  argv.push_back(nullptr);
  posix_spawn_file_actions_t actions;
  posix_spawn_file_actions_init(&actions);
  if (quiet) {
    posix_spawn_file_actions_addopen(&actions, 1, "/dev/null", O_WRONLY, 0);
    posix_spawn_file_actions_addopen(&actions, 2, "/dev/null", O_WRONLY, 0);
  }
  pid_t pid = 0;
  const int spawned = posix_spawn(&pid, argv[0], &actions, nullptr, argv.data(), environ);
  posix_spawn_file_actions_destroy(&actions);
  if (spawned != 0) return -1;
  int status = 0;
  pid_t waited = 0;
  do {
    waited = waitpid(pid, &status, 0);
  } while (waited == -1 && errno == EINTR);  // a signal is no reason to leave the child unreaped
  if (waited != pid) return -1;
  return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

/// The folder of the figure scripts: $CELLRELIEF_PLOT_DIR, else the source tree's (a build tree),
/// else share/cellrelief/plots beside the installed program.
inline std::filesystem::path plotScriptDir() {
  if (const char* dir = std::getenv("CELLRELIEF_PLOT_DIR")) return dir;
#ifdef CELLRELIEF_PLOT_SCRIPTS
  if (std::filesystem::is_directory(CELLRELIEF_PLOT_SCRIPTS)) return CELLRELIEF_PLOT_SCRIPTS;
#endif
  std::error_code ec;
  const std::filesystem::path exe = std::filesystem::read_symlink("/proc/self/exe", ec);
  return ec ? std::filesystem::path() : exe.parent_path().parent_path() / "share" / "cellrelief" / "plots";
}

inline std::string plotPython() {
#ifdef CELLRELIEF_PLOT_PYTHON
  return CELLRELIEF_PLOT_PYTHON;
#else
  return "/usr/bin/python3";
#endif
}

}  // namespace detail

/// Draws `png` from `csv` with apps/plots/<script>.py; false (with a line saying why) when it
/// could not: no Python, no matplotlib, or the script failed.
inline bool drawPlot(const std::string& script, const std::filesystem::path& csv, const std::filesystem::path& png) {
  const std::string python = detail::plotPython();
  const std::filesystem::path path = detail::plotScriptDir() / (script + ".py");
  if (python.empty() || access(python.c_str(), X_OK) != 0) {
    std::printf("no plot: Python (%s) is not there; %s holds the figure's data\n", python.c_str(), csv.c_str());
    return false;
  }
  if (!std::filesystem::exists(path)) {
    std::printf("no plot: the script %s is not there (set CELLRELIEF_PLOT_DIR); %s holds the figure's data\n",
                path.c_str(), csv.c_str());
    return false;
  }
  if (detail::runProgram({python, "-c", "import matplotlib"}, true) != 0) {
    std::printf("no plot: %s has no matplotlib (Debian: python3-matplotlib); %s holds the figure's data\n",
                python.c_str(), csv.c_str());
    return false;
  }
  std::fflush(stdout);
  if (detail::runProgram({python, path.string(), csv.string(), png.string()}) != 0) {
    std::printf("no plot: %s failed on %s\n", path.c_str(), csv.c_str());
    return false;
  }
  return true;
}

}  // namespace cellrelief::app
