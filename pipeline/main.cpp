// rangecal command-line entry point: everything lives in pipeline/cli.cpp.
#include "pipeline/cli.hpp"

int main(int argc, char** argv) {
  return rangecal::run_cli(argc, argv);
}
