// rangecal command-line entry point: everything lives in pipeline/cli/cli.cpp.
#include "pipeline/cli/cli.hpp"

int main(int argc, char** argv) {
  return rangecal::run_cli(argc, argv);
}
