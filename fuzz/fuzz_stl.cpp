// The STL reader (binary and ASCII) and the mesh sampler: fuzz/fuzz_mesh.hpp.
#include "fuzz_mesh.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) { return fuzz_mesh_file(data, size, ".stl"); }
