// The PLY reader (ascii, binary little and big endian) and the mesh sampler: fuzz/fuzz_mesh.hpp.
#include "fuzz_mesh.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) { return fuzz_mesh_file(data, size, ".ply"); }
