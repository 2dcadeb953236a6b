// Structs and constants shared by host code and kernels: defined once, read by both compilers.
#ifndef CLSPH_SHARED_H
#define CLSPH_SHARED_H

#ifdef __OPENCL_VERSION__
typedef uint cl_uint_t;
#else
#include <cstdint>
typedef std::uint32_t cl_uint_t;
#endif

// Key given to particles outside the domain: sorts after every valid cell key.
#define CLSPH_INVALID_KEY 0xffffffffu

#endif
