// Dealing a node's devices to its ranks, and the per-rank device spec (multi/rank_devices.hpp):
// pure host logic, no MPI and no device.

#include <doctest/doctest.h>

#include <algorithm>
#include <functional>
#include <string>
#include <vector>

#include "clsph/error.hpp"
#include "multi/rank_devices.hpp"

using namespace clsph;
using namespace clsph::multi;

namespace {

using Indices = std::vector<std::size_t>;

// Two GPUs of one platform and two CPU devices of another, as list_devices() would give them.
std::vector<DeviceInfo> node() {
    auto d = [](std::size_t i, const char* platform, const char* type) {
        DeviceInfo info;
        info.index = i;
        info.platform = platform;
        info.vendor = platform;
        info.name = std::string(type) + std::to_string(i);
        info.type = type;
        return info;
    };
    return {d(0, "NVIDIA CUDA", "gpu"), d(1, "NVIDIA CUDA", "gpu"), d(2, "Portable Computing Language", "cpu"),
            d(3, "Portable Computing Language", "cpu")};
}

std::string message_of(const std::function<void()>& f) {
    try {
        f();
    } catch (const DeviceSelectionError& e) {
        return e.what();
    }
    return "(no DeviceSelectionError)";
}

}  // namespace

TEST_CASE("deal_devices: one device a rank, round-robin when the ranks outnumber the devices") {
    const Indices selected{1, 4, 6};
    CHECK(deal_devices(selected, 0, 3) == Indices{1});
    CHECK(deal_devices(selected, 1, 3) == Indices{4});
    CHECK(deal_devices(selected, 2, 3) == Indices{6});
    const Indices expected[] = {{1}, {4}, {6}, {1}, {4}, {6}, {1}};
    for (int r = 0; r < 7; ++r) CHECK(deal_devices(selected, r, 7) == expected[r]);
    CHECK(deal_devices({5}, 0, 1) == Indices{5});
    CHECK(deal_devices({5}, 3, 4) == Indices{5});
}

TEST_CASE("deal_devices: contiguous blocks, earlier ranks taking the extra, when the devices outnumber the ranks") {
    CHECK(deal_devices({0, 1, 2, 3, 4}, 0, 2) == Indices{0, 1, 2});
    CHECK(deal_devices({0, 1, 2, 3, 4}, 1, 2) == Indices{3, 4});
    CHECK(deal_devices({0, 1, 2, 3}, 0, 1) == Indices{0, 1, 2, 3});
    // Every split: each device dealt exactly once, in order, block sizes differing by at most one.
    for (std::size_t devices = 1; devices <= 9; ++devices) {
        Indices selected;
        for (std::size_t i = 0; i < devices; ++i) selected.push_back(10 + 2 * i);
        for (int ranks = 1; ranks < static_cast<int>(devices); ++ranks) {
            CAPTURE(devices);
            CAPTURE(ranks);
            Indices all;
            std::size_t smallest = devices, largest = 0, previous = devices;
            for (int r = 0; r < ranks; ++r) {
                const Indices mine = deal_devices(selected, r, ranks);
                smallest = std::min(smallest, mine.size());
                largest = std::max(largest, mine.size());
                CHECK(mine.size() <= previous);  // earlier ranks never have fewer
                previous = mine.size();
                all.insert(all.end(), mine.begin(), mine.end());
            }
            CHECK(all == selected);
            CHECK(largest - smallest <= 1);
            CHECK(smallest >= 1);
        }
    }
}

TEST_CASE("deal_devices: an empty selection or an impossible place is refused") {
    CHECK_THROWS_AS(deal_devices({}, 0, 1), DeviceSelectionError);
    CHECK_THROWS_AS(deal_devices({0}, 1, 1), Error);
    CHECK_THROWS_AS(deal_devices({0}, -1, 2), Error);
    CHECK_THROWS_AS(deal_devices({0}, 0, 0), Error);
}

TEST_CASE("per-rank spec: each rank its own clause, ranges and '*'") {
    CHECK_FALSE(is_per_rank_spec("gpu"));
    CHECK_FALSE(is_per_rank_spec("0,2,platform:pocl"));
    CHECK(is_per_rank_spec("rank0=gpu"));
    const std::string spec = "rank0=gpu; rank1-3 = platform:pocl ;*=cpu;";
    CHECK(spec_for_rank(spec, 0) == "gpu");
    CHECK(spec_for_rank(spec, 1) == "platform:pocl");
    CHECK(spec_for_rank(spec, 3) == "platform:pocl");
    CHECK(spec_for_rank(spec, 4) == "cpu");
    CHECK(spec_for_rank(spec, 1000) == "cpu");
    CHECK(spec_for_rank("RANK2=0,1", 2) == "0,1");  // the usual grammar's commas are the clause's
    CHECK(spec_for_rank("*=default", 7) == "default");
}

TEST_CASE("per-rank spec: errors name the bad clause") {
    auto error = [](const std::string& spec, int rank) { return message_of([&] { spec_for_rank(spec, rank); }); };
    CHECK(error("rank0=gpu;rank1=cpu", 2).find("no clause names rank 2") != std::string::npos);
    CHECK(error("rank0=gpu;rnk1=cpu", 0).find("'rnk1' is not a rank") != std::string::npos);
    CHECK(error("rank0=gpu;rank1", 0).find("'rank1' has no '='") != std::string::npos);
    CHECK(error("rank0=;rank1=cpu", 1).find("'rank0=' names no devices") != std::string::npos);
    CHECK(error("rank0=gpu,rank1=cpu", 0).find("has two '='") != std::string::npos);
    CHECK(error("rank0-2=gpu;rank2=cpu", 0).find("rank 2 is named twice ('rank0-2=gpu' and 'rank2=cpu')") !=
          std::string::npos);
    CHECK(error("*=gpu;*=cpu", 0).find("'*' is given twice") != std::string::npos);
    CHECK(error("rank3-1=gpu", 2).find("empty range") != std::string::npos);
    CHECK(error("rank-1=gpu", 0).find("is not a rank") != std::string::npos);
    CHECK(error("rank99999999999=gpu", 0).find("is not a rank") != std::string::npos);
    CHECK(error("0=gpu", 0).find("'0' is not a rank") != std::string::npos);
    CHECK(error(" ; ", 0).find("no clause") != std::string::npos);
    // Every message shows the grammar.
    CHECK(error("x=gpu", 0).find("rank0=gpu;rank1=cpu") != std::string::npos);
}

TEST_CASE("rank_devices: the usual spec dealt over the node, a per-rank spec as it is") {
    const auto devices = node();
    // Two ranks on the node, "all": two devices each.
    CHECK(rank_devices(devices, "all", {0, 2, 0, 2}) == Indices{0, 1});
    CHECK(rank_devices(devices, "all", {1, 2, 1, 2}) == Indices{2, 3});
    // Four ranks over two nodes (two a node), the default spec (the GPUs): one GPU each.
    CHECK(rank_devices(devices, "default", {2, 4, 0, 2}) == Indices{0});
    CHECK(rank_devices(devices, "default", {3, 4, 1, 2}) == Indices{1});
    // Three ranks, two GPUs: the third shares the first.
    CHECK(rank_devices(devices, "gpu", {2, 3, 2, 3}) == Indices{0});
    // Per-rank: by world rank, not dealt.
    CHECK(rank_devices(devices, "rank0=gpu;rank1=cpu", {0, 2, 0, 2}) == Indices{0, 1});
    CHECK(rank_devices(devices, "rank0=gpu;rank1=cpu", {1, 2, 1, 2}) == Indices{2, 3});
    CHECK(rank_devices(devices, "rank0=1;*=platform:portable", {5, 6, 1, 2}) == Indices{2, 3});
    // A clause that selects nothing names the rank.
    const std::string e = message_of([&] { rank_devices(devices, "rank0=gpu;rank1=9", {1, 2, 1, 2}); });
    CHECK(e.rfind("rank 1: ", 0) == 0);
    CHECK(e.find("no device 9") != std::string::npos);
}

TEST_CASE("rank_devices: a per-rank clause 'none' gives the rank no device; 'none' is no term of the usual spec") {
    const auto devices = node();
    CHECK(rank_devices(devices, "rank0=gpu;rank1=none", {1, 2, 1, 2}).empty());
    CHECK(rank_devices(devices, "rank0=gpu;rank1=none", {0, 2, 0, 2}) == Indices{0, 1});
    CHECK(rank_devices(devices, "rank0=0;*=none", {3, 4, 1, 2}).empty());
    CHECK_THROWS_AS(rank_devices(devices, "none", {0, 2, 0, 2}), DeviceSelectionError);
}
