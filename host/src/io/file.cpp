#include "io/file.hpp"

#include "clsph/error.hpp"

#include <cerrno>
#include <charconv>
#include <cstdint>
#include <cstring>
#include <fstream>
#include <sstream>

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

std::string read_file(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    if (!in) throw Error("cannot read " + path + ": " + std::strerror(errno));
    std::ostringstream buf;
    buf << in.rdbuf();
    if (in.bad()) throw Error("cannot read " + path + ": " + std::strerror(errno));
    return buf.str();
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
