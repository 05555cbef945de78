// SPDX-License-Identifier: MIT
/// @file main.cpp
/// Entry point of the `cellrelief` command line.
#include <exception>
#include <iostream>
#include <vector>

#include <cellrelief/core/error.h>
#include <cellrelief/version.h>

#include "commands.h"

int main(int argc, char** argv) {
  CLI::App app{"cellrelief: relief representations of meshes and height maps", "cellrelief"};
  app.set_version_flag("--version", std::string("cellrelief ") + CELLRELIEF_VERSION_STRING);
  app.require_subcommand(1);
  const std::vector<cellrelief::app::Command> commands = {
      cellrelief::app::addInfoCommand(app),
      cellrelief::app::addCellsCommand(app),
      cellrelief::app::addConvertCommand(app),
      cellrelief::app::addReconstructCommand(app),
      cellrelief::app::addRenderCommand(app),
      cellrelief::app::addCompareBackendsCommand(app),
      cellrelief::app::addViewCommand(app),
      cellrelief::app::addBenchCommand(app),
      cellrelief::app::addIndirectCommand(app),
      cellrelief::app::addCompareOptimizersCommand(app),
      cellrelief::app::addPolycubeCommand(app),
      cellrelief::app::addGeoTexCommand(app),
      cellrelief::app::addDemoCommand(app),
  };

  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    return app.exit(e);
  }
  try {
    for (const auto& command : commands)
      if (command.cli->parsed()) return command.run();
  } catch (const cellrelief::Error& e) {
    std::cerr << "cellrelief: error: " << e.what() << "\n";
    return 1;
  } catch (const std::exception& e) {
    std::cerr << "cellrelief: unexpected error: " << e.what() << "\n";
    return 1;
  }
  return 0;
}
