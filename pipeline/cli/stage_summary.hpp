#pragma once
// The console summary of a stage that ran: one line per camera (or per stage) with the counts a
// range engineer checks — what came in, what was kept, what was dropped and why — then the
// warnings. Figures are rounded for reading; run.json keeps them exact.
#include <string>

#include "pipeline/io/run_log.hpp"

namespace rangecal {

/// A few lines of text ending in '\n'. With `verbose` the stage's run.json counts follow in full.
std::string stage_summary(const StageLog& log, bool verbose);

}  // namespace rangecal
