#pragma once
// Command-line options of the geovoronoi tool: --name value (or --name=value) pairs and flags.
#include "usage_error.hpp"

#include <cstdlib>
#include <map>
#include <set>
#include <string>
#include <vector>

namespace gvcli {

/// Parsed command line: --name value pairs, flags without a value, and which were given.
class arguments {
 public:
  /// `flags` take no value; every other allowed option takes exactly one. Options in `repeatable`
  /// (a subset of `with_value`) may be given several times: all() returns their values in order.
  arguments(const std::vector<std::string>& args, const std::set<std::string>& with_value,
            const std::set<std::string>& flags, const std::set<std::string>& repeatable = {}) {
    for (std::size_t i = 0; i < args.size(); ++i) {
      const std::string& a = args[i];
      std::string name = a, value;
      bool inline_value = false;
      if (a.rfind("--", 0) != 0) throw usage_error("unexpected argument '" + a + "'");
      const auto eq = a.find('=');
      if (eq != std::string::npos) name = a.substr(0, eq), value = a.substr(eq + 1), inline_value = true;
      if (flags.count(name)) {
        if (inline_value) throw usage_error("option " + name + " takes no value");
        values_[name] = "1";
      } else if (with_value.count(name)) {
        if (!inline_value) {
          if (i + 1 >= args.size() || args[i + 1].rfind("--", 0) == 0) throw usage_error("option " + name + " needs a value");
          value = args[++i];
        }
        if (values_.count(name) && !repeatable.count(name)) throw usage_error("option " + name + " given twice");
        values_[name] = value;
        all_[name].push_back(value);
      } else {
        throw usage_error("unknown option '" + name + "'");
      }
    }
  }
  bool has(const std::string& n) const { return values_.count(n) != 0; }
  /// Every value of option @p n, in the order given (empty when it was not given).
  std::vector<std::string> all(const std::string& n) const {
    const auto it = all_.find(n);
    return it == all_.end() ? std::vector<std::string>{} : it->second;
  }
  std::string get(const std::string& n, const std::string& fallback = {}) const {
    const auto it = values_.find(n);
    return it == values_.end() ? fallback : it->second;
  }
  std::string require(const std::string& n) const {
    if (!has(n)) throw usage_error("missing required option " + n);
    return get(n);
  }
  long long integer(const std::string& n, long long fallback, long long lo, long long hi) const {
    if (!has(n)) return fallback;
    const std::string s = get(n);
    char* end = nullptr;
    const long long x = std::strtoll(s.c_str(), &end, 10);
    if (s.empty() || *end != '\0' || x < lo || x > hi)
      throw usage_error("option " + n + " must be an integer from " + std::to_string(lo) + " to " + std::to_string(hi) +
                        ", got '" + s + "'");
    return x;
  }

 private:
  std::map<std::string, std::string> values_;
  std::map<std::string, std::vector<std::string>> all_;
};

/// Whether the command's arguments ask for its help (`--help` or `-h` anywhere).
inline bool wants_help(const std::vector<std::string>& args) {
  for (const auto& a : args)
    if (a == "--help" || a == "-h") return true;
  return false;
}

}  // namespace gvcli
