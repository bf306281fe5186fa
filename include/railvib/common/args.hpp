// railvib/common: command-line arguments of railvib_tool subcommands.
//
// Options are "--name value" or "--name=value"; flags are "--name". Every
// subcommand declares its options so `--help` lists them and an unknown or
// malformed option is refused before any work is done.
#pragma once

#include <map>
#include <stdexcept>
#include <string>
#include <vector>

namespace railvib {

class ArgError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

class ArgParser {
 public:
  ArgParser(std::string command, std::string summary);

  /// Declare an option taking a value; empty default means "required unless has() is checked".
  ArgParser& option(const std::string& name, const std::string& help, const std::string& default_value = "");
  /// Declare a boolean flag.
  ArgParser& flag(const std::string& name, const std::string& help);
  /// Parse; returns false if --help was asked (usage already printed to stdout).
  bool parse(const std::vector<std::string>& args);

  bool has(const std::string& name) const;
  bool isSet(const std::string& flag_name) const;
  std::string get(const std::string& name) const;
  /// A number, finite and within [lo, hi] (ArgError naming the option, the value and the range): every
  /// numeric option states its range where it is read, so no value sizes an allocation unchecked.
  double getDouble(const std::string& name, double lo, double hi) const;
  /// A whole number within [lo, hi] (ArgError otherwise).
  long getInt(const std::string& name, long lo, long hi) const;
  /// A comma-separated list of numbers, at least one, each finite and within [lo, hi] (ArgError naming
  /// the option, the item and the range otherwise).
  std::vector<double> getDoubles(const std::string& name, double lo, double hi) const;
  /// All values given to a repeatable option (e.g. --set a=b --set c=d).
  std::vector<std::string> getAll(const std::string& name) const;
  std::string usage() const;

 private:
  struct Spec {
    std::string help;
    std::string default_value;
    bool is_flag = false;
  };
  std::string command_;
  std::string summary_;
  std::vector<std::string> order_;
  std::map<std::string, Spec> specs_;
  std::multimap<std::string, std::string> values_;
};

}  // namespace railvib
