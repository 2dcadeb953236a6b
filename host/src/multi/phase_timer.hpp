// Host wall time of a scope added to one phase's total (where the step's time goes: host_phases()).
#pragma once
#include <chrono>
#include <map>
#include <string>

namespace clsph::multi {

using PhaseTotals = std::map<std::string, double>;

class PhaseTimer {
public:
    PhaseTimer(PhaseTotals& phases, const char* name)
        : phases_(phases), name_(name), start_(std::chrono::steady_clock::now()) {}
    ~PhaseTimer() { phases_[name_] += std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count(); }
    PhaseTimer(const PhaseTimer&) = delete;
    PhaseTimer& operator=(const PhaseTimer&) = delete;

private:
    PhaseTotals& phases_;
    const char* name_;
    std::chrono::steady_clock::time_point start_;
};

}  // namespace clsph::multi
