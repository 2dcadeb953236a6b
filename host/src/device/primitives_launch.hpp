// Helpers the primitives share: argument binding, buffer capacity checks and the choice of a
// work-group size every kernel of a primitive accepts. Internal to host/src/device/primitives_*.
#pragma once
#include "cl/device.hpp"
#include "cl/kernel_args.hpp"

#include <cstddef>
#include <functional>
#include <string>
#include <vector>

namespace clsph::device {

// n as a kernel's uint argument; throws clsph::Error when it does not fit (kernels index with uint).
cl_uint as_uint(std::size_t n);

using cl_rt::set_args;  // cl/kernel_args.hpp

// Throws clsph::Error naming `what` when `buffer` holds fewer than `elements` uints.
void require_elements(const std::string& what, const cl_rt::Buffer& buffer, std::size_t elements);

// Grows `buffer` to at least `bytes` (contents are not kept); scratch never shrinks.
void ensure_capacity(cl_rt::Device& dev, cl_rt::Buffer& buffer, std::size_t bytes, const std::string& what);

// Picks the work-group size: `requested` (a power of two) or, if 0, the device's largest power of
// two <= cap. `build(wg)` builds the kernels for that size and returns them; when one of them
// accepts fewer work-items (a driver may cap a kernel that uses many registers), the size is
// halved and the kernels rebuilt. Returns the size every returned kernel accepts.
std::size_t resolve_work_group(cl_rt::Device& dev, std::size_t requested, std::size_t cap,
                               const std::function<std::vector<cl::Kernel*>(std::size_t)>& build);

}  // namespace clsph::device
