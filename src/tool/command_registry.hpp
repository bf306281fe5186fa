// railvib_tool: subcommand registry. Each domain's command file registers its
// subcommands with a static Registrar, so adding a command touches one file.
#pragma once

#include <functional>
#include <map>
#include <string>
#include <vector>

namespace railvib::tool {

/// A subcommand: receives its arguments (without the command name), returns the exit code.
using CommandFn = std::function<int(const std::vector<std::string>& args)>;

struct CommandInfo {
  std::string summary;
  CommandFn run;
};

std::map<std::string, CommandInfo>& commandRegistry();

struct Registrar {
  Registrar(const std::string& name, const std::string& summary, CommandFn fn) {
    commandRegistry()[name] = CommandInfo{summary, std::move(fn)};
  }
};

}  // namespace railvib::tool
