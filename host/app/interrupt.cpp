#include "interrupt.hpp"

#include <csignal>
#include <signal.h>  // sigaction (POSIX)

namespace clsph::app {
namespace {

// The program's only global state: a signal handler can do nothing but set a flag of this type.
volatile std::sig_atomic_t g_interrupted = 0;

extern "C" void on_sigint(int) { g_interrupted = 1; }

}  // namespace

void install_interrupt_handler() {
    struct sigaction action {};
    action.sa_handler = on_sigint;
    sigemptyset(&action.sa_mask);
    action.sa_flags = SA_RESETHAND;  // the second Ctrl-C is not caught
    sigaction(SIGINT, &action, nullptr);
}

bool interrupt_requested() { return g_interrupted != 0; }

}  // namespace clsph::app
