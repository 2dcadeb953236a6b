// VTU frames: VTK XML unstructured grid, appended binary data with 64-bit block headers. Raw, each
// array is a UInt64 byte count followed by its bytes; compressed (VtuFormat::compress), each is
// the zlib block form of io/zlib_blocks.hpp. Offsets count from the '_' marker.
#include "clsph/io.hpp"
#include "io/file.hpp"
#include "io/vtu_format.hpp"
#include "io/zlib_blocks.hpp"

#include <algorithm>
#include <cstdint>
#include <cstring>
#include <limits>
#include <sstream>
#include <utility>
#include <vector>

namespace clsph {
namespace {

static_assert(sizeof(ParticleType) == 1, "type is written as UInt8");
static_assert(sizeof(std::array<float, 3>) == 12, "velocity is written as packed Float32 x 3");
static_assert(sizeof(std::array<double, 3>) == 24, "positions are written as packed Float64 x 3");
static_assert(io::zlib_block_size % 8 == 0, "a block holds whole cell indices");

// One array of the appended data: its tag and where its bytes come from.
struct Array {
    const char* type;
    const char* name;
    std::size_t components;
    std::uint64_t bytes;
    io::BlockSource source;
};

Array stored(const io::VtuArray& a, const void* data, std::size_t n) {
    const auto* base = static_cast<const unsigned char*>(data);
    return {a.type, a.name, a.components, n * a.components * a.bytes,
            [base](std::uint64_t offset, std::size_t, std::vector<unsigned char>&) { return base + offset; }};
}

// Vertex cells, computed a block at a time: connectivity i, offsets i + 1 (`first` 0 or 1), types
// 1 (VTK_VERTEX).
template <class Int>
Array cell_indices(const char* type, const char* name, std::size_t n, Int first) {
    return {type, name, 1, n * sizeof(Int),
            [first](std::uint64_t offset, std::size_t length, std::vector<unsigned char>& scratch) {
                scratch.resize(length);
                const std::uint64_t start = offset / sizeof(Int);
                for (std::size_t k = 0; k < length / sizeof(Int); ++k) {
                    const Int v = static_cast<Int>(start + k) + first;
                    std::memcpy(scratch.data() + k * sizeof(Int), &v, sizeof v);
                }
                return static_cast<const unsigned char*>(scratch.data());
            }};
}

Array vertex_types(std::size_t n) {
    return {"UInt8", "types", 1, n, [](std::uint64_t, std::size_t length, std::vector<unsigned char>& scratch) {
                scratch.assign(length, 1);
                return static_cast<const unsigned char*>(scratch.data());
            }};
}

void data_array(std::ostringstream& xml, const Array& a, std::uint64_t offset) {
    xml << "        <DataArray type=\"" << a.type << "\" Name=\"" << a.name << "\"";
    if (a.components > 1) xml << " NumberOfComponents=\"" << a.components << "\"";
    xml << " format=\"appended\" offset=\"" << offset << "\"/>\n";
}

}  // namespace

void write_vtu(const std::string& path, const Particles& p) { write_vtu(path, p, FrameFields{}); }

void write_vtu(const std::string& path, const Particles& p, const FrameFields& fields) {
    write_vtu(path, p, fields, VtuFormat{});
}

void write_vtu(const std::string& path, const Particles& p, const FrameFields& fields, const VtuFormat& format) {
    io::require_consistent(p, path);
    const std::size_t n = p.size();
    // The point-data arrays written, in their order, then the points and the cells.
    std::vector<Array> point_data;
    if (fields.id) point_data.push_back(stored(io::vtu_id, p.id.data(), n));
    if (fields.type) point_data.push_back(stored(io::vtu_type, p.type.data(), n));
    if (fields.velocity) point_data.push_back(stored(io::vtu_velocity, p.velocity.data(), n));
    if (fields.density) point_data.push_back(stored(io::vtu_density, p.density.data(), n));
    if (fields.pressure) point_data.push_back(stored(io::vtu_pressure, p.pressure.data(), n));
    const Array points = stored(io::vtu_position, p.position.data(), n);
    std::vector<Array> cells;
    if (n < static_cast<std::size_t>(std::numeric_limits<std::int32_t>::max())) {
        cells.push_back(cell_indices<std::int32_t>("Int32", "connectivity", n, 0));
        cells.push_back(cell_indices<std::int32_t>("Int32", "offsets", n, 1));
    } else {
        cells.push_back(cell_indices<std::int64_t>("Int64", "connectivity", n, 0));
        cells.push_back(cell_indices<std::int64_t>("Int64", "offsets", n, 1));
    }
    cells.push_back(vertex_types(n));

    std::vector<const Array*> all;
    for (const auto& a : point_data) all.push_back(&a);
    all.push_back(&points);
    for (const auto& a : cells) all.push_back(&a);
    // Compressed, every array is encoded before the header is written: the offsets depend on it.
    std::vector<std::string> encoded;
    if (format.compress)
        for (const Array* a : all) encoded.push_back(io::zlib_compress(a->bytes, a->source, format.threads));
    auto size_in_file = [&](std::size_t k) {
        return format.compress ? encoded[k].size() : sizeof(std::uint64_t) + all[k]->bytes;
    };

    std::ostringstream xml;
    xml << "<?xml version=\"1.0\"?>\n"
        << "<VTKFile type=\"UnstructuredGrid\" version=\"1.0\" byte_order=\""
        << (io::host_is_little_endian() ? "LittleEndian" : "BigEndian") << "\" header_type=\"UInt64\""
        << (format.compress ? " compressor=\"vtkZLibDataCompressor\"" : "") << ">\n"
        << "  <UnstructuredGrid>\n"
        << "    <Piece NumberOfPoints=\"" << n << "\" NumberOfCells=\"" << n << "\">\n"
        << "      <PointData" << (fields.type ? " Scalars=\"type\"" : "") << (fields.velocity ? " Vectors=\"velocity\"" : "")
        << ">\n";
    std::uint64_t offset = 0;
    std::size_t k = 0;
    auto next = [&] {
        data_array(xml, *all[k], offset);
        offset += size_in_file(k++);
    };
    for (std::size_t i = 0; i < point_data.size(); ++i) next();
    xml << "      </PointData>\n      <Points>\n";
    next();
    xml << "      </Points>\n      <Cells>\n";
    for (std::size_t i = 0; i < cells.size(); ++i) next();
    xml << "      </Cells>\n    </Piece>\n  </UnstructuredGrid>\n  <AppendedData encoding=\"raw\">\n   _";

    io::OutputFile out(path);
    out.write(xml.str());
    if (format.compress) {
        for (const auto& e : encoded) out.write(e);
    } else {
        std::vector<unsigned char> scratch;
        for (const Array* a : all) {
            out.write(&a->bytes, sizeof a->bytes);
            for (std::uint64_t at = 0; at < a->bytes; at += io::zlib_block_size) {
                const std::size_t length = static_cast<std::size_t>(std::min<std::uint64_t>(io::zlib_block_size, a->bytes - at));
                out.write(a->source(at, length, scratch), length);
            }
        }
    }
    out.write("\n  </AppendedData>\n</VTKFile>\n");
    out.commit();
}

}  // namespace clsph
