// The layout write_vtu writes and read_vtu expects, in one place: the point-data arrays, their
// VTK types and component counts.
#pragma once
#include "clsph/io.hpp"

#include <cstddef>
#include <string>

namespace clsph::io {

struct VtuArray {
    const char* name;
    const char* type;      // VTK type name
    std::size_t components;
    std::size_t bytes;     // per component
};

// In the order they are written: point data, then the points, then the cells.
inline constexpr VtuArray vtu_id{"id", "UInt32", 1, 4};
inline constexpr VtuArray vtu_type{"type", "UInt8", 1, 1};
inline constexpr VtuArray vtu_velocity{"velocity", "Float32", 3, 4};
inline constexpr VtuArray vtu_density{"density", "Float32", 1, 4};
inline constexpr VtuArray vtu_pressure{"pressure", "Float32", 1, 4};
inline constexpr VtuArray vtu_position{"position", "Float64", 3, 8};

// read_vtu of a .pvtu: its pieces, concatenated in the index's order (io/pvtu.cpp).
Particles read_pvtu(const std::string& path, FrameFields* present);

}  // namespace clsph::io
