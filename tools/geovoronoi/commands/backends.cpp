// geovoronoi backends: which backends this binary has, whether each can run here, and the default.
#include "../backends.hpp"
#include "../command.hpp"

#include <cstdio>

namespace gvcli {

namespace {

int run(const std::vector<std::string>& args) {
  const arguments a(args, {}, {});
  for (const auto& b : backends()) {
    const std::string state = b.built() ? "built, " + b.describe() : "not built";
    std::printf("%-7s %s\n", b.name, state.c_str());
  }
  std::printf("default %s\n", default_backend().name);
  return 0;
}

}  // namespace

const command backends_command = {
    "backends", "which backends this binary has, whether each can run here, and the default",
    "usage: geovoronoi backends\n"
    "\n"
    "Lists the backends (seq, thrust, cuda): whether each is built into this binary and, for cuda,\n"
    "whether a device answers; then the default that --backend falls back to (cuda when it can\n"
    "run, else thrust on a machine with more than one hardware thread, else seq).\n"
    "\n"
    "writes: nothing (prints the list)\n"
    "\n"
    "example:\n"
    "  geovoronoi backends\n",
    run};

}  // namespace gvcli
