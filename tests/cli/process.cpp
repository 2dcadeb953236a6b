#include "process.hpp"

#include <chrono>
#include <csignal>
#include <fcntl.h>
#include <fstream>
#include <sstream>
#include <stdexcept>
#include <sys/wait.h>
#include <thread>
#include <unistd.h>

namespace cli_test {

Process::Process(const std::string& program, const std::vector<std::string>& args, const std::string& log) {
    std::vector<std::string> argv_text{program};
    argv_text.insert(argv_text.end(), args.begin(), args.end());
    std::vector<char*> argv;
    for (auto& a : argv_text) argv.push_back(a.data());
    argv.push_back(nullptr);
    pid_ = fork();
    if (pid_ < 0) throw std::runtime_error("fork failed");
    if (pid_ == 0) {
        const int fd = open(log.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
        if (fd >= 0) {
            dup2(fd, STDOUT_FILENO);
            dup2(fd, STDERR_FILENO);
            close(fd);
        }
        execv(program.c_str(), argv.data());
        _exit(127);
    }
}

Process::~Process() {
    if (pid_ > 0) {
        kill(pid_, SIGKILL);
        waitpid(pid_, nullptr, 0);
    }
}

void Process::interrupt() {
    if (pid_ > 0) kill(pid_, SIGINT);
}

void Process::signal(int number) {
    if (pid_ > 0) kill(pid_, number);
}

int Process::wait(double timeout_s) {
    const auto deadline = std::chrono::steady_clock::now() + std::chrono::duration<double>(timeout_s);
    int status = 0;
    for (;;) {
        const pid_t r = waitpid(pid_, &status, WNOHANG);
        if (r == pid_) break;
        if (std::chrono::steady_clock::now() > deadline) {
            kill(pid_, SIGKILL);
            waitpid(pid_, nullptr, 0);
            pid_ = -1;
            return -1000;
        }
        std::this_thread::sleep_for(std::chrono::milliseconds(20));
    }
    pid_ = -1;
    if (WIFEXITED(status)) return WEXITSTATUS(status);
    return -WTERMSIG(status);
}

namespace {

int run_tool(const std::string& program, const std::vector<std::string>& args, std::string& output, double timeout_s) {
    const std::string log = std::string(CLSPH_CLI_WORK) + "/last_command.log";
    int code = 0;
    {
        Process p(program, args, log);
        code = p.wait(timeout_s);
    }
    output = read_text(log);
    return code;
}

}  // namespace

int run(const std::vector<std::string>& args, std::string& output, double timeout_s) {
    return run_tool(CLSPH_CLI, args, output, timeout_s);
}

int run_faulty(const std::vector<std::string>& args, std::string& output, double timeout_s) {
    return run_tool(CLSPH_FAULTY_CLI, args, output, timeout_s);
}

std::string read_text(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    std::ostringstream s;
    s << in.rdbuf();
    return s.str();
}

}  // namespace cli_test
