// laminar+sps: the sub-particle-scale stress pass (kernels/sps.cl) before each force pass.
#include "device/physics.hpp"

namespace clsph::device {

void Physics::build_sps(const std::string& options) {
    // The fine or the coarse form, never clusters (its lists cover the owned particles only, and
    // this pass covers the ghosts too) nor lanes (not written for lanes: on CPUs it runs as fine).
    sps_ = true;
    std::string o = options;
    if (form_ == Interaction::coarse) o += " -DCLSPH_COARSE -DWG=" + std::to_string(coarse_wg_);
    if (*device_.quirks().interaction_options) o += std::string(" ") + device_.quirks().interaction_options;
    sps_k_ = device_.kernel("sps.cl", "sps_stress", o);
}

void Physics::sps_stress(ParticleStore& ps, const CellPipeline& cells) {
    // Every particle held, ghosts included: the force pass reads tau of owned particles' neighbours,
    // which lie in the owned columns or the inner halo column (whose neighbours are all here).
    const std::size_t n = ps.ranges.active();
    if (n == 0) return;
    const std::size_t bytes = 2 * 4 * sizeof(float) * ps.capacity();
    if (tau_.bytes() < bytes) {
        tau_ = cl_rt::Buffer();
        tau_ = device_.alloc(bytes, "SPS stress");
    }
    const bool coarse = form_ == Interaction::coarse;
    cl_uint a = 0;
    sps_k_.setArg(a++, cl_uint{0});
    sps_k_.setArg(a++, static_cast<cl_uint>(n));
    sps_k_.setArg(a++, grid_.params());
    sps_k_.setArg(a++, sp_.support2);
    sps_k_.setArg(a++, ps.pos.get());
    sps_k_.setArg(a++, coarse ? cells.cell_start().get() : ps.vals.get());
    sps_k_.setArg(a++, cells.ranges().get());
    sps_k_.setArg(a++, sp_);
    sps_k_.setArg(a++, ps.velrho.get());
    sps_k_.setArg(a++, ps.id.get());
    sps_k_.setArg(a++, tau_.get());
    if (no_slip_) sps_k_.setArg(a++, ps.accel.get());  // the walls' v_wall - v_G (kernels/wall_velocity.h)
    if (coarse)
        device_.launch("sph.sps", sps_k_, cells.cells() * coarse_wg_, coarse_wg_);
    else
        device_.launch("sph.sps", sps_k_, n, wg_);
}

}  // namespace clsph::device
