// Marching cubes numbering, shared by the kernels (marching_cubes.cl) and the host's table
// generator (host/src/surface/mc_table.cpp) and tests.
//   corner c = 0..7 of a cube: (x, y, z) = (c & 1, (c >> 1) & 1, (c >> 2) & 1)
//   edge e = 0..11: 0-3 along x at (y, z) = (e & 1, e >> 1); 4-7 along y at (x, z) = ((e-4) & 1,
//   (e-4) >> 1); 8-11 along z at (x, y) = ((e-8) & 1, (e-8) >> 1)
//   case = sum over corners of (value >= iso) << c: "inside" is value >= iso
//   table: per case, CLSPH_MC_MAX_TRIANGLES triangles of 3 edges each; unused entries are 255
#ifndef CLSPH_MARCHING_CUBES_H
#define CLSPH_MARCHING_CUBES_H

#define CLSPH_MC_MAX_TRIANGLES 8
#define CLSPH_MC_CASE_ENTRIES (3 * CLSPH_MC_MAX_TRIANGLES)

#endif
