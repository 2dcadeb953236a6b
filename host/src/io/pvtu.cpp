// Parallel VTU indexes (.pvtu): one frame as several pieces (clsph run --pieces, one per device),
// which ParaView opens as one dataset. The index declares the point-data arrays and the points as
// the pieces hold them (types and component counts from io/vtu_format.hpp) and names each piece.
#include "clsph/error.hpp"
#include "clsph/io.hpp"
#include "io/file.hpp"
#include "io/vtu_format.hpp"
#include "io/xml.hpp"

#include <sstream>

namespace clsph {
namespace {

void p_data_array(std::ostringstream& xml, const io::VtuArray& a) {
    xml << "      <PDataArray type=\"" << a.type << "\" Name=\"" << a.name << "\"";
    if (a.components > 1) xml << " NumberOfComponents=\"" << a.components << "\"";
    xml << "/>\n";
}

std::string directory_of(const std::string& path) {
    const auto slash = path.find_last_of('/');
    return slash == std::string::npos ? std::string() : path.substr(0, slash + 1);
}

}  // namespace

void write_pvtu(const std::string& path, const std::vector<std::string>& pieces, const FrameFields& fields) {
    std::ostringstream xml;
    xml << "<?xml version=\"1.0\"?>\n"
        << "<VTKFile type=\"PUnstructuredGrid\" version=\"1.0\" byte_order=\""
        << (io::host_is_little_endian() ? "LittleEndian" : "BigEndian") << "\" header_type=\"UInt64\">\n"
        << "  <PUnstructuredGrid GhostLevel=\"0\">\n"
        << "    <PPointData" << (fields.type ? " Scalars=\"type\"" : "") << (fields.velocity ? " Vectors=\"velocity\"" : "")
        << ">\n";
    if (fields.id) p_data_array(xml, io::vtu_id);
    if (fields.type) p_data_array(xml, io::vtu_type);
    if (fields.velocity) p_data_array(xml, io::vtu_velocity);
    if (fields.density) p_data_array(xml, io::vtu_density);
    if (fields.pressure) p_data_array(xml, io::vtu_pressure);
    xml << "    </PPointData>\n    <PPoints>\n";
    p_data_array(xml, io::vtu_position);
    xml << "    </PPoints>\n";
    for (const auto& piece : pieces) xml << "    <Piece Source=\"" << io::xml_escape(piece) << "\"/>\n";
    xml << "  </PUnstructuredGrid>\n</VTKFile>\n";
    io::OutputFile out(path);
    out.write(xml.str());
    out.commit();
}

std::vector<std::string> read_pvtu_sources(const std::string& path) {
    const std::string xml = io::read_file(path, std::size_t{64} << 20);
    const auto file = io::xml_tags(xml, "VTKFile");
    if (file.empty() || io::xml_attribute(file[0], "type") != std::string("PUnstructuredGrid"))
        throw Error(path + ": not a parallel VTK unstructured grid (.pvtu)");
    std::vector<std::string> sources;
    for (const auto& tag : io::xml_tags(xml, "Piece")) {
        const auto source = io::xml_attribute(tag, "Source");
        if (!source || source->empty()) throw Error(path + ": a Piece without a Source: " + tag);
        sources.push_back(*source);
    }
    return sources;
}

namespace io {

Particles read_pvtu(const std::string& path, FrameFields* present) {
    Particles all;
    FrameFields got;
    for (const auto& source : read_pvtu_sources(path)) {
        // A piece is a VTU file: an index naming an index would never end.
        if (source.size() > 5 && source.compare(source.size() - 5, 5, ".pvtu") == 0)
            throw Error(path + ": piece " + source + " is an index itself, not a VTU file");
        FrameFields here;
        const Particles p = read_vtu(source[0] == '/' ? source : directory_of(path) + source, present ? &here : nullptr);
        got.id = got.id && here.id;
        got.type = got.type && here.type;
        got.velocity = got.velocity && here.velocity;
        got.density = got.density && here.density;
        got.pressure = got.pressure && here.pressure;
        for (std::size_t i = 0; i < p.size(); ++i)
            all.push_back(p.id[i], p.type[i], p.position[i], p.velocity[i], p.density[i], p.pressure[i]);
    }
    if (present) *present = got;
    return all;
}

}  // namespace io
}  // namespace clsph
