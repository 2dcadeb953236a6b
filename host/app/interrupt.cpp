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

// The program's only global state: what a signal handler may touch.
volatile std::sig_atomic_t g_signal = 0;

// Two slots, so the main thread fills one while the handler may read the other; g_armed names the
// slot to write (0: none). Plain char arrays: the handler must not allocate.
struct AbortRecord {
    char path[4096];
    char tmp[4096];
    char* text = nullptr;  // owned (new[]), replaced only after the slot is no longer armed
    std::size_t size = 0;
};
AbortRecord g_records[2];
std::atomic<int> g_armed{0};  // 0: nothing to write; 1 or 2: g_records[g_armed - 1]
static_assert(std::atomic<int>::is_always_lock_free, "the signal handler reads g_armed");

void write_abort_record() {
    const int slot = g_armed.load();
    if (slot == 0) return;
    const AbortRecord& r = g_records[slot - 1];
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
    if (g_signal == 0) {
        g_signal = signal;
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

int interrupt_signal() { return g_signal; }

const char* signal_name(int signal) {
    switch (signal) {
        case SIGINT: return "SIGINT";
        case SIGTERM: return "SIGTERM";
        default: return "a signal";
    }
}

void arm_abort_record(const std::string& path, const std::string& text) {
    const int current = g_armed.load();
    const int slot = current == 1 ? 2 : 1;  // the slot the handler is not using
    AbortRecord& r = g_records[slot - 1];
    delete[] r.text;
    r.text = new char[text.size()];
    std::memcpy(r.text, text.data(), text.size());
    r.size = text.size();
    copy_path(r.path, path);
    copy_path(r.tmp, path + ".abort");
    g_armed.store(slot);
}

void disarm_abort_record() { g_armed.store(0); }

}  // namespace clsph::app
