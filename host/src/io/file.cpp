#include "io/file.hpp"

#include "clsph/error.hpp"

#include <cerrno>
#include <charconv>
#include <cstdint>
#include <cstring>
#include <fstream>
#include <sstream>
#include <sys/stat.h>
#include <algorithm>
#include <cstdio>

namespace clsph::io {

OutputFile::OutputFile(std::string path) : path_(std::move(path)), tmp_(path_ + ".tmp") {
    file_ = std::fopen(tmp_.c_str(), "wb");
    if (!file_) fail("cannot write");
}

OutputFile::~OutputFile() {
    if (file_) {
        std::fclose(file_);
        std::remove(tmp_.c_str());
    }
}

void OutputFile::fail(const std::string& what) const {
    throw Error(what + " " + path_ + ": " + std::strerror(errno));
}

void OutputFile::write(const void* data, std::size_t bytes) {
    if (bytes > 0 && std::fwrite(data, 1, bytes, file_) != bytes) fail("cannot write");
}

void OutputFile::commit() {
    const bool flushed = std::fflush(file_) == 0;
    const int saved = errno;
    const bool closed = std::fclose(file_) == 0;
    file_ = nullptr;
    if (!flushed || !closed) {
        if (!flushed) errno = saved;
        std::remove(tmp_.c_str());
        fail("cannot write");
    }
    if (std::rename(tmp_.c_str(), path_.c_str()) != 0) {
        const int err = errno;
        std::remove(tmp_.c_str());
        errno = err;
        fail("cannot rename the finished file into place as");
    }
}

namespace {

std::string bytes_text(std::uintmax_t b) {
    const char* unit[] = {"bytes", "KiB", "MiB", "GiB", "TiB"};
    double v = static_cast<double>(b);
    int u = 0;
    while (v >= 1024.0 && u < 4) v /= 1024.0, ++u;
    char text[48];
    std::snprintf(text, sizeof text, u == 0 ? "%.0f %s" : "%.1f %s", v, unit[u]);
    return text;
}

}  // namespace

std::string file_problem(const std::string& path, std::size_t limit) {
    struct stat st {};
    if (::stat(path.c_str(), &st) != 0) return std::strerror(errno);
    if (S_ISDIR(st.st_mode)) return "it is a directory, not a file";
    if (!S_ISREG(st.st_mode)) return "it is not a regular file (a device, a pipe or a socket)";
    if (static_cast<std::uintmax_t>(st.st_size) > limit)
        return "the file is " + bytes_text(static_cast<std::uintmax_t>(st.st_size)) + ", more than the " +
               bytes_text(limit) + " allowed";
    return "";
}

std::string read_file(const std::string& path, std::size_t limit) {
    if (const std::string why = file_problem(path, limit); !why.empty()) throw Error("cannot read " + path + ": " + why);
    std::ifstream in(path, std::ios::binary);
    if (!in) throw Error("cannot read " + path + ": " + std::strerror(errno));
    // At most limit + 1 bytes, even if the file grows while it is read.
    std::string text;
    char chunk[65536];
    while (in && text.size() <= limit) {
        in.read(chunk, static_cast<std::streamsize>(std::min<std::size_t>(sizeof chunk, limit + 1 - text.size())));
        text.append(chunk, static_cast<std::size_t>(in.gcount()));
        if (in.gcount() == 0) break;
    }
    if (in.bad()) throw Error("cannot read " + path + ": " + std::strerror(errno));
    if (text.size() > limit) throw Error("cannot read " + path + ": it grew past the " + bytes_text(limit) + " allowed");
    return text;
}

std::string exact_text(double v) {
    char buf[40];
    const auto r = std::to_chars(buf, buf + sizeof buf, v);
    return std::string(buf, r.ptr);
}

std::string exact_text(float v) {
    char buf[40];
    const auto r = std::to_chars(buf, buf + sizeof buf, v);
    return std::string(buf, r.ptr);
}

bool host_is_little_endian() {
    const std::uint16_t one = 1;
    unsigned char first = 0;
    std::memcpy(&first, &one, 1);
    return first == 1;
}

void require_consistent(const Particles& p, const std::string& path) {
    const std::size_t n = p.id.size();
    if (p.type.size() != n || p.position.size() != n || p.velocity.size() != n || p.density.size() != n ||
        p.pressure.size() != n)
        throw Error("cannot write " + path + ": the particle arrays have different lengths (id has " +
                    std::to_string(n) + " elements)");
}

}  // namespace clsph::io
