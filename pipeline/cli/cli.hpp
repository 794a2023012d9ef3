#pragma once
// The rangecal command line (docs/cli.md). Exit codes: 0 ok; 2 bad usage or config; 3 bad or
// insufficient input data; 4 calibration failed or degenerate.
namespace rangecal {

int run_cli(int argc, char** argv);

}  // namespace rangecal
