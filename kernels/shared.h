// Structs and constants shared by host code and kernels: defined once, read by both compilers.
// Only 4-byte members, so host and device layouts agree without padding rules.
#ifndef CLSPH_SHARED_H
#define CLSPH_SHARED_H

#ifdef __OPENCL_VERSION__
typedef uint clsph_uint;
typedef float clsph_float;
#else
#include <cstdint>
typedef std::uint32_t clsph_uint;
typedef float clsph_float;
#endif

// Key given to particles outside the domain is the all-ones value of the sorted bits (GridParams
// key_bits), so it sorts after every cell key; valid keys never reach it (the b field is padded).

// The uniform grid, axes in key order: s (split axis, most significant), a, b (least significant,
// padded by one empty cell at each end so the three cells of a row never wrap into the next row).
typedef struct {
    clsph_float cell_s, cell_a, cell_b;  // cell edge per axis (>= kernel support)
    clsph_uint n_s, n_a, n_b;            // cells per axis (b without its two pad cells)
    clsph_uint shift_a, shift_s;         // key = s << shift_s | a << shift_a | (b + 1)
    clsph_uint mask_a, mask_b;           // field masks after shifting down
    clsph_float ext_s, ext_a, ext_b;     // domain extent per axis (particles beyond are outside)
    clsph_uint periodic_a;               // 1 when axis a wraps around
    clsph_uint invalid_key;              // all ones in key_bits: outside the domain
} GridParams;

// Physics constants of a run (see host/src/device/physics.cpp for how each is derived).
typedef struct {
    clsph_float h, inv_h, support2;      // smoothing length, 1/h, (2h)^2
    clsph_float kernel_norm;             // alpha_D of the 3-D kernel
    clsph_float mass;                    // particle mass rho0 dp^3 (fluid and boundary)
    clsph_float rho0, inv_rho0, eos_b;   // Tait: p = B ((rho/rho0)^7 - 1)
    clsph_float c0;                      // speed of sound
    clsph_float visc_alpha, eta2;        // Monaghan viscosity alpha, 0.01 h^2
    clsph_float visc_alpha_wall;         // the same between fluid and boundary particles
    clsph_float diffusion;               // delta h c0 (0: off)
    clsph_float hydro;                   // rho0^2 / (gamma B), for the Fourtakas hydrostatic term
    clsph_float gx, gy, gz;              // gravity
    clsph_float rho_min, rho_max;        // allowed density band (absolute)
    clsph_float visc_laminar;            // 4 nu, nu the kinematic viscosity (laminar models)
    clsph_float sps_smag, sps_blin;      // SPS: (Cs dp)^2, Cs = 0.12; (2/3) CI dp^2, CI = 0.0066
} SphParams;

// mDBC (kernels/mdbc.cl): the smallest |det| of the dimensionless correction matrix (the identity,
// det 1, for a full support) for which the first-order interpolation is used; below it, Shepard.
// A ghost node near a corner sees a quarter of its support (det ~ 0.004 at h = 1.3 dp), where the
// first-order gradient is unreliable.
#define CLSPH_MDBC_DET 1e-3f

// The particle type in the top bit of the 32-bit id word, the id in the low 31 bits (ids up to
// 2^31 - 1 = 2.1e9 particles; the type needs one bit: fluid or boundary).
#define CLSPH_TYPE_SHIFT 31u
#define CLSPH_TYPE_FLUID 0u
#define CLSPH_TYPE_BOUNDARY 1u
#define CLSPH_ID_MASK 0x7fffffffu

// Open boundaries on the devices (docs/scenes.md, inlets and outlets), boxes relative to the
// domain's min corner. An inlet's box (kernels/inlets.cl, device/inlet_zones.cpp): the buffer's
// velocity is direction * speed * factor, the factor of the lattice point nearest the particle
// along the profile's axis (factors[first + k], k = round((x - column0) / dp)).
typedef struct {
    clsph_float lo[3], hi[3];     // the box
    clsph_float direction[3];     // the flow's unit vector
    clsph_float column0, inv_dp;  // the profile's first lattice coordinate along its axis, 1/dp
    clsph_uint axis;              // the profile's axis; 3: none (every point at factor 1)
    clsph_uint columns, first;    // the profile's lattice points and where their factors start
} InletBox;

// An outlet's zone (kernels/outlets.cl, device/outlet_zones.cpp): fluid past its face `axis`
// (`upper`: the max face) within its extent across is removed; inside it, with hold 1 the density
// is `value`, with hold 2 Tait's for the hydrostatic pressure below the level z = `value`.
typedef struct {
    clsph_float lo[3], hi[3];
    clsph_uint axis, upper;
    clsph_uint hold;  // 0: nothing, 1: a density, 2: a level
    clsph_float value;
} OutletZone;

#endif
