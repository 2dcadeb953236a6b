#include "surface/mc_table.hpp"

#include "clsph/error.hpp"

#include <algorithm>
#include <cmath>
#include <vector>

namespace clsph::surface {

std::array<int, 3> corner_offset(int c) { return {c & 1, (c >> 1) & 1, (c >> 2) & 1}; }

std::array<int, 2> edge_corners(int e) {
    if (e < 4) {  // along x at (y, z)
        const int y = e & 1, z = e >> 1;
        return {(y << 1) | (z << 2), 1 | (y << 1) | (z << 2)};
    }
    if (e < 8) {  // along y at (x, z)
        const int x = (e - 4) & 1, z = (e - 4) >> 1;
        return {x | (z << 2), x | 2 | (z << 2)};
    }
    const int x = (e - 8) & 1, y = (e - 8) >> 1;  // along z at (x, y)
    return {x | (y << 1), x | (y << 1) | 4};
}

namespace {

int edge_between(int a, int b) {
    for (int e = 0; e < 12; ++e) {
        const auto c = edge_corners(e);
        if ((c[0] == a && c[1] == b) || (c[0] == b && c[1] == a)) return e;
    }
    return -1;
}

using Vec = std::array<double, 3>;
Vec midpoint(int e) {
    const auto c = edge_corners(e);
    const auto a = corner_offset(c[0]), b = corner_offset(c[1]);
    return {0.5 * (a[0] + b[0]), 0.5 * (a[1] + b[1]), 0.5 * (a[2] + b[2])};
}

// The four corners of face f (axis f / 2 fixed at f % 2) in cyclic order.
std::array<int, 4> face_corners(int f) {
    const int axis = f / 2, side = f % 2;
    const int u = (axis + 1) % 3, v = (axis + 2) % 3;
    std::array<int, 4> out{};
    const int cyc[4][2] = {{0, 0}, {1, 0}, {1, 1}, {0, 1}};
    for (int k = 0; k < 4; ++k) {
        int bits = side << axis;
        bits |= cyc[k][0] << u;
        bits |= cyc[k][1] << v;
        out[k] = bits;
    }
    return out;
}

Vec corner_pos(int c) {
    const auto o = corner_offset(c);
    return {double(o[0]), double(o[1]), double(o[2])};
}

Vec cross(const Vec& a, const Vec& b) { return {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]}; }
double dot(const Vec& a, const Vec& b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }

// Orders a segment (edges a, b) on face f so that its direction is s x N, where N is the face's
// outward normal and s points from the segment's inside corners to its outside ones. A neighbour
// cube sees the same face with -N, so it runs the shared segment the other way: the triangles on
// both sides of every mesh edge agree in orientation.
std::array<int, 2> directed(int f, int a, int b, const Vec& inside_to_outside) {
    Vec n{0, 0, 0};
    n[f / 2] = f % 2 ? 1.0 : -1.0;
    const Vec d = cross(inside_to_outside, n);
    const Vec ma = midpoint(a), mb = midpoint(b);
    const Vec ab{mb[0] - ma[0], mb[1] - ma[1], mb[2] - ma[2]};
    return dot(ab, d) >= 0 ? std::array<int, 2>{a, b} : std::array<int, 2>{b, a};
}

CaseTable build() {
    CaseTable t{};
    for (auto& row : t) row.fill(255);
    for (int cs = 0; cs < 256; ++cs) {
        auto inside = [&](int c) { return ((cs >> c) & 1) != 0; };
        // Directed segments on the six faces, between crossing edges.
        std::vector<std::array<int, 2>> segments;
        for (int f = 0; f < 6; ++f) {
            const auto fc = face_corners(f);
            int crossing[4], n = 0;
            for (int k = 0; k < 4; ++k)
                if (inside(fc[k]) != inside(fc[(k + 1) % 4])) crossing[n++] = k;  // edge fc[k]-fc[k+1]
            auto edge_of = [&](int k) { return edge_between(fc[k], fc[(k + 1) % 4]); };
            if (n == 2) {
                Vec in{0, 0, 0}, out{0, 0, 0};  // mean inside and mean outside corner of the face
                int n_in = 0;
                for (int k = 0; k < 4; ++k) {
                    const Vec p = corner_pos(fc[k]);
                    n_in += inside(fc[k]) ? 1 : 0;
                    for (int d = 0; d < 3; ++d) (inside(fc[k]) ? in : out)[d] += p[d];
                }
                Vec s{0, 0, 0};  // from the face's inside corners to its outside ones
                for (int d = 0; d < 3; ++d) s[d] = out[d] / (4 - n_in) - in[d] / n_in;
                segments.push_back(directed(f, edge_of(crossing[0]), edge_of(crossing[1]), s));
            } else if (n == 4) {  // two inside corners on a diagonal: cut each off
                Vec centre{0, 0, 0};
                for (int k = 0; k < 4; ++k)
                    for (int d = 0; d < 3; ++d) centre[d] += 0.25 * corner_pos(fc[k])[d];
                for (int k = 0; k < 4; ++k)
                    if (inside(fc[k])) {
                        const Vec c = corner_pos(fc[k]);
                        segments.push_back(directed(f, edge_of((k + 3) % 4), edge_of(k),
                                                    {centre[0] - c[0], centre[1] - c[1], centre[2] - c[2]}));
                    }
            }
        }
        // Chain the directed segments into loops: at every crossing edge one segment ends and
        // another begins (each crossing edge is on exactly two faces).
        std::vector<bool> used(segments.size(), false);
        int tri = 0;
        for (std::size_t s0 = 0; s0 < segments.size(); ++s0) {
            if (used[s0]) continue;
            std::vector<int> loop{segments[s0][0]};
            int at = segments[s0][1];
            used[s0] = true;
            while (at != loop.front()) {
                loop.push_back(at);
                std::size_t next = segments.size();
                for (std::size_t s = 0; s < segments.size(); ++s)
                    if (!used[s] && segments[s][0] == at) next = s;
                if (next == segments.size()) throw Error("marching cubes: case table generation found an open loop");
                used[next] = true;
                at = segments[next][1];
            }
            for (std::size_t k = 1; k + 1 < loop.size(); ++k) {
                if (tri >= CLSPH_MC_MAX_TRIANGLES) throw Error("marching cubes: case table overflow");
                t[cs][3 * tri] = static_cast<std::uint8_t>(loop[0]);
                t[cs][3 * tri + 1] = static_cast<std::uint8_t>(loop[k]);
                t[cs][3 * tri + 2] = static_cast<std::uint8_t>(loop[k + 1]);
                ++tri;
            }
        }
    }
    return t;
}

}  // namespace

const CaseTable& case_table() {
    static const CaseTable table = build();  // constant data, built once
    return table;
}

}  // namespace clsph::surface
