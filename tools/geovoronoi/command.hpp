#pragma once
// A command of the geovoronoi tool: its name, a one-line summary for the overview, its help text
// (usage with defaults, the outputs it writes, an example), and what runs it. One file per command
// under commands/; main.cpp lists them.

#include <string>
#include <vector>

namespace gvcli {

struct command {
  const char* name;
  const char* summary;
  const char* help;
  int (*run)(const std::vector<std::string>& args);  ///< the arguments after the command's name
};

extern const command voronoi_command;
extern const command shape_functions_command;
extern const command cut_command;
extern const command voxelize_command;
extern const command demo_command;
extern const command backends_command;

}  // namespace gvcli
