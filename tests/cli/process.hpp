// Running the clsph tool from a test: fork + exec (no shell, so no quoting), stdout and stderr
// into one log file, and a way to interrupt it as Ctrl-C would.
#pragma once
#include <string>
#include <sys/types.h>
#include <vector>

namespace cli_test {

class Process {
public:
    // Starts `program` with `args`; its output goes to `log`.
    Process(const std::string& program, const std::vector<std::string>& args, const std::string& log);
    ~Process();  // kills it (SIGKILL) if it is still running
    Process(const Process&) = delete;
    Process& operator=(const Process&) = delete;

    void interrupt();  // SIGINT
    void signal(int number);
    // The exit status; -N when a signal N ended it; -1000 when it outlived `timeout_s` (then killed).
    int wait(double timeout_s = 120.0);

private:
    pid_t pid_ = -1;
};

// Runs the shipped tool (CLSPH_CLI) to the end; returns the exit status (as Process::wait) and
// the output.
int run(const std::vector<std::string>& args, std::string& output, double timeout_s = 120.0);
// The same with the test build of the tool (CLSPH_FAULTY_CLI: clsph-faulty, which reads
// CLSPH_TEST_FAULT; the shipped clsph ignores it).
int run_faulty(const std::vector<std::string>& args, std::string& output, double timeout_s = 120.0);

std::string read_text(const std::string& path);

}  // namespace cli_test
