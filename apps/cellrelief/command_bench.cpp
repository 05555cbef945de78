// SPDX-License-Identifier: MIT
/// @file command_bench.cpp
/// `cellrelief bench <name> [options]`: runs the benchmark program bench_<name> that sits beside
/// this executable (bench_cells, bench_relief, bench_trace, bench_silhouettes, bench_backends), passing
/// the options through. The benchmarks are separate programs because they link the peers they
/// compare against (Embree, OpenVDB's level-set tools), which the command line itself does not need.
#include <cerrno>
#include <cstring>
#include <filesystem>
#include <memory>
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
  if (!std::filesystem::exists(program))
    throw Error(ErrorKind::FileNotFound, program,
                "no such benchmark (built: bench_cells, bench_relief, and bench_trace, bench_silhouettes and bench_backends with Embree)");
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
  auto* cmd = app.add_subcommand("bench", "Run a benchmark: cells, relief, trace, silhouettes or backends (options pass through)");
  auto o = std::make_shared<BenchCli>();
  cmd->add_option("name", o->name, "cells, relief, trace, silhouettes or backends")->required();
  // Everything after the name goes to the benchmark as it is.
  cmd->prefix_command();
  return {cmd, [o, cmd]() {
            o->args = cmd->remaining();
            return runBench(*o);
          }};
}

}  // namespace cellrelief::app
