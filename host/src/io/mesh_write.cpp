// Triangle meshes as VTP (VTK XML PolyData, appended raw data with 64-bit block headers, like the
// VTU frames) and as binary PLY.
#include "clsph/error.hpp"
#include "clsph/mesh.hpp"
#include "io/file.hpp"

#include <cstring>
#include <sstream>

namespace clsph {
namespace {

static_assert(sizeof(std::array<float, 3>) == 12, "vectors are written as packed Float32 x 3");
static_assert(sizeof(std::array<std::uint32_t, 3>) == 12, "triangles are written as packed UInt32 x 3");

void check(const TriangleMesh& m, const std::string& path) {
    if (!m.normals.empty() && m.normals.size() != m.positions.size())
        throw Error(path + ": the mesh has " + std::to_string(m.normals.size()) + " normals for " +
                    std::to_string(m.positions.size()) + " vertices");
    for (const auto& t : m.triangles)
        for (auto v : t)
            if (v >= m.positions.size())
                throw Error(path + ": a triangle refers to vertex " + std::to_string(v) + " of " +
                            std::to_string(m.positions.size()));
}

}  // namespace

void write_vtp(const std::string& path, const TriangleMesh& m) {
    check(m, path);
    const std::uint64_t nv = m.positions.size(), nt = m.triangles.size();
    const bool normals = !m.normals.empty();
    std::ostringstream xml;
    xml << "<?xml version=\"1.0\"?>\n"
        << "<VTKFile type=\"PolyData\" version=\"1.0\" byte_order=\""
        << (io::host_is_little_endian() ? "LittleEndian" : "BigEndian") << "\" header_type=\"UInt64\">\n"
        << "  <PolyData>\n"
        << "    <Piece NumberOfPoints=\"" << nv << "\" NumberOfVerts=\"0\" NumberOfLines=\"0\" NumberOfStrips=\"0\" "
        << "NumberOfPolys=\"" << nt << "\">\n";
    std::uint64_t offset = 0;
    auto array = [&](const char* type, const char* name, int components, std::uint64_t bytes) {
        xml << "        <DataArray type=\"" << type << "\" Name=\"" << name << "\"";
        if (components > 1) xml << " NumberOfComponents=\"" << components << "\"";
        xml << " format=\"appended\" offset=\"" << offset << "\"/>\n";
        offset += 8 + bytes;
    };
    if (normals) {
        xml << "      <PointData Normals=\"normal\">\n";
        array("Float32", "normal", 3, nv * 12);
        xml << "      </PointData>\n";
    }
    xml << "      <Points>\n";
    array("Float32", "position", 3, nv * 12);
    xml << "      </Points>\n      <Polys>\n";
    array("UInt32", "connectivity", 1, nt * 12);
    array("UInt64", "offsets", 1, nt * 8);
    xml << "      </Polys>\n    </Piece>\n  </PolyData>\n  <AppendedData encoding=\"raw\">\n   _";

    io::OutputFile out(path);
    out.write(xml.str());
    auto block = [&](const void* data, std::uint64_t bytes) {
        out.write(&bytes, sizeof bytes);
        if (bytes) out.write(data, bytes);
    };
    if (normals) block(m.normals.data(), nv * 12);
    block(m.positions.data(), nv * 12);
    block(m.triangles.data(), nt * 12);
    std::vector<std::uint64_t> offsets(nt);
    for (std::uint64_t t = 0; t < nt; ++t) offsets[t] = 3 * (t + 1);
    block(offsets.data(), nt * 8);
    out.write("\n  </AppendedData>\n</VTKFile>\n");
    out.commit();
}

void write_ply(const std::string& path, const TriangleMesh& m) {
    check(m, path);
    const bool normals = !m.normals.empty();
    std::ostringstream header;
    header << "ply\nformat " << (io::host_is_little_endian() ? "binary_little_endian" : "binary_big_endian")
           << " 1.0\ncomment clsph free surface\nelement vertex " << m.positions.size()
           << "\nproperty float x\nproperty float y\nproperty float z\n";
    if (normals) header << "property float nx\nproperty float ny\nproperty float nz\n";
    header << "element face " << m.triangles.size() << "\nproperty list uchar uint vertex_indices\nend_header\n";
    io::OutputFile out(path);
    out.write(header.str());
    std::vector<char> buf;
    const std::size_t stride = normals ? 24 : 12;
    buf.resize(stride * std::min<std::size_t>(m.positions.size(), 65536));
    for (std::size_t v0 = 0; v0 < m.positions.size(); v0 += 65536) {
        const std::size_t n = std::min<std::size_t>(65536, m.positions.size() - v0);
        for (std::size_t k = 0; k < n; ++k) {
            std::memcpy(&buf[stride * k], m.positions[v0 + k].data(), 12);
            if (normals) std::memcpy(&buf[stride * k + 12], m.normals[v0 + k].data(), 12);
        }
        out.write(buf.data(), stride * n);
    }
    std::vector<char> faces(13 * std::min<std::size_t>(m.triangles.size(), 65536));
    for (std::size_t t0 = 0; t0 < m.triangles.size(); t0 += 65536) {
        const std::size_t n = std::min<std::size_t>(65536, m.triangles.size() - t0);
        for (std::size_t k = 0; k < n; ++k) {
            faces[13 * k] = 3;
            std::memcpy(&faces[13 * k + 1], m.triangles[t0 + k].data(), 12);
        }
        out.write(faces.data(), 13 * n);
    }
    out.commit();
}

TriangleMesh read_ply(const std::string& path) {
    const std::string data = io::read_file(path);
    const auto end = data.find("end_header\n");
    if (data.compare(0, 4, "ply\n") != 0 || end == std::string::npos) throw Error(path + ": not a PLY file");
    std::istringstream h(data.substr(0, end));
    std::string line;
    std::size_t nv = 0, nt = 0, vprops = 0;
    bool in_vertex = false;
    while (std::getline(h, line)) {
        std::istringstream w(line);
        std::string word, what;
        w >> word;
        if (word == "element") {
            std::size_t count = 0;
            w >> what >> count;
            in_vertex = what == "vertex";
            (in_vertex ? nv : nt) = count;
        } else if (word == "property" && in_vertex) {
            ++vprops;
        }
    }
    if (vprops != 3 && vprops != 6) throw Error(path + ": expected 3 or 6 vertex properties");
    const std::size_t stride = 4 * vprops;
    std::size_t at = end + 11;
    if (data.size() < at + nv * stride + nt * 13) throw Error(path + ": truncated");
    TriangleMesh m;
    m.positions.resize(nv);
    if (vprops == 6) m.normals.resize(nv);
    for (std::size_t v = 0; v < nv; ++v, at += stride) {
        std::memcpy(m.positions[v].data(), &data[at], 12);
        if (vprops == 6) std::memcpy(m.normals[v].data(), &data[at + 12], 12);
    }
    m.triangles.resize(nt);
    for (std::size_t t = 0; t < nt; ++t, at += 13) {
        if (data[at] != 3) throw Error(path + ": a face is not a triangle");
        std::memcpy(m.triangles[t].data(), &data[at + 1], 12);
    }
    return m;
}

}  // namespace clsph
