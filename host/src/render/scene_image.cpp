#include "render/scene_image.hpp"

#include "render/rank_images.hpp"

#include "render/field.hpp"
#include "render/renderer.hpp"

#include <algorithm>
#include <cmath>
#include <memory>

namespace clsph::render {

// A box as triangles with face normals (outwards), each face a grid of kFaceCells^2 squares: the
// rasteriser gives a triangle to one work-item, so a face in two triangles covering half the
// picture would be drawn by two work-items alone (4 ms of the H200's frame, measured).
namespace {
constexpr int kFaceCells = 24;
constexpr std::array<float, 3> kWater{0.30f, 0.55f, 0.92f}, kSolid{0.62f, 0.60f, 0.58f};
constexpr std::array<std::uint8_t, 3> kBackground{246, 246, 246};
}  // namespace

TriangleMesh box_mesh(const std::vector<SolidBox>& boxes) {
    TriangleMesh m;
    for (const auto& b : boxes) {
        for (std::size_t axis = 0; axis < 3; ++axis)
            for (int side = 0; side < 2; ++side) {
                const std::size_t u = (axis + 1) % 3, v = (axis + 2) % 3;
                std::array<float, 3> n{0, 0, 0};
                n[axis] = side ? 1.0f : -1.0f;
                const auto base = static_cast<std::uint32_t>(m.positions.size());
                for (int j = 0; j <= kFaceCells; ++j)
                    for (int i = 0; i <= kFaceCells; ++i) {
                        std::array<float, 3> p{};
                        p[axis] = static_cast<float>(side ? b.max[axis] : b.min[axis]);
                        p[u] = static_cast<float>(b.min[u] + (b.max[u] - b.min[u]) * i / kFaceCells);
                        p[v] = static_cast<float>(b.min[v] + (b.max[v] - b.min[v]) * j / kFaceCells);
                        m.positions.push_back(p);
                        m.normals.push_back(n);
                    }
                const auto at = [&](int i, int j) { return base + static_cast<std::uint32_t>(j * (kFaceCells + 1) + i); };
                for (int j = 0; j < kFaceCells; ++j)
                    for (int i = 0; i < kFaceCells; ++i) {
                        m.triangles.push_back({at(i, j), at(i + 1, j), at(i + 1, j + 1)});
                        m.triangles.push_back({at(i, j), at(i + 1, j + 1), at(i, j + 1)});
                    }
            }
    }
    return m;
}

DeviceLayer solids_layer(FrameCache& cache, cl_rt::Device& device, const Scene& scene,
                         const std::vector<scene::RigidPose>& poses, UploadedLayer& moved) {
    const scene::RigidPose rest;
    const bool at_rest = std::all_of(poses.begin(), poses.end(), [&](const scene::RigidPose& p) { return p.R == rest.R && p.T == rest.T; });
    if (poses.empty() || at_rest) return cache.boxes(device, scene.solids).layer();
    TriangleMesh all;
    for (std::size_t i = 0; i < scene.solids.size(); ++i) {
        const TriangleMesh one = box_mesh({scene.solids[i]});
        const scene::RigidPose& p = i < poses.size() ? poses[i] : rest;
        const auto base = static_cast<std::uint32_t>(all.positions.size());
        for (std::size_t v = 0; v < one.positions.size(); ++v) {
            const auto& x = one.positions[v];
            const auto& n = one.normals[v];
            const Vec3 y = p.apply({x[0], x[1], x[2]});
            std::array<float, 3> m{};
            for (std::size_t k = 0; k < 3; ++k) m[k] = static_cast<float>(p.R[3 * k] * n[0] + p.R[3 * k + 1] * n[1] + p.R[3 * k + 2] * n[2]);
            all.positions.push_back({static_cast<float>(y[0]), static_cast<float>(y[1]), static_cast<float>(y[2])});
            all.normals.push_back(m);
        }
        for (const auto& t : one.triangles) all.triangles.push_back({t[0] + base, t[1] + base, t[2] + base});
    }
    Layer layer{&all, {}, kSolid};
    for (std::uint32_t t = 0; t < all.triangles.size(); ++t) layer.triangles.push_back(t);
    moved = cache.renderer(device).upload(layer);
    return moved.layer();
}

std::vector<std::array<Vec3, 2>> wall_lines(const std::vector<BoxWalls>& walls) {
    std::vector<std::array<Vec3, 2>> lines;
    for (const auto& w : walls)
        for (int axis = 0; axis < 3; ++axis)
            for (int a = 0; a < 2; ++a)
                for (int b = 0; b < 2; ++b) {
                    const int u = (axis + 1) % 3, v = (axis + 2) % 3;
                    Vec3 p0{}, p1{};
                    p0[static_cast<std::size_t>(u)] = p1[static_cast<std::size_t>(u)] = a ? w.max[static_cast<std::size_t>(u)] : w.min[static_cast<std::size_t>(u)];
                    p0[static_cast<std::size_t>(v)] = p1[static_cast<std::size_t>(v)] = b ? w.max[static_cast<std::size_t>(v)] : w.min[static_cast<std::size_t>(v)];
                    p0[static_cast<std::size_t>(axis)] = w.min[static_cast<std::size_t>(axis)];
                    p1[static_cast<std::size_t>(axis)] = w.max[static_cast<std::size_t>(axis)];
                    lines.push_back({p0, p1});
                }
    return lines;
}

namespace {


// Across ranks, what the ranks other than 0 return: no picture (rank 0 finishes it), the range.
Image unfinished(const std::array<double, 2>& range) {
    Image none;
    none.range = range;
    return none;
}

// The devices' images composited by depth, the walls' outlines drawn over, on the background.
Image finish(std::vector<DepthImage> images, const Scene& scene, const CameraView& camera) {
    DepthImage im;
    if (images.empty()) {
        im.width = camera.width;
        im.height = camera.height;
        im.depth.assign(std::size_t{camera.width} * camera.height, 0xffffffffu);
        im.colour.assign(im.depth.size(), 0);
    } else {
        im = composite(images);
    }
    draw_lines(im, camera, wall_lines(scene.walls), {70, 70, 70});
    return to_rgb(im, kBackground);
}

}  // namespace
}  // namespace clsph::render

namespace clsph {

std::array<float, 3> device_colour(std::size_t d) {
    // Eight colours told apart at a glance, none the grey of the solids nor the blue of the
    // uniform surface (so that a view coloured by device never looks like the plain one).
    static constexpr std::array<std::array<float, 3>, 8> palette{{{0.95f, 0.55f, 0.20f},
                                                                  {0.20f, 0.40f, 0.85f},
                                                                  {0.35f, 0.75f, 0.35f},
                                                                  {0.85f, 0.30f, 0.35f},
                                                                  {0.60f, 0.45f, 0.85f},
                                                                  {0.90f, 0.80f, 0.30f},
                                                                  {0.30f, 0.80f, 0.80f},
                                                                  {0.85f, 0.50f, 0.75f}}};
    return palette[d % palette.size()];
}

}  // namespace clsph

namespace clsph::render {

Image render_scene(multi::SlabDriver& driver, const device::Grid& grid, const Scene& scene, const TriangleMesh& surface,
                   const CameraView& camera, const ImageStyle& style) {
    auto& slabs = driver.slabs();
    // Each surface triangle to the slab owning the column of its centroid.
    const int split = grid.axis(0);
    std::vector<std::vector<std::uint32_t>> mine(slabs.size());
    for (std::uint32_t t = 0; t < surface.triangles.size(); ++t) {
        double x = 0;
        for (auto v : surface.triangles[t]) x += surface.positions[v][static_cast<std::size_t>(split)] / 3.0;
        const double rel = (x - scene.domain.min[static_cast<std::size_t>(split)]) / grid.params().cell_s;
        const std::size_t column = rel <= 0 ? 0 : std::min<std::size_t>(static_cast<std::size_t>(rel), grid.params().n_s - 1);
        std::size_t owner = slabs.size() - 1;
        for (std::size_t d = 0; d < slabs.size(); ++d)
            if (column >= slabs[d].first_col && column < slabs[d].end_col) {
                owner = d;
                break;
            }
        mine[owner].push_back(t);
    }
    const TriangleMesh solids = box_mesh(scene.solids);
    std::vector<std::uint32_t> all_solids(solids.triangles.size());
    for (std::uint32_t t = 0; t < all_solids.size(); ++t) all_solids[t] = t;
    const std::uint32_t mode = field_mode(style.surface);
    const auto range = mode ? field_range(driver, grid, style) : std::array<double, 2>{NAN, NAN};
    std::vector<DepthImage> images;
    Ranks* ranks = driver.ranks();
    const bool root = !ranks || ranks->rank() == 0;
    SlabImages<DepthImage> sent;  // across ranks, on the others: this rank's images, for rank 0
    for (std::size_t d = 0; d < slabs.size(); ++d) {
        if (!driver.here(d)) continue;  // across ranks: drawn there
        if (mine[d].empty() && !(d == 0 && !all_solids.empty())) continue;
        const auto colour = style.surface == SurfaceColour::by_device ? device_colour(d) : kWater;
        Renderer r(*slabs[d].device);
        // The water's triangles uploaded to the device owning them, coloured there from its particles.
        std::vector<UploadedLayer> up;
        up.push_back(r.upload({&surface, mine[d], colour}));
        if (d == 0) up.push_back(r.upload({&solids, all_solids, kSolid}));
        std::vector<DeviceLayer> layers;
        for (const auto& u : up) layers.push_back(u.layer());
        cl_rt::Buffer values;
        if (mode && up.front().count > 0) {
            FieldSampler sampler(*slabs[d].device, grid, slabs[d].physics->point_options());
            values = sampler.vertex_values(mode, driver.params(), range, up.front().positions, surface.positions.size(),
                                           *slabs[d].store, *slabs[d].cells);
            layers.front().values = &values;
        }
        if (root)
            images.push_back(r.draw(camera, layers));
        else
            sent.emplace_back(d, r.draw(camera, layers));
    }
    if (ranks) {  // the other ranks' slabs come after rank 0's: their images after its own
        for (auto& [d, im] : gather_to_rank0(*ranks, sent)) images.push_back(std::move(im));
        if (!root) return unfinished(range);
    }
    Image out = finish(std::move(images), scene, camera);
    out.range = range;
    return out;
}

Image render_scene(multi::SlabDriver& driver, const device::Grid& grid, const Scene& scene, const surface::DeviceParts& surface,
                   const CameraView& camera, const ImageStyle& style, FrameCache& cache,
                   const std::vector<scene::RigidPose>& poses) {
    auto& slabs = driver.slabs();
    const std::uint32_t mode = field_mode(style.surface);
    const auto range = mode ? field_range(driver, grid, style) : std::array<double, 2>{NAN, NAN};
    // The first device that draws keeps its image and finishes the picture; the others' images are
    // read back and merged into it there, in the devices' order.
    RenderTarget target;
    cl_rt::Device* shows = nullptr;
    Ranks* ranks = driver.ranks();
    const bool root = !ranks || ranks->rank() == 0;
    SlabImages<DepthImage> sent;  // across ranks, on the others: this rank's images, for rank 0
    for (std::size_t d = 0; d < slabs.size(); ++d) {
        if (!driver.here(d)) continue;  // across ranks: drawn there
        const surface::DeviceSurface* part = d < surface.parts.size() ? surface.parts[d].get() : nullptr;
        // The triangles' count stays on the device: the capacity is drawn, each kernel stopping at the count.
        const bool water = part && part->triangle_capacity() > 0, boxes = d == 0 && !scene.solids.empty();
        if (!water && !boxes) continue;
        Renderer& r = cache.renderer(*slabs[d].device);
        std::vector<DeviceLayer> layers;
        const auto colour = style.surface == SurfaceColour::by_device ? device_colour(d) : kWater;
        cl_rt::Buffer values;  // the field at the vertices, from this device's particles
        if (water) {
            DeviceLayer layer{&part->positions(), &part->normals(), &part->triangles(), part->triangle_capacity(), colour};
            layer.live = &part->totals();
            layer.live_at = 2;
            layers.push_back(layer);
            if (mode) {
                FieldSampler sampler(*slabs[d].device, grid, slabs[d].physics->point_options());
                values = sampler.vertex_values(mode, driver.params(), range, part->positions(), part->capacity().vertices,
                                               *slabs[d].store, *slabs[d].cells);
                layers.back().values = &values;
            }
        }
        UploadedLayer moved;
        if (boxes) layers.push_back(solids_layer(cache, *slabs[d].device, scene, poses, moved));  // in the same image
        if (!root) {
            sent.emplace_back(d, r.draw(camera, layers));
        } else if (!shows) {
            shows = slabs[d].device;
            target = r.render(camera, layers);
        } else {
            cache.finisher(*shows).merge(target, r.draw(camera, layers));
        }
    }
    if (ranks) {  // the other ranks' slabs come after rank 0's: merged after its own, in slab order
        for (const auto& [d, im] : gather_to_rank0(*ranks, sent)) {
            if (!shows) {  // none of rank 0's slabs draws: an empty image on its first device first
                for (std::size_t k = 0; k < slabs.size() && !shows; ++k)
                    if (driver.here(k)) shows = slabs[k].device;
                target = cache.renderer(*shows).render(camera, {});
            }
            cache.finisher(*shows).merge(target, im);
        }
        if (!root) return unfinished(range);
    }
    Image out = shows ? cache.finisher(*shows).finish(target, line_pixels(camera, wall_lines(scene.walls)), {70, 70, 70},
                                                      kBackground, false)
                      : finish({}, scene, camera);
    out.range = range;
    return out;
}

}  // namespace clsph::render
