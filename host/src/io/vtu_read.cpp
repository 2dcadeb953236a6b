// Reading back what write_vtu writes (round-trip tests, tools): the header's DataArray tags give
// each array's type and offset into the appended data, raw or zlib-compressed; a .pvtu is read as
// its pieces (io/pvtu.cpp).
#include "clsph/error.hpp"
#include "clsph/io.hpp"
#include "io/file.hpp"
#include "io/vtu_format.hpp"
#include "io/xml.hpp"
#include "io/zlib_blocks.hpp"

#include <cstdint>
#include <cstring>
#include <stdexcept>

namespace clsph {
namespace {

struct VtuFile {
    std::string path, bytes, header;
    std::size_t data = 0;  // offset of the byte after '_'
    std::size_t points = 0;
    bool compressed = false;  // compressor="vtkZLibDataCompressor"

    [[noreturn]] void fail(const std::string& what) const { throw Error(path + ": " + what); }

    // Copies array `a` into `dest` (n * components elements) after checking its tag and size;
    // returns false when there is no such array and it may be missing (`optional`).
    bool array(const io::VtuArray& a, void* dest, bool optional = false) const {
        for (const auto& tag : io::xml_tags(header, "DataArray")) {
            if (io::xml_attribute(tag, "Name") != std::string(a.name)) continue;
            if (io::xml_attribute(tag, "type") != std::string(a.type))
                fail(std::string("array ") + a.name + " is not of type " + a.type);
            const std::size_t comps = std::stoul(io::xml_attribute(tag, "NumberOfComponents").value_or("1"));
            if (comps != a.components) fail(std::string("array ") + a.name + " has the wrong number of components");
            const auto offset = io::xml_attribute(tag, "offset");
            if (!offset || io::xml_attribute(tag, "format") != std::string("appended"))
                fail(std::string("array ") + a.name + " is not in the appended data");
            const std::size_t at = data + std::stoull(*offset);
            std::uint64_t size = 0;
            const std::uint64_t want = points * a.components * a.bytes;
            if (compressed) {
                if (at > bytes.size()) fail(std::string("array ") + a.name + " lies beyond the end of the file");
                io::zlib_uncompress(bytes.data() + at, bytes.size() - at, dest, want, path + ": array " + a.name);
                return true;
            }
            if (at + sizeof size > bytes.size()) fail(std::string("array ") + a.name + " lies beyond the end of the file");
            std::memcpy(&size, bytes.data() + at, sizeof size);
            if (size != want || at + sizeof size + size > bytes.size())
                fail(std::string("array ") + a.name + " has " + std::to_string(size) + " bytes, expected " + std::to_string(want));
            if (size > 0) std::memcpy(dest, bytes.data() + at + sizeof size, size);
            return true;
        }
        if (optional) return false;
        fail(std::string("no array named ") + a.name);
    }
};

}  // namespace

Particles read_vtu(const std::string& path) { return read_vtu(path, nullptr); }

Particles read_vtu(const std::string& path, FrameFields* present) {
    if (path.size() > 5 && path.compare(path.size() - 5, 5, ".pvtu") == 0) return io::read_pvtu(path, present);
    VtuFile f{path, io::read_file(path), {}, 0, 0, false};
    const std::size_t appended = f.bytes.find("<AppendedData");
    const std::size_t marker = appended == std::string::npos ? appended : f.bytes.find('_', appended);
    if (marker == std::string::npos) f.fail("not a VTU file with appended raw data (as write_vtu writes)");
    f.header = f.bytes.substr(0, appended);
    f.data = marker + 1;

    const auto file_tags = io::xml_tags(f.header, "VTKFile");
    if (file_tags.empty() || io::xml_attribute(file_tags[0], "type") != std::string("UnstructuredGrid"))
        f.fail("not a VTK unstructured grid");
    const std::string order = io::host_is_little_endian() ? "LittleEndian" : "BigEndian";
    if (io::xml_attribute(file_tags[0], "byte_order") != order) f.fail("byte order is not this host's " + order);
    if (io::xml_attribute(file_tags[0], "header_type") != std::string("UInt64")) f.fail("block headers are not UInt64");
    if (const auto compressor = io::xml_attribute(file_tags[0], "compressor")) {
        if (*compressor != "vtkZLibDataCompressor") f.fail("compressor " + *compressor + " is not vtkZLibDataCompressor");
        f.compressed = true;
    }
    const auto pieces = io::xml_tags(f.header, "Piece");
    if (pieces.size() != 1) f.fail("expected exactly one Piece");
    try {
        f.points = std::stoull(io::xml_attribute(pieces[0], "NumberOfPoints").value_or("x"));
    } catch (const std::exception&) {
        f.fail("Piece has no valid NumberOfPoints");
    }

    Particles p;
    p.resize(f.points);
    try {
        const bool optional = present != nullptr;
        FrameFields got;
        got.id = f.array(io::vtu_id, p.id.data(), optional);
        got.type = f.array(io::vtu_type, p.type.data(), optional);
        got.velocity = f.array(io::vtu_velocity, p.velocity.data(), optional);
        got.density = f.array(io::vtu_density, p.density.data(), optional);
        got.pressure = f.array(io::vtu_pressure, p.pressure.data(), optional);
        f.array(io::vtu_position, p.position.data());
        if (present) *present = got;
    } catch (const std::logic_error&) {  // std::stoul on a malformed attribute
        f.fail("malformed DataArray attributes");
    }
    for (auto t : p.type)
        if (t != ParticleType::fluid && t != ParticleType::boundary) f.fail("a particle type is neither 0 nor 1");
    return p;
}

}  // namespace clsph
