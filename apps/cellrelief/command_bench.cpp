// SPDX-License-Identifier: MIT
/// @file command_bench.cpp
/// `cellrelief bench <name> [options]`: runs the benchmark program bench_<name> that sits beside
/// this executable (apps/bench: cells, relief, trace, silhouettes, backends, polycube_render, and
/// with CGAL geotex, polycube, indirection), passing the options through. The benchmarks are
/// separate programs because they link the peers they compare against (Embree, OpenVDB's level-set
/// tools, CGAL), which the command line itself does not need.
#include <algorithm>
#include <cerrno>
#include <cstring>
#include <filesystem>
#include <memory>
#include <string>
#include <vector>

#include <unistd.h>

#include <cellrelief/core/error.h>

#include "commands.h"

namespace cellrelief::app {

namespace {

struct BenchCli {
  std::string name;
  std::vector<std::string> args;
};

int runBench(const BenchCli& o) {
  const std::filesystem::path self = std::filesystem::read_symlink("/proc/self/exe");
  const std::filesystem::path program = self.parent_path() / ("bench_" + o.name);
  if (!std::filesystem::exists(program)) {
    std::vector<std::string> names;
    for (const auto& entry : std::filesystem::directory_iterator(self.parent_path())) {
      const std::string file = entry.path().filename().string();
      if (file.rfind("bench_", 0) == 0) names.push_back(file.substr(6));
    }
    std::sort(names.begin(), names.end());
    std::string built;
    for (const std::string& name : names) built += (built.empty() ? "" : ", ") + name;
    throw Error(ErrorKind::FileNotFound, program,
                "no such benchmark (built here: " + (built.empty() ? std::string("none") : built) + ")");
  }
  std::vector<std::string> words = {program.string()};
  words.insert(words.end(), o.args.begin(), o.args.end());
  std::vector<char*> argv;
  for (std::string& w : words) argv.push_back(w.data());
  argv.push_back(nullptr);
  ::execv(program.c_str(), argv.data());
  throw Error(ErrorKind::Unsupported, program, std::string("cannot run it: ") + std::strerror(errno));
}

}  // namespace

Command addBenchCommand(CLI::App& app) {
  auto* cmd = app.add_subcommand("bench", "Run a benchmark program bench_<name> (options pass through)");
  auto o = std::make_shared<BenchCli>();
  cmd->add_option("name", o->name, "cells, relief, trace, silhouettes, backends, polycube_render, geotex, polycube or indirection")->required();
  // Everything after the name goes to the benchmark as it is.
  cmd->prefix_command();
  return {cmd, [o, cmd]() {
            o->args = cmd->remaining();
            return runBench(*o);
          }};
}

}  // namespace cellrelief::app
