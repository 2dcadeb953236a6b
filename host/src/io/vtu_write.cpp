// VTU frames: VTK XML unstructured grid, appended raw binary data with 64-bit block headers
// (each array is a UInt64 byte count followed by its bytes; offsets count from the '_' marker).
#include "clsph/io.hpp"
#include "io/file.hpp"
#include "io/vtu_format.hpp"

#include <algorithm>
#include <cstdint>
#include <limits>
#include <sstream>
#include <utility>
#include <vector>

namespace clsph {
namespace {

static_assert(sizeof(ParticleType) == 1, "type is written as UInt8");
static_assert(sizeof(std::array<float, 3>) == 12, "velocity is written as packed Float32 x 3");
static_assert(sizeof(std::array<double, 3>) == 24, "positions are written as packed Float64 x 3");

struct Block {
    const io::VtuArray* array;
    std::uint64_t bytes;
};

void data_array(std::ostringstream& xml, const char* type, const char* name, std::size_t components,
                std::uint64_t offset) {
    xml << "        <DataArray type=\"" << type << "\" Name=\"" << name << "\"";
    if (components > 1) xml << " NumberOfComponents=\"" << components << "\"";
    xml << " format=\"appended\" offset=\"" << offset << "\"/>\n";
}

// Vertex cells: connectivity i, offsets i + 1, types 1 (VTK_VERTEX), written in chunks.
template <class Int>
void write_cells(io::OutputFile& out, std::size_t n) {
    std::vector<Int> chunk;
    for (int pass = 0; pass < 2; ++pass) {
        const std::uint64_t bytes = n * sizeof(Int);
        out.write(&bytes, sizeof bytes);
        for (std::size_t i = 0; i < n; i += 65536) {
            const std::size_t m = std::min<std::size_t>(65536, n - i);
            chunk.resize(m);
            for (std::size_t k = 0; k < m; ++k) chunk[k] = static_cast<Int>(i + k + static_cast<std::size_t>(pass));
            out.write(chunk.data(), m * sizeof(Int));
        }
    }
    const std::uint64_t bytes = n;
    out.write(&bytes, sizeof bytes);
    const std::vector<std::uint8_t> types(std::min<std::size_t>(n, 65536), 1);
    for (std::size_t i = 0; i < n; i += types.size()) out.write(types.data(), std::min(types.size(), n - i));
}

}  // namespace

void write_vtu(const std::string& path, const Particles& p) { write_vtu(path, p, FrameFields{}); }

void write_vtu(const std::string& path, const Particles& p, const FrameFields& fields) {
    io::require_consistent(p, path);
    // The point-data arrays written, in their order, with their data.
    std::vector<std::pair<const io::VtuArray*, const void*>> point_data;
    if (fields.id) point_data.push_back({&io::vtu_id, p.id.data()});
    if (fields.type) point_data.push_back({&io::vtu_type, p.type.data()});
    if (fields.velocity) point_data.push_back({&io::vtu_velocity, p.velocity.data()});
    if (fields.density) point_data.push_back({&io::vtu_density, p.density.data()});
    if (fields.pressure) point_data.push_back({&io::vtu_pressure, p.pressure.data()});
    const std::size_t n = p.size();
    const bool small = n < static_cast<std::size_t>(std::numeric_limits<std::int32_t>::max());
    const char* int_type = small ? "Int32" : "Int64";
    const std::uint64_t int_bytes = small ? 4 : 8;

    std::ostringstream xml;
    xml << "<?xml version=\"1.0\"?>\n"
        << "<VTKFile type=\"UnstructuredGrid\" version=\"1.0\" byte_order=\""
        << (io::host_is_little_endian() ? "LittleEndian" : "BigEndian") << "\" header_type=\"UInt64\">\n"
        << "  <UnstructuredGrid>\n"
        << "    <Piece NumberOfPoints=\"" << n << "\" NumberOfCells=\"" << n << "\">\n"
        << "      <PointData" << (fields.type ? " Scalars=\"type\"" : "") << (fields.velocity ? " Vectors=\"velocity\"" : "")
        << ">\n";
    std::uint64_t offset = 0;
    auto next = [&](const io::VtuArray& a) {
        data_array(xml, a.type, a.name, a.components, offset);
        offset += 8 + n * a.components * a.bytes;
    };
    for (const auto& [a, data] : point_data) next(*a);
    xml << "      </PointData>\n      <Points>\n";
    next(io::vtu_position);
    xml << "      </Points>\n      <Cells>\n";
    data_array(xml, int_type, "connectivity", 1, offset);
    offset += 8 + n * int_bytes;
    data_array(xml, int_type, "offsets", 1, offset);
    offset += 8 + n * int_bytes;
    data_array(xml, "UInt8", "types", 1, offset);
    xml << "      </Cells>\n    </Piece>\n  </UnstructuredGrid>\n  <AppendedData encoding=\"raw\">\n   _";

    io::OutputFile out(path);
    out.write(xml.str());
    auto block = [&](const void* data, const io::VtuArray& a) {
        const std::uint64_t bytes = n * a.components * a.bytes;
        out.write(&bytes, sizeof bytes);
        out.write(data, bytes);
    };
    for (const auto& [a, data] : point_data) block(data, *a);
    block(p.position.data(), io::vtu_position);
    if (small)
        write_cells<std::int32_t>(out, n);
    else
        write_cells<std::int64_t>(out, n);
    out.write("\n  </AppendedData>\n</VTKFile>\n");
    out.commit();
}

}  // namespace clsph
