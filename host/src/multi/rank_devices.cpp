#include "multi/rank_devices.hpp"

#include "clsph/error.hpp"

#include <algorithm>
#include <cctype>
#include <climits>
#include <optional>

namespace clsph::multi {
namespace {

std::string trim(const std::string& s) {
    const auto b = s.find_first_not_of(" \t\r\n");
    if (b == std::string::npos) return {};
    return s.substr(b, s.find_last_not_of(" \t\r\n") - b + 1);
}

// One clause of a per-rank spec: the ranks [first, last] it names (all of them for '*').
struct Clause {
    std::string text;  // as written, for errors
    bool any = false;
    int first = 0, last = 0;
    std::string spec;
};

[[noreturn]] void bad(const std::string& spec, const std::string& why) {
    throw DeviceSelectionError("per-rank device spec '" + spec + "': " + why +
                               "\n  (clauses 'rankN=SPEC', 'rankN-M=SPEC' or '*=SPEC' separated by ';', SPEC as for"
                               " --devices, e.g. 'rank0=gpu;rank1=cpu')");
}

// A non-negative int written in decimal, the whole of `s`.
std::optional<int> rank_number(const std::string& s) {
    if (s.empty() || s.size() > 9 || !std::all_of(s.begin(), s.end(), [](unsigned char c) { return std::isdigit(c); }))
        return std::nullopt;
    return std::stoi(s);
}

std::vector<Clause> parse(const std::string& spec) {
    std::vector<Clause> clauses;
    std::size_t begin = 0;
    while (begin <= spec.size()) {
        const std::size_t end = std::min(spec.find(';', begin), spec.size());
        const std::string text = trim(spec.substr(begin, end - begin));
        begin = end + 1;
        if (text.empty()) continue;  // "rank0=gpu;" and ";;" are harmless
        const auto eq = text.find('=');
        if (eq == std::string::npos) bad(spec, "'" + text + "' has no '=' (every clause is RANKS=SPEC)");
        Clause c;
        c.text = text;
        const std::string ranks = trim(text.substr(0, eq));
        c.spec = trim(text.substr(eq + 1));
        if (c.spec.empty()) bad(spec, "'" + text + "' names no devices after '='");
        if (c.spec.find('=') != std::string::npos) bad(spec, "'" + text + "' has two '=' (is a ';' missing?)");
        std::string lowered = ranks;
        for (auto& ch : lowered) ch = static_cast<char>(std::tolower(static_cast<unsigned char>(ch)));
        if (ranks == "*") {
            c.any = true;
        } else if (lowered.rfind("rank", 0) == 0) {
            const std::string digits = lowered.substr(4);
            const auto dash = digits.find('-');
            const auto first = rank_number(digits.substr(0, dash));
            const auto last = dash == std::string::npos ? first : rank_number(digits.substr(dash + 1));
            if (!first || !last) bad(spec, "'" + ranks + "' is not a rank (write rankN, rankN-M or *)");
            if (*last < *first) bad(spec, "'" + ranks + "' is an empty range of ranks");
            c.first = *first;
            c.last = *last;
        } else {
            bad(spec, "'" + ranks + "' is not a rank (write rankN, rankN-M or *)");
        }
        for (const Clause& o : clauses) {
            if (c.any && o.any) bad(spec, "'*' is given twice ('" + o.text + "' and '" + text + "')");
            if (!c.any && !o.any && c.first <= o.last && o.first <= c.last)
                bad(spec, "rank " + std::to_string(std::max(c.first, o.first)) + " is named twice ('" + o.text + "' and '" +
                              text + "')");
        }
        clauses.push_back(std::move(c));
    }
    if (clauses.empty()) bad(spec, "no clause");
    return clauses;
}

}  // namespace

std::vector<std::size_t> deal_devices(const std::vector<std::size_t>& selected, int local_rank, int local_size) {
    if (local_size < 1 || local_rank < 0 || local_rank >= local_size)
        throw Error("dealing devices to ranks: local rank " + std::to_string(local_rank) + " of " +
                    std::to_string(local_size) + " is not a place on a node");
    if (selected.empty()) throw DeviceSelectionError("dealing devices to ranks: the node's selection has no device");
    const std::size_t devices = selected.size(), ranks = static_cast<std::size_t>(local_size),
                      r = static_cast<std::size_t>(local_rank);
    if (ranks >= devices) return {selected[r % devices]};
    const std::size_t base = devices / ranks, extra = devices % ranks;
    const std::size_t first = r * base + std::min(r, extra), count = base + (r < extra ? 1 : 0);
    return {selected.begin() + static_cast<std::ptrdiff_t>(first),
            selected.begin() + static_cast<std::ptrdiff_t>(first + count)};
}

bool is_per_rank_spec(const std::string& spec) { return spec.find('=') != std::string::npos; }

std::string spec_for_rank(const std::string& spec, int rank) {
    const std::vector<Clause> clauses = parse(spec);
    const Clause* any = nullptr;
    for (const Clause& c : clauses) {
        if (c.any) any = &c;
        else if (c.first <= rank && rank <= c.last) return c.spec;
    }
    if (any) return any->spec;
    bad(spec, "no clause names rank " + std::to_string(rank) + " (add 'rank" + std::to_string(rank) + "=...' or '*=...')");
}

std::vector<std::size_t> rank_devices(const std::vector<DeviceInfo>& devices, const std::string& spec,
                                      const RankPlace& place) {
    const bool per_rank = is_per_rank_spec(spec);
    const std::string own = per_rank ? spec_for_rank(spec, place.rank) : spec;
    if (per_rank && own == "none") return {};  // the rank takes part without slabs
    std::vector<std::size_t> selected;
    try {
        selected = select_devices(devices, own);
    } catch (const DeviceSelectionError& e) {
        throw DeviceSelectionError("rank " + std::to_string(place.rank) + ": " + e.what());
    }
    if (per_rank) return selected;
    return deal_devices(selected, place.local_rank, place.local_size);
}

}  // namespace clsph::multi
