#include "frame_filter.hpp"

#include <clsph/error.hpp>

#include <algorithm>
#include <cmath>
#include <utility>

namespace clsph::app {

FrameFilter FrameFilter::from_options(std::size_t stride, const std::vector<double>& box, const std::string& fields) {
    FrameFilter f;
    f.fields = FrameFields::parse(fields, "--fields");
    if (stride < 1) throw Error("--output-stride: expected an integer K >= 1 (every K-th particle by id)");
    f.stride = stride;
    if (!box.empty()) {
        if (box.size() != 6) throw Error("--output-box: expected 6 numbers XMIN YMIN ZMIN XMAX YMAX ZMAX");
        for (int k = 0; k < 3; ++k)
            if (!(std::isfinite(box[k]) && std::isfinite(box[k + 3]) && box[k] < box[k + 3]))
                throw Error("--output-box: expected finite numbers XMIN YMIN ZMIN XMAX YMAX ZMAX with each min below its max");
        f.box = std::array<double, 6>{box[0], box[1], box[2], box[3], box[4], box[5]};
    }
    return f;
}

ParticleSelection FrameFilter::device_selection() const {
    ParticleSelection s;
    s.stride = static_cast<std::uint32_t>(std::min<std::size_t>(stride, 0xffffffffu));
    s.box = box;
    return s;
}

bool FrameFilter::keeps(std::uint32_t id, const std::array<double, 3>& x) const {
    if (id % stride != 0) return false;
    if (!box) return true;
    const auto& b = *box;
    return x[0] >= b[0] && x[1] >= b[1] && x[2] >= b[2] && x[0] <= b[3] && x[1] <= b[4] && x[2] <= b[5];
}

Particles FrameFilter::apply(Particles p) const {
    if (keeps_all()) return p;
    Particles out;
    for (std::size_t i = 0; i < p.size(); ++i)
        if (keeps(p.id[i], p.position[i]))
            out.push_back(p.id[i], p.type[i], p.position[i], p.velocity[i], p.density[i], p.pressure[i]);
    return out;
}

}  // namespace clsph::app
