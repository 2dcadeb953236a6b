// Binding a kernel's arguments in one call, in order: set_args(kernel, n, grid_params, pos, ...).
// Counts and indices given as std::size_t are narrowed to the kernels' uint with a check (a
// particle index past 2^32 is an error that says so, never a silent wrap); Buffers bind their
// cl::Buffer; everything else (cl_uint, float, parameter structs) binds as it is.
#pragma once
#include "cl/cl.hpp"
#include "cl/memory.hpp"

#include <cstddef>
#include <type_traits>

namespace clsph::cl_rt {

// n as a kernel's uint; throws clsph::Error naming `what` when it does not fit.
cl_uint checked_uint(std::size_t n, const char* what = "a count or index");

namespace detail {
template <class T>
decltype(auto) kernel_arg(const T& v) {
    if constexpr (std::is_same_v<T, std::size_t> && !std::is_same_v<std::size_t, cl_uint>)
        return checked_uint(v);
    else if constexpr (std::is_same_v<T, Buffer>)
        return (v.get());
    else
        return (v);
}
}  // namespace detail

template <class... Args>
void set_args(cl::Kernel& kernel, const Args&... args) {
    static_assert(((!std::is_same_v<Args, double>) && ...), "kernels take float, not double");
    static_assert(((!std::is_same_v<Args, bool>) && ...), "pass a cl_uint for a kernel's flag");
    cl_uint i = 0;
    (kernel.setArg(i++, detail::kernel_arg(args)), ...);
}

}  // namespace clsph::cl_rt
