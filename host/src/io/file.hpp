// Files for the writers: written whole to "<path>.tmp" and renamed into place on commit(), so that
// a reader (ParaView following a .pvd, a run cut short) never sees half a file; errors name the
// path and the OS error.
#pragma once
#include "clsph/particles.hpp"

#include <cstddef>
#include <cstdio>
#include <string>
#include <string_view>

namespace clsph::io {

class OutputFile {
public:
    explicit OutputFile(std::string path);
    ~OutputFile();  // without commit(): the temporary file is removed
    OutputFile(const OutputFile&) = delete;
    OutputFile& operator=(const OutputFile&) = delete;

    void write(const void* data, std::size_t bytes);
    void write(std::string_view text) { write(text.data(), text.size()); }
    // Flushes, closes and renames into place (a full disk shows up here, at the latest).
    void commit();

private:
    [[noreturn]] void fail(const std::string& what) const;
    std::string path_, tmp_;
    std::FILE* file_ = nullptr;
};

// Why `path` cannot be read as a file of at most `limit` bytes ("" when it can): it is missing,
// a directory, not a regular file (a device such as /dev/zero, a pipe: streams with no end), or
// larger than the limit. Checked before a byte is read, so an endless stream cannot fill memory.
std::string file_problem(const std::string& path, std::size_t limit);

// The whole file, which must be a regular file of at most `limit` bytes; Error "cannot read
// PATH: <why>".
std::string read_file(const std::string& path, std::size_t limit = std::size_t{4} << 30);

// The shortest decimal text that reads back as exactly the same value.
std::string exact_text(double v);
std::string exact_text(float v);

bool host_is_little_endian();

// Error naming `path` unless every array of `p` has as many elements as p.id.
void require_consistent(const Particles& p, const std::string& path);

}  // namespace clsph::io
