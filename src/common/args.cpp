#include "railvib/common/args.hpp"

#include <cmath>
#include <iostream>
#include <sstream>

namespace railvib {

ArgParser::ArgParser(std::string command, std::string summary)
    : command_(std::move(command)), summary_(std::move(summary)) {}

ArgParser& ArgParser::option(const std::string& name, const std::string& help, const std::string& default_value) {
  order_.push_back(name);
  specs_[name] = Spec{help, default_value, false};
  return *this;
}

ArgParser& ArgParser::flag(const std::string& name, const std::string& help) {
  order_.push_back(name);
  specs_[name] = Spec{help, "", true};
  return *this;
}

bool ArgParser::parse(const std::vector<std::string>& args) {
  for (size_t i = 0; i < args.size(); ++i) {
    const std::string& a = args[i];
    if (a == "--help" || a == "-h") {
      std::cout << usage();
      return false;
    }
    if (a.rfind("--", 0) != 0) throw ArgError(command_ + ": unexpected argument '" + a + "' (see --help)");
    std::string name = a.substr(2);
    std::string value;
    bool has_inline = false;
    const auto eq = name.find('=');
    if (eq != std::string::npos) {
      value = name.substr(eq + 1);
      name = name.substr(0, eq);
      has_inline = true;
    }
    auto it = specs_.find(name);
    if (it == specs_.end()) throw ArgError(command_ + ": unknown option --" + name + " (see --help)");
    if (it->second.is_flag) {
      if (has_inline) throw ArgError(command_ + ": --" + name + " is a flag and takes no value");
      values_.emplace(name, "true");
      continue;
    }
    if (!has_inline) {
      if (i + 1 >= args.size()) throw ArgError(command_ + ": --" + name + " needs a value");
      value = args[++i];
    }
    values_.emplace(name, value);
  }
  return true;
}

bool ArgParser::has(const std::string& name) const {
  if (values_.count(name)) return true;
  auto it = specs_.find(name);
  return it != specs_.end() && !it->second.default_value.empty();
}

bool ArgParser::isSet(const std::string& flag_name) const { return values_.count(flag_name) > 0; }

std::string ArgParser::get(const std::string& name) const {
  auto v = values_.find(name);
  if (v != values_.end()) return v->second;
  auto it = specs_.find(name);
  if (it == specs_.end()) throw std::logic_error("undeclared option --" + name);
  if (it->second.default_value.empty()) throw ArgError(command_ + ": option --" + name + " is required");
  return it->second.default_value;
}

namespace {
std::string rangeText(double lo, double hi) {
  std::ostringstream s;
  s << "[" << lo << ", " << hi << "]";
  return s.str();
}
}  // namespace

double ArgParser::getDouble(const std::string& name, double lo, double hi) const {
  const std::string s = get(name);
  size_t used = 0;
  double v = 0.0;
  try {
    v = std::stod(s, &used);
  } catch (const std::exception&) {
    used = 0;
  }
  if (used != s.size() || s.empty() || !std::isfinite(v))
    throw ArgError(command_ + ": --" + name + " = '" + s + "' is not a finite number");
  if (!(v >= lo && v <= hi))
    throw ArgError(command_ + ": --" + name + " = " + s + " is outside its range " + rangeText(lo, hi));
  return v;
}

long ArgParser::getInt(const std::string& name, long lo, long hi) const {
  const std::string s = get(name);
  size_t used = 0;
  long v = 0;
  try {
    v = std::stol(s, &used);
  } catch (const std::exception&) {
    used = 0;
  }
  if (used != s.size() || s.empty()) throw ArgError(command_ + ": --" + name + " = '" + s + "' is not a whole number");
  if (v < lo || v > hi)
    throw ArgError(command_ + ": --" + name + " = " + s + " is outside its range [" + std::to_string(lo) + ", " +
                   std::to_string(hi) + "]");
  return v;
}

std::vector<double> ArgParser::getDoubles(const std::string& name, double lo, double hi) const {
  const std::string text = get(name);
  std::vector<double> out;
  std::stringstream list(text);
  for (std::string item; std::getline(list, item, ',');) {
    size_t used = 0;
    double v = 0.0;
    try {
      v = std::stod(item, &used);
    } catch (const std::exception&) {
      used = 0;
    }
    if (item.empty() || used != item.size() || !std::isfinite(v) || v < lo || v > hi) {
      std::ostringstream why;
      why << command_ << ": --" << name << " = '" << text << "': '" << item << "' is not a number in [" << lo << ", "
          << hi << "]";
      throw ArgError(why.str());
    }
    out.push_back(v);
  }
  if (out.empty()) throw ArgError(command_ + ": --" + name + " needs at least one value");
  return out;
}

std::vector<std::string> ArgParser::getAll(const std::string& name) const {
  std::vector<std::string> out;
  auto range = values_.equal_range(name);
  for (auto it = range.first; it != range.second; ++it) out.push_back(it->second);
  return out;
}

std::string ArgParser::usage() const {
  std::ostringstream s;
  s << "usage: railvib_tool " << command_ << " [options]\n\n" << summary_ << "\n\noptions:\n";
  for (const auto& name : order_) {
    const Spec& spec = specs_.at(name);
    std::string left = "  --" + name + (spec.is_flag ? "" : " VALUE");
    s << left << std::string(left.size() < 26 ? 26 - left.size() : 1, ' ') << spec.help;
    if (!spec.default_value.empty()) s << " (default " << spec.default_value << ")";
    s << "\n";
  }
  s << "  --help                  this text\n";
  return s.str();
}

}  // namespace railvib
