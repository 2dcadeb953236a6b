// A test interaction on the shared neighbour loop: per particle, the number of neighbours within
// the support (itself included), the sum of q_j * w(r) with w(r) = (1 - r^2/R^2)^3, and, for
// sampled particles, the list of neighbour ids. Proves both iteration schemes against brute force.
#include "shared.h"

typedef struct {
    float4 pos;
    float q;
    uint id;
} ProbeNeighbour;

typedef struct {
    uint count;
    float sum;
    int slot;
} ProbeState;

#define INTERACTION_NAME neighbour_probe
#define INTERACTION_ARGS                                                                             \
    , __global const float *quantity, __global const uint *ids, __global const int *sample_slot,    \
        const uint max_list, __global uint *list, __global uint *count_out, __global float *sum_out
#define NEIGHBOUR_T ProbeNeighbour
#define LOAD_NEIGHBOUR(nb, j) \
    do {                      \
        (nb).q = quantity[j]; \
        (nb).id = ids[j];     \
    } while (0)
#define STATE_T ProbeState
#define STATE_INIT(st, i, self) \
    do {                        \
        (st).count = 0u;        \
        (st).sum = 0.0f;        \
        (st).slot = sample_slot[i]; \
    } while (0)
#define PAIR(st, self, nb, i, j, rij, r2)                                          \
    do {                                                                           \
        const float u = 1.0f - (r2) / support2;                                    \
        (st).sum += (nb).q * u * u * u;                                            \
        if ((st).slot >= 0 && (st).count < max_list)                               \
            list[(uint)(st).slot * max_list + (st).count] = (nb).id & CLSPH_ID_MASK; \
        (st).count += 1u;                                                          \
    } while (0)
#define STATE_STORE(st, i)          \
    do {                            \
        count_out[i] = (st).count;  \
        sum_out[i] = (st).sum;      \
    } while (0)

#include "neighbour_loop.h"
