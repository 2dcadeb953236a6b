// Ctrl-C during a run: the handler only sets a flag; the run loop looks at it after each step, so
// the state it stops with is a complete step and the final frame is consistent.
#pragma once

namespace clsph::app {

// Installs the SIGINT handler (one-shot: a second Ctrl-C gets the default action and kills the
// process, for a run stuck inside a long device call).
void install_interrupt_handler();
bool interrupt_requested();

}  // namespace clsph::app
