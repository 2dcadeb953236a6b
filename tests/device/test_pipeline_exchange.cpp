// The exchange's edge layout on every device against the host: arrivals around a sorted middle, the
// edges sorted alone (the rest of the cell pipeline: test_pipeline.cpp).
#include "pipeline_support.hpp"
#include "device/cell_pipeline.hpp"
#include "clsph/error.hpp"
#include "support/test_devices.hpp"

#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <map>
#include <set>

using namespace clsph;
using namespace clsph::device;
using namespace pipeline_test;

TEST_SUITE("pipeline") {
TEST_CASE("exchange with overlap: arrivals around a sorted middle, edges sorted alone, match the host") {
    // The layout the overlapped exchange builds (host/src/multi/slab_driver.cpp): the kept
    // particles sorted at an offset (ghosts and leavers dropped to the end of that block), arrivals
    // from the left below, from the right above, then only the edges sorted. The result must be
    // exactly the kept-in-range particles and the arrivals, sorted, each with its own data.
    const Box box{{0.0, 0.0, 0.0}, {3.0, 1.0, 1.0}};
    for (auto* d : test::devices()) {
        CAPTURE(d->label());
        auto gen = test::rng(131);
        Grid grid(box, 0.1);
        const GridParams g = grid.params();
        REQUIRE(grid.axis(0) == 0);
        auto column_key = [&](std::size_t c) { return static_cast<std::uint32_t>(c) << g.shift_s; };
        auto column_of = [&](std::uint32_t key) { return static_cast<std::size_t>(key >> g.shift_s); };
        // This device needs columns [4, 26); its old slab was [5, 25): arrivals from the left lie
        // below column 6, from the right at 24 and above.
        const std::size_t lo = 4, hi = 26, b_left = 6, b_right = 24;
        auto in_columns = [&](std::size_t n, double c0, double c1) {
            return random_points(gen, n, Box{{c0 * 0.1, 0.0, 0.0}, {c1 * 0.1, 1.0, 1.0}});
        };
        auto kept_x = in_columns(900, 4, 26);
        const auto leavers = in_columns(60, 1, 4), leavers_right = in_columns(60, 26, 29);
        kept_x.insert(kept_x.end(), leavers.begin(), leavers.end());
        kept_x.insert(kept_x.end(), leavers_right.begin(), leavers_right.end());
        std::shuffle(kept_x.begin(), kept_x.end(), gen);
        const auto ghosts_x = in_columns(150, 4, 26);  // stale ghosts: valid keys in pos.w, dropped anyway
        const auto left_all = in_columns(120, 4, 6), right_all = in_columns(110, 24, 26);
        // Arrivals on both sides, on one side only (the other edge is skipped), and the edges
        // sorted on every key bit instead of the few that vary within each (EdgeSort's bounds).
        struct Variant { bool left, right, bounded; };
        for (const Variant v : {Variant{true, true, true}, Variant{true, true, false}, Variant{false, true, true},
                                Variant{true, false, true}}) {
            CAPTURE(v.left);
            CAPTURE(v.right);
            CAPTURE(v.bounded);
            const std::vector<std::array<double, 3>> none;
            const auto& left_x = v.left ? left_all : none;
            const auto& right_x = v.right ? right_all : none;

            std::vector<std::array<double, 3>> held = kept_x;
            held.insert(held.end(), ghosts_x.begin(), ghosts_x.end());
            Particles held_p = make_particles(held);
            const std::size_t n_kept = kept_x.size(), n_held = held.size();
            // Arrivals: ids of their own, packed as the inbox holds them.
            std::vector<float> a_pos, a_vel, a_acc;
            std::vector<std::uint32_t> a_id;
            std::map<std::uint32_t, std::array<float, 8>> expected;  // id -> pos (offset, key), velrho
            auto add_expected = [&](std::uint32_t id, std::uint32_t key, const std::array<float, 3>& off, const std::array<float, 4>& vr) {
                float k;
                std::memcpy(&k, &key, sizeof k);
                expected[id] = {off[0], off[1], off[2], k, vr[0], vr[1], vr[2], vr[3]};
            };
            for (const auto* side : {&left_x, &right_x})
                for (const auto& x : *side) {
                    std::array<float, 3> off{};
                    const std::uint32_t key = grid.locate(x, off);
                    const std::uint32_t id = 100000 + static_cast<std::uint32_t>(a_id.size());
                    const std::array<float, 4> vr{0.5f, static_cast<float>(id % 7), -1.0f, 990.0f + static_cast<float>(id % 11)};
                    float k;
                    std::memcpy(&k, &key, sizeof k);
                    a_pos.insert(a_pos.end(), {off[0], off[1], off[2], k});
                    a_vel.insert(a_vel.end(), vr.begin(), vr.end());
                    a_acc.insert(a_acc.end(), {0.0f, 0.0f, -9.81f, 0.0f});
                    a_id.push_back(id);
                    add_expected(id, key, off, vr);
                }
            const std::size_t n_left = left_x.size(), n_right = right_x.size();
            // The canonical order: [left arrivals | kept, in their held order | right arrivals] sorted stably.
            std::vector<std::pair<std::uint32_t, std::uint32_t>> canonical;  // (key, id)
            for (std::size_t j = 0; j < a_id.size(); ++j) {
                std::uint32_t key;
                std::memcpy(&key, &a_pos[4 * j + 3], sizeof key);
                if (j == n_left) canonical.resize(canonical.size() + n_kept, {0xffffffffu, 0u});  // the kept: below
                canonical.push_back({key, a_id[j]});
            }
            if (n_right == 0) canonical.resize(canonical.size() + n_kept, {0xffffffffu, 0u});
            std::size_t n_in_range = 0, x_exact = 0, y_exact = 0;
            for (std::size_t i = 0; i < n_kept; ++i) {
                std::array<float, 3> off{};
                const std::uint32_t key = grid.locate(kept_x[i], off);
                const std::size_t c = column_of(key);
                canonical[n_left + i] = {c < lo || c >= hi ? 0xffffffffu : key, held_p.id[i]};
                if (c < lo || c >= hi) continue;
                ++n_in_range;
                x_exact += c < b_left;
                y_exact += c >= b_right;
                add_expected(held_p.id[i], key, off, {held_p.velocity[i][0], held_p.velocity[i][1], held_p.velocity[i][2], held_p.density[i]});
            }
            // The bounds the exchange uses are upper bounds: take a few more than needed.
            std::uniform_int_distribution<std::size_t> extra(0, 20);
            const std::size_t x_bound = std::min(n_in_range, x_exact + extra(gen)), y_bound = std::min(n_in_range, y_exact + extra(gen));
            // As the exchange plans them (Exchange::plan): a side without arrivals has no edge.
            const std::size_t S = n_left, left = n_left > 0 ? S + x_bound : 0;
            const std::size_t right = S + n_in_range - (n_right > 0 ? y_bound : 0);
            const std::size_t end = n_right > 0 ? S + n_held + n_right : right, valid = n_left + n_in_range + n_right;
            REQUIRE(left < right);
            std::stable_sort(canonical.begin(), canonical.end(), [](const auto& a, const auto& b) { return a.first < b.first; });

            // The edges go through the reorder scratch, four arrays side by side (the exchange checks
            // the same before it takes this path).
            const std::size_t m = left + (end - right);
            ParticleStore ps(*d, grid, std::max(end, CellPipeline::edge_scratch_bytes(m) / (4 * sizeof(float)) + 1));
            ps.upload(held_p);
            d->fill(ps.scratch, kPoison, 4 * ps.capacity());
            CellPipeline cp(*d, grid);
            const KeyRange needed{column_key(lo), column_key(hi)};
            cp.enqueue_sort_keys(ps, SortSelection{n_held, 0, n_kept, n_held, needed, false});
            cp.enqueue_reorder(ps, n_held, S);
            d->fill(ps.id, kPoison, S);  // the room below must be filled by the arrivals
            ParticleArrays inbox;
            inbox.allocate(*d, n_left + n_right, "test inbox");
            d->write(inbox.pos, a_pos.data(), a_pos.size());
            d->write(inbox.velrho, a_vel.data(), a_vel.size());
            d->write(inbox.accel, a_acc.data(), a_acc.size());
            d->write(inbox.id, a_id.data(), a_id.size());
            copy_particles(*d, inbox, 0, ps, 0, n_left);
            copy_particles(*d, inbox, n_left, ps, S + n_held, n_right);
            EdgeSort edges{left, right, end, S + n_in_range, S + n_held, end > right ? end - right - (n_held - n_in_range) : 0, needed};
            if (v.bounded) {  // the old slab [5, 25): arrivals below column 6 and from column 24
                edges.left_top = column_key(b_left);
                edges.right_bottom = column_key(b_right);
            }
            cp.enqueue_edge_sort(ps, edges);
            cp.enqueue_rekey(ps, valid);
            std::vector<float> pos(4 * valid), vel(4 * valid);
            std::vector<std::uint32_t> ids(valid), keys(valid);
            d->read(ps.pos, pos.data(), 4 * valid);
            d->read(ps.velrho, vel.data(), 4 * valid);
            d->read(ps.id, ids.data(), valid);
            d->read(ps.keys, keys.data(), valid);

            REQUIRE(expected.size() == valid);
            std::set<std::uint32_t> seen;
            std::size_t wrong = 0, unsorted = 0;
            for (std::size_t i = 0; i < valid; ++i) {
                const std::uint32_t id = ids[i] & CLSPH_ID_MASK;
                std::uint32_t key;
                std::memcpy(&key, &pos[4 * i + 3], sizeof key);
                if (i > 0 && keys[i] < keys[i - 1]) ++unsorted;
                auto it = expected.find(id);
                if (keys[i] != key || it == expected.end() || !seen.insert(id).second ||
                    std::memcmp(it->second.data(), &pos[4 * i], 4 * sizeof(float)) != 0 ||
                    std::memcmp(it->second.data() + 4, &vel[4 * i], 4 * sizeof(float)) != 0)
                    ++wrong;
            }
            INFO(n_left << " + " << n_in_range << " + " << n_right << " particles, edges [0, " << left << ") and [" << right
                        << ", " << end << ")");
            CHECK(wrong == 0);
            CHECK(unsorted == 0);
            CHECK(seen.size() == valid);
            // Within each cell too, the order one device would give them (the results' bitwise sameness
            // on any device count rests on it).
            std::size_t misplaced = 0;
            for (std::size_t i = 0; i < valid; ++i) misplaced += (ids[i] & CLSPH_ID_MASK) != (canonical[i].second & CLSPH_ID_MASK);
            CHECK(misplaced == 0);
        }
    }
}
}

TEST_SUITE("pipeline") {
TEST_CASE("the interior's tables, built while the arrivals travel, give its cells the merged tables' rows") {
    // The halo overlapped with the interior (multi/exchange.cpp, docs/multi_device.md): the kept
    // particles sorted at an offset, the room below them still waiting for the left arrivals
    // (poisoned here), tables over both with key 0 for the room, bounded (nothing read back).
    // Every particle of the interior columns (two inside the old slab [5, 25)) must get the cell and
    // the rows the tables of the merged particles give it; the count must be at most the merged
    // count + 1, the rule by which the exchange knows the tables held every cell, and where the
    // tables were too small for them, that rule must say so.
    const Box box{{0.0, 0.0, 0.0}, {3.0, 1.0, 1.0}};
    for (auto* d : test::devices()) {
        CAPTURE(d->label());
        auto gen = test::rng(137);
        Grid grid(box, 0.1);
        const GridParams g = grid.params();
        REQUIRE(grid.axis(0) == 0);
        auto column_key = [&](std::size_t c) { return static_cast<std::uint32_t>(c) << g.shift_s; };
        auto in_columns = [&](std::size_t n, double c0, double c1) {
            return random_points(gen, n, Box{{c0 * 0.1, 0.0, 0.0}, {c1 * 0.1, 1.0, 1.0}});
        };
        // Kept particles in columns [4, 26), arrivals from the left below column 6 and from the
        // right at 24 and above; the interior [7, 23).
        const auto kept_x = in_columns(2000, 4, 26), left_x = in_columns(150, 4, 6), right_x = in_columns(140, 24, 26);
        const std::uint32_t lo = column_key(7), hi = column_key(23);
        const std::size_t S = left_x.size(), n_kept = kept_x.size();
        const KeyRange all{0, g.invalid_key};
        std::set<std::uint32_t> kept_cells;
        for (const auto& x : kept_x) {
            std::array<float, 3> off{};
            kept_cells.insert(grid.locate(x, off));
        }

        // The merged particles, sorted as one device would: the reference tables.
        std::vector<std::array<double, 3>> merged = left_x;
        merged.insert(merged.end(), kept_x.begin(), kept_x.end());
        merged.insert(merged.end(), right_x.begin(), right_x.end());
        ParticleStore ref(*d, grid, merged.size() + 16);
        ref.upload(make_particles(merged));
        CellPipeline cref(*d, grid);
        cref.enqueue_sort(ref, SortSelection{merged.size(), 0, merged.size(), merged.size(), all, true});
        const std::size_t k_ref = cref.build_tables(ref, merged.size());
        const std::vector<std::size_t> at_ref = cref.locate(ref, merged.size(), {lo, hi});
        const std::size_t first = at_ref[0], last = at_ref[1];
        REQUIRE(last > first);

        // The kept particles alone, sorted into [S, S + n_kept), the room below poisoned; tables
        // with room for the merged count + 1, then with the least room there is.
        for (const bool roomy : {true, false}) {
            CAPTURE(roomy);
            ParticleStore ps(*d, grid, merged.size() + 16);
            ps.upload(make_particles(kept_x));
            CellPipeline cp(*d, grid);
            cp.set_edges_apart(true);
            if (roomy) cp.reserve_cells(k_ref + 1);
            cp.enqueue_sort_keys(ps, SortSelection{n_kept, 0, n_kept, n_kept, all, true});
            ps.reserve(merged.size());
            cp.enqueue_reorder(ps, n_kept, S);
            d->fill(ps.pos, kPoison, 4 * S);
            d->fill(ps.vals, kPoison, ps.capacity());
            cp.enqueue_interior_tables(ps, S + n_kept, S);
            std::uint32_t count[2] = {0, 0};
            d->read(cp.cell_count(), count, 2);
            const std::size_t cap = cp.interior_capacity();
            INFO(count[1] << " cells found, the tables hold " << cap << "; merged: " << k_ref);
            CHECK(count[1] == kept_cells.size() + 1);  // the hole's cell and the kept particles'
            CHECK(count[1] <= k_ref + 1);
            if (!roomy) {
                // The exchange's rule (merged count + 1 within the capacity) never trusts tables that overflowed.
                CHECK((count[1] <= cap || k_ref + 1 > cap));
                if (count[1] <= cap) {
                    MESSAGE("the least room held them all: the overflow was not exercised");
                    continue;
                }
                // And tables that overflowed are safe to read: the interior's pass runs on them before
                // anyone knows (it read past the arrays, and crashed pocl, before they were).
                const std::size_t n = S + n_kept, rows = grid.rows();
                std::vector<std::uint32_t> cell(n), starts(cap + 1), rg(2 * rows * cap);
                d->read(ps.vals, cell.data(), n);
                d->read(cp.cell_start(), starts.data(), cap + 1);
                d->read(cp.ranges(), rg.data(), rg.size());
                CHECK(count[0] == cap);
                CHECK(std::all_of(cell.begin(), cell.end(), [&](std::uint32_t c) { return c < cap; }));
                CHECK(std::all_of(starts.begin(), starts.end(), [&](std::uint32_t x) { return x <= n; }));
                CHECK(starts[cap] == n);
                CHECK(std::all_of(rg.begin(), rg.end(), [&](std::uint32_t x) { return x <= n; }));
                continue;
            }
            REQUIRE(count[1] <= cap);

            // Per interior particle: its key, its cell's key and every row against the reference.
            const std::size_t rows = grid.rows(), n = merged.size(), k = cap;
            std::vector<std::uint32_t> keys(n), keys_ref(n), cell(n), cell_ref(n), ck(k), ck_ref(k_ref);
            std::vector<std::uint32_t> rg(2 * rows * k), rg_ref(2 * rows * k_ref);
            d->read(ps.keys, keys.data(), S + n_kept);
            d->read(ref.keys, keys_ref.data(), n);
            d->read(ps.vals, cell.data(), S + n_kept);
            d->read(ref.vals, cell_ref.data(), n);
            d->read(cp.cell_key(), ck.data(), k);
            d->read(cref.cell_key(), ck_ref.data(), k_ref);
            d->read(cp.ranges(), rg.data(), rg.size());
            d->read(cref.ranges(), rg_ref.data(), rg_ref.size());
            std::size_t wrong_key = 0, wrong_cell = 0, wrong_rows = 0;
            for (std::size_t i = first; i < last; ++i) {
                wrong_key += keys[i] != keys_ref[i];
                const std::uint32_t c = cell[i], c_ref = cell_ref[i];
                if (c >= count[0] || ck[c] != ck_ref[c_ref]) {
                    ++wrong_cell;
                    continue;
                }
                for (std::size_t r = 0; r < 2 * rows; ++r) wrong_rows += rg[2 * rows * c + r] != rg_ref[2 * rows * c_ref + r];
            }
            INFO("interior particles [" << first << ", " << last << ") of " << n);
            CHECK(wrong_key == 0);
            CHECK(wrong_cell == 0);
            CHECK(wrong_rows == 0);
        }
    }
}
}
