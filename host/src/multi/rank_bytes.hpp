// Host arrays as bytes, for what goes between MPI ranks through Ranks::gather_text (mesh parts,
// images): each vector as its length and its elements, read back in the same order.
#pragma once
#include "clsph/error.hpp"

#include <cstdint>
#include <cstring>
#include <string>
#include <type_traits>
#include <vector>

namespace clsph::multi {

template <class T>
void put_bytes(std::string& out, const std::vector<T>& v) {
    static_assert(std::is_trivially_copyable_v<T>);
    const std::uint64_t n = v.size();
    out.append(reinterpret_cast<const char*>(&n), 8);
    out.append(reinterpret_cast<const char*>(v.data()), v.size() * sizeof(T));
}

inline void put_word(std::string& out, std::uint64_t w) { out.append(reinterpret_cast<const char*>(&w), 8); }

// Reads what put_* wrote, from `at` on; throws clsph::Error naming `what` when the bytes end early.
class ByteReader {
public:
    ByteReader(const std::string& in, const char* what) : in_(in), what_(what) {}
    bool done() const { return at_ >= in_.size(); }
    std::uint64_t word() {
        need(8);
        std::uint64_t w = 0;
        std::memcpy(&w, in_.data() + at_, 8);
        at_ += 8;
        return w;
    }
    template <class T>
    void take(std::vector<T>& v) {
        const std::uint64_t n = word();
        if ((in_.size() - at_) / sizeof(T) < n) fail();
        v.resize(static_cast<std::size_t>(n));
        std::memcpy(v.data(), in_.data() + at_, v.size() * sizeof(T));
        at_ += v.size() * sizeof(T);
    }

private:
    void need(std::size_t n) const {
        if (in_.size() - at_ < n) fail();
    }
    [[noreturn]] void fail() const { throw Error(std::string(what_) + " across ranks: a rank's part is malformed"); }
    const std::string& in_;
    const char* what_;
    std::size_t at_ = 0;
};

}  // namespace clsph::multi
