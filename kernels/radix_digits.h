// The radix sort's digit counts of one tile (kernels/radix_sort.cl, sort_histogram), shared with
// the step ahead's first launch, which counts the first pass's digits of the keys it makes
// (kernels/drift_histogram.cl). Needs ITEMS (pairs per work-item) defined at build time.
#ifndef CLSPH_RADIX_DIGITS_H
#define CLSPH_RADIX_DIGITS_H

// Adds this work-item's ITEMS keys (the blocked arrangement: tile positions lid * ITEMS + j, those
// below `count` only) to hist[digit], the digit being (key >> shift) & mask. One atomic per run of
// equal digits: keys that are nearly sorted already (particle cell keys one step after the last
// sort) would otherwise all hammer the same counter.
inline void count_digits(const uint* key, const uint count, const uint shift, const uint mask, __local uint* hist) {
    const uint first = get_local_id(0) * ITEMS;
    uint run_digit = (key[0] >> shift) & mask;
    uint run = 0;
    for (uint j = 0; j < ITEMS; ++j) {
        if (first + j < count) {
            const uint d = (key[j] >> shift) & mask;
            if (d != run_digit) {
                if (run) atomic_add(&hist[run_digit], run);
                run_digit = d;
                run = 0;
            }
            ++run;
        }
    }
    if (run) atomic_add(&hist[run_digit], run);
}

#endif
