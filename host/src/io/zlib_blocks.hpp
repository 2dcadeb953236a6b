// The compressed form of one VTK XML array (compressor="vtkZLibDataCompressor", header_type UInt64):
// the data cut into blocks of block_size bytes, each compressed with zlib on its own, preceded by the
// header [number of blocks, block size, size of the last block when it is partial (0 when it is
// full), compressed size of each block], all UInt64. Blocks are independent, so several threads
// compress them at once.
#pragma once
#include <cstddef>
#include <cstdint>
#include <functional>
#include <string>
#include <vector>

namespace clsph::io {

inline constexpr std::size_t zlib_block_size = std::size_t{1} << 16;

// Where the bytes [offset, offset + length) of an array come from: a pointer into the array, or
// `scratch` filled with them (for arrays computed on the fly, such as the vertex cells). Called
// from several threads at once, each with its own scratch.
using BlockSource = std::function<const unsigned char*(std::uint64_t offset, std::size_t length, std::vector<unsigned char>& scratch)>;

// Header and compressed blocks of an array of `bytes` bytes, compressed by up to `threads` threads
// (at least one). Throws clsph::Error when zlib fails.
std::string zlib_compress(std::uint64_t bytes, const BlockSource& source, unsigned threads);
std::string zlib_compress(const void* data, std::uint64_t bytes, unsigned threads);

// The array starting at `at` (its header first) decompressed into `dest`, which holds `want`
// bytes; `size` is how many bytes there are from `at` to the end of the file. Returns the bytes the
// array takes in the file (header and blocks). Throws clsph::Error starting with `what` when the
// header or a block is malformed or the array does not hold exactly `want` bytes.
std::size_t zlib_uncompress(const char* at, std::size_t size, void* dest, std::uint64_t want, const std::string& what);

}  // namespace clsph::io
