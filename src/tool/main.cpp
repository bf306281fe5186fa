// railvib_tool: one command-line entry to every analysis of the core library.
#include <iostream>

#include "command_registry.hpp"
#include "railvib/common/args.hpp"
#include "railvib/common/config.hpp"
#include "railvib/common/version.hpp"
#include "railvib/soil/soil_comm.hpp"

namespace railvib::tool {
std::map<std::string, CommandInfo>& commandRegistry() {
  static std::map<std::string, CommandInfo> registry;
  return registry;
}
}  // namespace railvib::tool

namespace {
void printUsage() {
  std::cout << "usage: railvib_tool COMMAND [options]   (railvib_tool COMMAND --help for its options; "
               "railvib_tool --version)\n\ncommands:\n";
  for (const auto& [name, info] : railvib::tool::commandRegistry()) {
    std::cout << "  " << name << std::string(name.size() < 20 ? 20 - name.size() : 1, ' ') << info.summary << "\n";
  }
}
}  // namespace

int main(int argc, char** argv) {
  if (argc < 2 || std::string(argv[1]) == "--help" || std::string(argv[1]) == "-h") {
    printUsage();
    return argc < 2 ? 2 : 0;
  }
  const std::string command = argv[1];
  if (command == "--version") {
    std::cout << "railvib " << railvib::railvibVersion() << "\n";
    return 0;
  }
  auto& registry = railvib::tool::commandRegistry();
  auto it = registry.find(command);
  if (it == registry.end()) {
    std::cerr << "railvib_tool: unknown command '" << command << "'\n";
    printUsage();
    return 2;
  }
  std::vector<std::string> args(argv + 2, argv + argc);
  // Under mpirun (soil, soil-bench ranks) an error on one rank stops every rank: the others would wait
  // in the next exchange for ever.
  auto fail = [&](int code) {
    if (railvib::soil::startedByMpiLauncher()) {
      const auto world = railvib::soil::worldSoilComm();
      if (world->size() > 1) world->abort("railvib_tool " + command + " failed on this rank (above)", code);
    }
    return code;
  };
  try {
    return it->second.run(args);
  } catch (const railvib::ConfigError& e) {
    std::cerr << e.what() << "\n";
    return fail(3);
  } catch (const railvib::ArgError& e) {
    std::cerr << e.what() << "\n";
    return fail(2);
  } catch (const std::exception& e) {
    std::cerr << "railvib_tool " << command << ": error: " << e.what() << "\n";
    return fail(1);
  }
}
