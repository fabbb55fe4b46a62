// What a benchmark report says about its run: the machine, how busy it was,
// and the command that made it.
#ifndef CHROMATAG_BENCH_RUN_INFO_H_
#define CHROMATAG_BENCH_RUN_INFO_H_

#include <string>

namespace chromatag::bench {

// The model name, and the family and model numbers that identify the core
// when a virtual machine hides the name ("AMD EPYC"), with the logical CPUs.
std::string CpuModel();

// The 1, 5 and 15 minute load averages: other work on the machine slows
// every detector alike but makes the absolute times noisier.
std::string LoadAverage();

// The command as typed (the program's file name, then its arguments), those
// with spaces quoted.
std::string CommandLine(int argc, char** argv);

}  // namespace chromatag::bench

#endif  // CHROMATAG_BENCH_RUN_INFO_H_
