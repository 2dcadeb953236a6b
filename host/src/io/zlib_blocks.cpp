#include "io/zlib_blocks.hpp"

#include "clsph/error.hpp"

#include <zlib.h>

#include <algorithm>
#include <cstring>
#include <exception>
#include <thread>

namespace clsph::io {
namespace {

// zlib's level 1: frames are written while the devices step, and particle data (float mantissas)
// gains little from the slower levels.
constexpr int level = 1;

}  // namespace

std::string zlib_compress(std::uint64_t bytes, const BlockSource& source, unsigned threads) {
    const std::uint64_t blocks = (bytes + zlib_block_size - 1) / zlib_block_size;
    std::vector<std::string> compressed(blocks);
    auto work = [&](std::uint64_t first, std::uint64_t stride) {
        std::vector<unsigned char> scratch;
        for (std::uint64_t b = first; b < blocks; b += stride) {
            const std::uint64_t offset = b * zlib_block_size;
            const std::size_t length = static_cast<std::size_t>(std::min<std::uint64_t>(zlib_block_size, bytes - offset));
            const unsigned char* data = source(offset, length, scratch);
            uLongf size = compressBound(static_cast<uLong>(length));
            std::string& out = compressed[b];
            out.resize(size);
            if (compress2(reinterpret_cast<Bytef*>(out.data()), &size, data, static_cast<uLong>(length), level) != Z_OK)
                throw Error("zlib could not compress a block of " + std::to_string(length) + " bytes");
            out.resize(size);
        }
    };
    const auto workers = static_cast<unsigned>(std::min<std::uint64_t>(std::max(threads, 1u), std::max<std::uint64_t>(blocks, 1)));
    if (workers == 1) {
        work(0, 1);
    } else {
        std::vector<std::thread> pool;
        std::vector<std::exception_ptr> errors(workers);
        for (unsigned t = 0; t < workers; ++t)
            pool.emplace_back([&, t] {
                try {
                    work(t, workers);
                } catch (...) {
                    errors[t] = std::current_exception();
                }
            });
        for (auto& t : pool) t.join();
        for (const auto& e : errors)
            if (e) std::rethrow_exception(e);
    }
    std::vector<std::uint64_t> header = {blocks, zlib_block_size, bytes % zlib_block_size};
    std::size_t total = 0;
    for (const auto& c : compressed) {
        header.push_back(c.size());
        total += c.size();
    }
    std::string out(header.size() * sizeof(std::uint64_t), '\0');
    std::memcpy(out.data(), header.data(), out.size());
    out.reserve(out.size() + total);
    for (const auto& c : compressed) out += c;
    return out;
}

std::string zlib_compress(const void* data, std::uint64_t bytes, unsigned threads) {
    const auto* base = static_cast<const unsigned char*>(data);
    return zlib_compress(
        bytes, [base](std::uint64_t offset, std::size_t, std::vector<unsigned char>&) { return base + offset; }, threads);
}

std::size_t zlib_uncompress(const char* at, std::size_t size, void* dest, std::uint64_t want, const std::string& what) {
    auto fail = [&](const std::string& why) -> void { throw Error(what + ": " + why); };
    std::uint64_t head[3];
    if (size < sizeof head) fail("its compression header lies beyond the end of the file");
    std::memcpy(head, at, sizeof head);
    const std::uint64_t blocks = head[0], block = head[1], last = head[2];
    if (block == 0 || last >= block || (blocks == 0 && last != 0)) fail("malformed compression header");
    // The uncompressed size the header claims, checked without overflow before anything is read.
    if (blocks > want / block + 1) fail("holds more than the " + std::to_string(want) + " bytes expected");
    const std::uint64_t total = blocks == 0 ? 0 : (last ? (blocks - 1) * block + last : blocks * block);
    if (total != want) fail("holds " + std::to_string(total) + " bytes, expected " + std::to_string(want));
    const std::size_t header_bytes = (3 + blocks) * sizeof(std::uint64_t);
    if (header_bytes > size) fail("its compression header lies beyond the end of the file");
    std::size_t used = header_bytes;
    auto* out = static_cast<unsigned char*>(dest);
    for (std::uint64_t b = 0; b < blocks; ++b) {
        std::uint64_t length = 0;
        std::memcpy(&length, at + (3 + b) * sizeof(std::uint64_t), sizeof length);
        if (length > size - used) fail("block " + std::to_string(b) + " lies beyond the end of the file");
        const std::uint64_t expect = (b + 1 == blocks && last) ? last : block;
        uLongf got = static_cast<uLongf>(expect);
        const int code = uncompress(out, &got, reinterpret_cast<const Bytef*>(at + used), static_cast<uLong>(length));
        if (code != Z_OK || got != expect)
            fail("block " + std::to_string(b) + " does not decompress to " + std::to_string(expect) + " bytes (zlib: " +
                 (code == Z_OK ? "short" : zError(code)) + ")");
        out += expect;
        used += static_cast<std::size_t>(length);
    }
    return used;
}

}  // namespace clsph::io
