#pragma once
// The geovoronoi command line (run.cpp), shared by the tool's main() and the Python extension's
// cli_main() (`python -m geovoronoi`): the same commands, outputs, messages and exit codes.

#include <string>
#include <vector>

namespace gvcli {

/// Runs the command line @p args (the arguments after the program's name): prints what the command
/// prints, every failure as one line on stderr, and returns the exit code (0 success, 2 usage or bad
/// input, 1 runtime failure; docs/cli.md, "Exit codes").
int run(const std::vector<std::string>& args) noexcept;
/// The same for main()'s arguments.
int run(int argc, char** argv) noexcept;

}  // namespace gvcli
