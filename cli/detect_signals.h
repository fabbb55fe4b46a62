// How `chromatag detect` ends on a signal. Ctrl-C (SIGINT), SIGTERM, SIGHUP
// (the terminal closed) or SIGQUIT (Ctrl-backslash): the first ends the
// reading, the frames under way finish and are printed, then the summary; a
// second one stops waiting for them (a stalled stream, a slow frame) and
// prints the summary at once. Either way every printed line is whole, and
// the exit code is 128 + the signal, as a shell expects.
#ifndef CHROMATAG_CLI_DETECT_SIGNALS_H_
#define CHROMATAG_CLI_DETECT_SIGNALS_H_

#include <atomic>

namespace chromatag::cli {

// Set by the handler: the first signal (stop reading), the second (stop
// waiting), and which signal it was.
extern std::atomic<bool> g_stop;
extern std::atomic<bool> g_stop_now;
extern std::atomic<int> g_signal;
// Workers inside an overlay's write, and whether the process is to end as
// soon as the last of them is done.
extern std::atomic<int> g_writing;
extern std::atomic<bool> g_end_after_writes;

// Clears the flags and catches the ending signals; from the start of the
// command, so that a signal while the detector is set up still ends with a
// summary.
void CatchEndingSignals();
// Their default actions again.
void ReleaseEndingSignals();

// Ends the process by `signal`, its default action.
void EndBy(int signal);

// Ends the process by `signal` itself, its handler reset, after the summary:
// a shell then knows the job was interrupted (a loop over files stops too).
[[noreturn]] void DieBy(int signal);

}  // namespace chromatag::cli

#endif  // CHROMATAG_CLI_DETECT_SIGNALS_H_
