// The time step chosen on the device (docs/multi_device.md, "The step ahead"): the kick's
// per-group reductions become the next CFL step, clamped to the next event, with no host round
// trip. The arithmetic is the host's (simulation.cpp, next_dt and run_until) in double, whose
// divide and sqrt OpenCL rounds correctly, so both paths take bitwise the same steps.
//
// clock[0] time before the step under way      clock[1] its dt (dt_f: the same as float)
// clock[2] the next CFL step, not yet clamped
// clock[3] the event the run lands on (a frame, --until; +inf: none)
// clock[4] run.list_buffer: how far any particle may have moved since the cell tables were built
//          (multi/list_schedule.hpp, the same bound in the same arithmetic)
// *halt    non-zero: every kernel that changes the state does nothing (an event reached, the cell
//          tables overflowed, a particle failed the checks); the host clears it
// records  a ring of step records, one per slot of the host's ring (StepRecord::from)
#pragma OPENCL EXTENSION cl_khr_fp64 : enable
// No a * b + c fused into one rounding: the host's arithmetic is separate multiplies and adds.
#pragma OPENCL FP_CONTRACT OFF

#define HALT_EVENT 1u
#define HALT_BAD 2u
#define HALT_CELLS 4u
#define HALT_LISTS 8u
#define NO_PARTICLE 0xffffffffu

// Several devices (docs/multi_device.md, "The step ahead on several devices"): this device's part
// of what every device's end_step needs from all of them, at sums[at]: max |v|^2 and max |a|^2 over
// its kick's groups, and 1 where it holds a failed particle. Maxima are exact in any order.
#ifndef CLOCK_WG
#define CLOCK_WG 1
#endif
__kernel void step_sums(const uint groups, __global const float4* partials, __global const uint* bad,
                        __global float4* sums, const uint at) {
    __local float2 m[CLOCK_WG];
    const uint lid = get_local_id(0);
    float2 mine = (float2)(0.0f, 0.0f);
    for (uint g = lid; g < groups; g += CLOCK_WG) {
        const float4 p = partials[g];
        mine = (float2)(fmax(mine.x, p.x), fmax(mine.y, p.y));
    }
    m[lid] = mine;
    barrier(CLK_LOCAL_MEM_FENCE);
    if (lid != 0u) return;
    for (uint k = 1u; k < CLOCK_WG; ++k) mine = (float2)(fmax(mine.x, m[k].x), fmax(mine.y, m[k].y));
    sums[at] = (float4)(mine.x, mine.y, *bad == NO_PARTICLE ? 0.0f : 1.0f, 0.0f);
}

// After the kick: the reductions over its work-groups, time advanced, the next CFL step and the
// next step's dt (the CFL step shortened to land on the event, as run_until does on the host;
// Physics::set_clock computes the first one on the host), the record, and the counters reset for
// the next step (so the host enqueues no fills). One work-group of CLOCK_WG items: they stage the
// partials in local memory a tile at a time (one work-item reading them from global memory one
// after another waited on each load: 26 us a step on the H200), and the first item sums each tile
// in the partials' order, as before, so the sums are bitwise the same.
#ifndef CLOCK_WG
#define CLOCK_WG 1
#endif
__kernel void end_step(const uint groups, const double cfl, const double h, const double c0, const double fixed_dt,
                       const double dt_floor, const double dt_viscous, const double half_buffer,
                       __global const float4* partials, __global uint* bad, __global const uint* ids,
                       __global const float4* velrho, __global uint* settle_counters,
                       __global const uint* cell_count, __global double* clock, __global float* dt_f,
                       __global uint* halt, __global double* records, const uint slot,
                       __global const float4* sums, const uint slabs) {
    __local float4 tile[CLOCK_WG];
    const uint lid = get_local_id(0);
    __global double* record = records + slot * 17u;  // StepRecord::kDoubles
    const uint halted = *halt;
    if (lid == 0u) {
        record[15] = (double)cell_count[1];
        record[6] = (double)halted;
    }
    if (halted != 0u) return;  // this step changed nothing: the host redoes or drops it (uniform)
    double vmax2 = 0.0, amax2 = 0.0, energy = 0.0, fluid = 0.0;
    for (uint base = 0; base < groups; base += CLOCK_WG) {
        if (base + lid < groups) tile[lid] = partials[base + lid];
        barrier(CLK_LOCAL_MEM_FENCE);
        if (lid == 0u) {
            const uint n = min((uint)CLOCK_WG, groups - base);
            for (uint g = 0; g < n; ++g) {
                const float4 p = tile[g];
                vmax2 = fmax(vmax2, (double)p.x);
                amax2 = fmax(amax2, (double)p.y);
                energy += (double)p.z;
                fluid += (double)(ulong)p.w;
            }
        }
        barrier(CLK_LOCAL_MEM_FENCE);
    }
    if (lid != 0u) return;
    const uint b = *bad;
    double gv = vmax2, ga = amax2;  // over every device
    bool failed = b != NO_PARTICLE;
    for (uint s = 0u; s < slabs; ++s) {
        const float4 q = sums[slot * slabs + s];
        gv = s == 0u ? (double)q.x : fmax(gv, (double)q.x);
        ga = s == 0u ? (double)q.y : fmax(ga, (double)q.y);
        failed = failed || q.z != 0.0f;
    }
    double next = fixed_dt;
    if (!(fixed_dt > 0.0)) {
        // Monaghan's force and acoustic (CFL) limits: dt = cfl min(sqrt(h/|a|max), h/(c0 + |v|max)).
        const double amax = sqrt(ga), vmax = sqrt(gv);
        const double dt_force = amax > 0.0 ? sqrt(h / amax) : INFINITY;
        const double dt_sound = h / (c0 + vmax);
        next = fmin(cfl * fmin(dt_force, dt_sound), dt_viscous);  // dt_viscous: infinity, or 0.125 h^2 / nu
    }
    const double t = clock[0] + clock[1];
    clock[0] = t;
    clock[2] = next;
    const double dt_next = fmin(next, fmax(clock[3] - t, 1e-12));
    record[0] = t;
    record[1] = clock[1];  // before it becomes the next step's
    record[2] = vmax2;
    record[3] = amax2;
    record[4] = energy;
    record[5] = next;
    record[7] = b == NO_PARTICLE ? -1.0 : (double)b;
    if (b != NO_PARTICLE) {
        const float4 vr = velrho[b];
        record[8] = (double)ids[b];
        record[9] = (double)vr.x;
        record[10] = (double)vr.y;
        record[11] = (double)vr.z;
        record[12] = (double)vr.w;
    }
    record[13] = (double)settle_counters[0];
    record[14] = (double)settle_counters[1];
    record[16] = fluid;
    clock[1] = dt_next;
    dt_f[0] = (float)dt_next;
    settle_counters[0] = settle_counters[1] = settle_counters[2] = 0u;
    *bad = NO_PARTICLE;
    // A failed particle or a collapsed step (the host reports both): nothing after it may change
    // the state the host stops at.
    if (failed || next < dt_floor) *halt = HALT_BAD;
    else if (!(t < clock[3] - 1e-12)) *halt = HALT_EVENT;
    else if (half_buffer > 0.0) {
        // The next step's bound (ListSchedule::due): (|v| + |a| dt / 2) dt, a relative 1e-6 more.
        const double moved = clock[4] + (sqrt(gv) + 0.5 * sqrt(ga) * dt_next) * dt_next * (1.0 + 1e-6);
        if (moved < half_buffer) clock[4] = moved;
        else *halt = HALT_LISTS;  // NaN included
    }
}
