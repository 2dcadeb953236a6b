// Ctrl-C and SIGTERM during a run: the handler only records the signal; the run loop looks at it
// after each step, so the state it stops with is a complete step and the final frame is
// consistent. A second signal cannot wait for that: it writes a run.json prepared in advance
// (saying how the run ended) with async-signal-safe calls and exits at once.
#pragma once
#include <string>

namespace clsph::app {

// Installs the handler for SIGINT and SIGTERM.
void install_interrupt_handler();
// 0 while no signal came; else the first signal's number (SIGINT, SIGTERM).
int interrupt_signal();
inline bool interrupt_requested() { return interrupt_signal() != 0; }
// "SIGINT", "SIGTERM".
const char* signal_name(int signal);

// What a second signal writes to `path` (via `path`.abort and a rename) before the process exits
// with 128 + the signal. Call from the main thread, with the handler's copy replaced atomically
// (the handler sees the old text or the new one, never half of each).
void arm_abort_record(const std::string& path, const std::string& text);
// After the run's own last run.json is written: a second signal then just exits.
void disarm_abort_record();

}  // namespace clsph::app
