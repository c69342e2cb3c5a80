// The command line of the geovoronoi tool (docs/cli.md), run by the tool's main() and by the Python
// extension's cli_main() (`python -m geovoronoi`). This file only dispatches: the commands live in
// commands/ (one file each), the backend table in backends.cpp.
//
//   geovoronoi COMMAND [options]      COMMAND: voronoi, shape-functions, cut, voxelize, demo,
//                                    backends
//   geovoronoi help [COMMAND]         geovoronoi COMMAND --help         geovoronoi --version
//
// Exit codes (errors.hpp): 0 success, 2 usage or bad input, 1 runtime failure; one line on stderr.

#include "run.hpp"

#include "arguments.hpp"
#include "command.hpp"
#include "errors.hpp"
#include "usage_error.hpp"

#include <cstdio>
#include <string>
#include <vector>

#ifndef GEOVORONOI_TOOL_VERSION
#error "GEOVORONOI_TOOL_VERSION (the CMake project version) must be defined by the build"
#endif

namespace {

using gvcli::command;
using gvcli::usage_error;

const command* const commands[] = {&gvcli::voronoi_command, &gvcli::shape_functions_command, &gvcli::cut_command,
                                   &gvcli::voxelize_command, &gvcli::demo_command,
                                   &gvcli::backends_command};

std::string command_names() {
  std::string s;
  for (const command* c : commands) s += (s.empty() ? "" : ", ") + std::string(c->name);
  return s;
}

const command& find_command(const std::string& name) {
  for (const command* c : commands)
    if (name == c->name) return *c;
  throw usage_error("unknown command '" + name + "' (" + command_names() + "; --help for usage)");
}

void overview() {
  std::printf("geovoronoi %s: geodesic Voronoi diagrams and Voronoi shape functions on voxel grids\n\n"
              "usage: geovoronoi COMMAND [options]\n\ncommands:\n",
              GEOVORONOI_TOOL_VERSION);
  for (const command* c : commands) std::printf("  %-16s %s\n", c->name, c->summary);
  std::printf("\n  geovoronoi help COMMAND, geovoronoi COMMAND --help   a command's options, defaults, outputs, example\n"
              "  geovoronoi --version                                 the version\n"
              "\nexit codes: 0 success, 2 usage or bad input, 1 runtime failure (disk full, I/O error, out of\n"
              "memory, another run replaced DIR); every failure prints one line on stderr\n"
              "example:\n  geovoronoi demo --out demo-out\n");
}

int dispatch(std::vector<std::string> args) {
  if (args.empty()) throw usage_error("missing command (" + command_names() + "; --help for usage)");
  const std::string name = args.front();
  args.erase(args.begin());
  if (name == "--version" || name == "-V") {
    std::printf("geovoronoi %s\n", GEOVORONOI_TOOL_VERSION);
    return 0;
  }
  if (name == "--help" || name == "-h" || name == "help") {
    if (args.size() > 1) throw usage_error("help takes at most one command name");
    if (args.empty()) overview();
    else std::fputs(find_command(args.front()).help, stdout);
    return 0;
  }
  const command& c = find_command(name);
  if (gvcli::wants_help(args)) {
    std::fputs(c.help, stdout);
    return 0;
  }
  return c.run(args);
}

}  // namespace

namespace gvcli {

int run(const std::vector<std::string>& args) noexcept {
  try {
    clamp_thread_count();
    return dispatch(args);
  } catch (...) {
    return report_current_exception();  // one line, exit 1 or 2 (errors.hpp)
  }
}

int run(int argc, char** argv) noexcept {
  try {
    return run(std::vector<std::string>(argv + 1, argv + argc));
  } catch (...) {  // the arguments' copy
    return report_current_exception();
  }
}

}  // namespace gvcli
