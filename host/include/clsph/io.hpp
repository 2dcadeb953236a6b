// Particle frames on disk: VTU (ParaView), CSV, and the .pvd collection that makes a series of
// VTU frames one time series in ParaView. Every file is written to "<path>.tmp" and renamed into
// place, so a run that is cut short never leaves a half-written frame or collection behind.
// Errors are clsph::Error naming the path and the OS error.
#pragma once
#include "clsph/particles.hpp"

#include <string>
#include <vector>

namespace clsph {

// One frame as a VTK XML unstructured grid, binary (appended raw data, little or big endian as the
// host is): points = positions (Float64), one vertex cell per particle (so ParaView's Surface and
// Points representations show them), point data id (UInt32), type (UInt8: 0 fluid, 1 boundary),
// velocity (Float32 x 3), density and pressure (Float32).
void write_vtu(const std::string& path, const Particles& particles);

// Which point-data arrays a frame holds (positions always): `clsph run --fields`.
struct FrameFields {
    bool id = true, type = true, velocity = true, density = true, pressure = true;
    // "all", or a comma-separated list of id, type, velocity, density, pressure; throws clsph::Error
    // naming `option` (and the unknown name) otherwise.
    static FrameFields parse(const std::string& list, const std::string& option = "--fields");
    bool all() const { return id && type && velocity && density && pressure; }
};
// write_vtu with only the chosen point-data arrays (and write_csv with only their columns).
void write_vtu(const std::string& path, const Particles& particles, const FrameFields& fields);

// How a VTU frame is encoded: raw (the default), or compressed as ParaView reads it
// (compressor="vtkZLibDataCompressor": each array in zlib blocks of 64 KiB, `clsph run --compress`),
// by up to `threads` threads at once.
struct VtuFormat {
    bool compress = false;
    unsigned threads = 1;
};
void write_vtu(const std::string& path, const Particles& particles, const FrameFields& fields, const VtuFormat& format);

// One frame as pieces (`clsph run --pieces`: one VTU per device): the parallel index (.pvtu) that
// makes the VTU files `pieces` (as the index should name them: relative to its directory) one
// dataset in ParaView, declaring the arrays `fields` chose as write_vtu writes them.
void write_pvtu(const std::string& path, const std::vector<std::string>& pieces, const FrameFields& fields);
// The pieces a .pvtu written by write_pvtu names, as it names them.
std::vector<std::string> read_pvtu_sources(const std::string& path);

// Reads a file written by write_vtu, raw or compressed (not VTU files in general: for round-trip
// tests and tools), or an index written by write_pvtu: its pieces in order, concatenated.
// Every array must be there; with `present`, arrays a chosen-fields frame left out are allowed,
// left at zero and reported in *present.
Particles read_vtu(const std::string& path);
Particles read_vtu(const std::string& path, FrameFields* present);

// One frame as CSV with the header `id,type,x,y,z,vx,vy,vz,rho,p`; type is 0 (fluid) or 1
// (boundary); every number is written with as many digits as reading it back exactly needs.
void write_csv(const std::string& path, const Particles& particles);
void write_csv(const std::string& path, const Particles& particles, const FrameFields& fields);
Particles read_csv(const std::string& path);

struct PvdEntry {
    double time = 0.0;  // simulated seconds
    std::string file;   // as written in the collection: relative to the .pvd's directory
};

// A ParaView collection (.pvd) that grows by one frame at a time. The file is valid from the
// moment the writer exists (an empty collection) and is rewritten whole after each add().
class PvdWriter {
public:
    explicit PvdWriter(std::string path);
    // `file` as the collection should name it: relative to the .pvd's directory, so that the
    // output directory can be moved.
    void add(double time, const std::string& file);
    const std::string& path() const { return path_; }
    const std::vector<PvdEntry>& entries() const { return entries_; }

private:
    void rewrite() const;
    std::string path_;
    std::vector<PvdEntry> entries_;
};

// The entries of a .pvd written by PvdWriter, in file order.
std::vector<PvdEntry> read_pvd(const std::string& path);

}  // namespace clsph
