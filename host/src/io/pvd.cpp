// ParaView collections (.pvd): the list of (time, frame file) that opens as a time series.
#include "clsph/error.hpp"
#include "clsph/io.hpp"
#include "io/file.hpp"
#include "io/xml.hpp"

#include <charconv>

namespace clsph {

PvdWriter::PvdWriter(std::string path) : path_(std::move(path)) { rewrite(); }

void PvdWriter::add(double time, const std::string& file) {
    entries_.push_back({time, file});
    try {
        rewrite();
    } catch (...) {
        entries_.pop_back();  // the file on disk still lists the frames before this one
        throw;
    }
}

void PvdWriter::rewrite() const {
    std::string xml = "<?xml version=\"1.0\"?>\n<VTKFile type=\"Collection\" version=\"0.1\" byte_order=\"";
    xml += io::host_is_little_endian() ? "LittleEndian" : "BigEndian";
    xml += "\">\n  <Collection>\n";
    for (const auto& e : entries_)
        xml += "    <DataSet timestep=\"" + io::exact_text(e.time) + "\" group=\"\" part=\"0\" file=\"" +
               io::xml_escape(e.file) + "\"/>\n";
    xml += "  </Collection>\n</VTKFile>\n";
    io::OutputFile out(path_);
    out.write(xml);
    out.commit();
}

std::vector<PvdEntry> read_pvd(const std::string& path) {
    const std::string xml = io::read_file(path);
    if (io::xml_tags(xml, "Collection").empty()) throw Error(path + ": not a ParaView collection (no <Collection>)");
    std::vector<PvdEntry> entries;
    for (const auto& tag : io::xml_tags(xml, "DataSet")) {
        const auto time = io::xml_attribute(tag, "timestep");
        const auto file = io::xml_attribute(tag, "file");
        PvdEntry e;
        const char* end = time ? time->data() + time->size() : nullptr;
        if (!time || !file || std::from_chars(time->data(), end, e.time).ptr != end)
            throw Error(path + ": a DataSet without a valid timestep and file: " + tag);
        e.file = *file;
        entries.push_back(e);
    }
    return entries;
}

}  // namespace clsph
