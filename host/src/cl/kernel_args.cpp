#include "cl/kernel_args.hpp"

#include "clsph/error.hpp"

#include <limits>
#include <string>

namespace clsph::cl_rt {

cl_uint checked_uint(std::size_t n, const char* what) {
    if (n > std::numeric_limits<cl_uint>::max())
        throw Error(std::string(what) + " of " + std::to_string(n) + " does not fit the kernels' 32-bit unsigned integers");
    return static_cast<cl_uint>(n);
}

}  // namespace clsph::cl_rt
