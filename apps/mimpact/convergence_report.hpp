#pragma once

#include "mimpact/analysis/lzb_convergence.hpp"
#include "mimpact/analysis/lzb_tolerance_study.hpp"

namespace mimpact::cli {

// The tolerance study's table and its finest velocities, to stdout.
void print_tolerance_table(const analysis::ToleranceStudy& study);

// The table of the paper's tables 2-4 and the extrapolated velocities, to stdout.
void print_convergence_table(const analysis::ConvergenceStudy& study);

}  // namespace mimpact::cli
