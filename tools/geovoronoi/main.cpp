// geovoronoi: the command-line tool (docs/cli.md). Everything but this entry point is the front-end
// layer (the static library geovoronoi_frontend, shared with the Python extension): run.cpp.
#include "run.hpp"

int main(int argc, char** argv) { return gvcli::run(argc, argv); }
