#include "interrupt.hpp"

#include <csignal>
#include <cstring>
#include <fcntl.h>   // open
#include <signal.h>  // sigaction (POSIX)
#include <unistd.h>  // write, close, _exit

#include <atomic>
#include <cstdio>

namespace clsph::app {
namespace {

// What a second signal writes before the process exits, prepared in advance by the main thread:
// the handler may not allocate or format (it can run between any two instructions, inside the
// allocator too). Plain char arrays for the paths for the same reason.
struct AbortRecord {
    char path[4096];
    char tmp[4096];
    char* text = nullptr;  // owned (new[]), replaced only after the slot is no longer armed
    std::size_t size = 0;
};

// The program's only mutable global, and why it must be one: a signal handler takes no argument,
// so what it reads must be reachable without one. Only the handler and the functions below touch
// it. `signal` is the volatile sig_atomic_t the language lets a handler write; the abort record
// has two slots so the main thread fills one while the handler may read the other, and `armed`
// (lock-free, so the handler may read it) names the slot to write (0: none, else 1 or 2).
struct HandlerState {
    volatile std::sig_atomic_t signal = 0;  // 0 until a signal came; then the first one's number
    AbortRecord records[2];
    std::atomic<int> armed{0};
};
HandlerState g_handler;
static_assert(std::atomic<int>::is_always_lock_free, "the signal handler reads HandlerState::armed");

void write_abort_record() {
    const int slot = g_handler.armed.load();
    if (slot == 0) return;
    const AbortRecord& r = g_handler.records[slot - 1];
    const int fd = ::open(r.tmp, O_WRONLY | O_CREAT | O_TRUNC, 0644);
    if (fd < 0) return;
    std::size_t done = 0;
    while (done < r.size) {
        const ssize_t n = ::write(fd, r.text + done, r.size - done);
        if (n <= 0) break;
        done += static_cast<std::size_t>(n);
    }
    ::close(fd);
    if (done == r.size) ::rename(r.tmp, r.path);
}

extern "C" void on_signal(int signal) {
    if (g_handler.signal == 0) {
        g_handler.signal = signal;
        return;
    }
    // The second signal: the run cannot stop cleanly any more; say so in run.json and go.
    write_abort_record();
    ::_exit(128 + signal);
}

void copy_path(char (&dst)[4096], const std::string& src) {
    std::snprintf(dst, sizeof dst, "%s", src.c_str());
}

}  // namespace

void install_interrupt_handler() {
    struct sigaction action {};
    action.sa_handler = on_signal;
    sigemptyset(&action.sa_mask);
    sigaddset(&action.sa_mask, SIGINT);  // one handler at a time
    sigaddset(&action.sa_mask, SIGTERM);
    action.sa_flags = SA_RESTART;
    sigaction(SIGINT, &action, nullptr);
    sigaction(SIGTERM, &action, nullptr);
}

int interrupt_signal() { return g_handler.signal; }

const char* signal_name(int signal) {
    switch (signal) {
        case SIGINT: return "SIGINT";
        case SIGTERM: return "SIGTERM";
        default: return "a signal";
    }
}

void arm_abort_record(const std::string& path, const std::string& text) {
    const int current = g_handler.armed.load();
    const int slot = current == 1 ? 2 : 1;  // the slot the handler is not using
    AbortRecord& r = g_handler.records[slot - 1];
    delete[] r.text;
    r.text = new char[text.size()];
    std::memcpy(r.text, text.data(), text.size());
    r.size = text.size();
    copy_path(r.path, path);
    copy_path(r.tmp, path + ".abort");
    g_handler.armed.store(slot);
}

void disarm_abort_record() { g_handler.armed.store(0); }

}  // namespace clsph::app
