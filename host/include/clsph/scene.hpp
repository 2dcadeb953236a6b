// What to simulate: physics parameters, the domain, fluid blocks, boundaries, probes and run
// control. Built in code or read from a JSON file (Scene::from_file). Units: SI (m, s, kg).
#pragma once
#include "clsph/interaction.hpp"
#include "clsph/particles.hpp"

#include <array>
#include <cstdint>
#include <limits>
#include <optional>
#include <string>
#include <vector>

namespace clsph {

using Vec3 = std::array<double, 3>;

enum class KernelType { wendland_c2, cubic_spline };
enum class DensityMode { continuity, summation };
enum class Diffusion { none, molteni_colagrossi, fourtakas };
// How boundary particles get their density: dbc, the continuity equation (Crespo et al. 2007);
// mdbc, from a ghost node mirrored into the fluid (English et al. 2021, docs/scenes.md).
enum class BoundaryMethod { dbc, mdbc };
// The velocity the fluid sees at a boundary particle (JSON: boundaries.slip): wall, the wall's
// own (0 at rest; a moving solid's or body's); no_slip (mdbc only), the fluid's velocity at the
// particle's ghost node mirrored about the wall's, 2 v_wall - v_G (English et al. 2021).
enum class WallSlip { wall, no_slip };
// physics.alpha_wall of a scene file with mDBC walls that does not give one: with it the dam
// break's surge front is 3.3 % RMS from Koshizuka & Oka at L/dp = 20, h = 2 dp, against 11.6 %
// without (on the H200; tests/device/test_mdbc.cpp, BENCHMARKS.md).
constexpr double kMdbcWallFriction = 0.3;
// Time integration: Leap-frog (kick-drift-kick, one force pass per step) or Symplectic (position
// Verlet predictor-corrector, two force passes per step; docs/scenes.md).
enum class Integrator { leapfrog, symplectic };
// Viscosity (docs/scenes.md): Monaghan's artificial viscosity (alpha, alpha_wall); Morris's laminar
// viscosity with a kinematic viscosity nu; laminar plus the Smagorinsky sub-particle-scale eddy
// viscosity (laminar_sps).
enum class Viscosity { artificial, laminar, laminar_sps };

struct PhysicsParams {
    double dp = 0.01;                 // particle spacing (m)
    double hdp = 2.0;                 // smoothing length h = hdp * dp
    KernelType kernel = KernelType::wendland_c2;
    DensityMode density = DensityMode::continuity;
    Diffusion diffusion = Diffusion::fourtakas;
    double delta = 0.1;               // density diffusion coefficient
    double rho0 = 1000.0;             // reference density (kg/m^3)
    double gamma = 7.0;               // Tait exponent (the kernels assume 7)
    double coefsound = 20.0;          // c0 = coefsound * sqrt(g * H), H = initial fluid height
    double c0 = 0.0;                  // speed of sound (m/s); 0: from coefsound
    double alpha = 0.02;              // Monaghan artificial viscosity, fluid-fluid
    double alpha_wall = 0.0;          // the same between fluid and boundary particles (wall friction)
    Viscosity viscosity = Viscosity::artificial;
    double kinematic_viscosity = 1e-6;  // nu (m^2/s) of the laminar models; water at 20 C
    Vec3 gravity{0.0, 0.0, -9.81};    // m/s^2
    double cfl = 0.2;                 // Courant number of the adaptive time step
    Integrator integrator = Integrator::leapfrog;
    double density_min = 0.7;         // a density outside [min, max] * rho0 stops the run
    double density_max = 1.3;

    double h() const { return hdp * dp; }
    double support() const { return 2.0 * h(); }
    // The laminar models' stability limit on the time step, dt <= 0.125 h^2 / nu (Morris et al.
    // 1997); infinity for artificial viscosity or nu = 0.
    double viscous_dt() const {
        if (viscosity == Viscosity::artificial || !(kinematic_viscosity > 0)) return std::numeric_limits<double>::infinity();
        return 0.125 * h() * h() / kinematic_viscosity;
    }
};

struct Domain {
    Vec3 min{0, 0, 0}, max{1, 1, 1};
    std::array<bool, 3> periodic{false, false, false};
    int split_axis = -1;  // -1: the longest axis
};

// A box of fluid on the dp lattice, in hydrostatic equilibrium below `surface` (default: its top).
struct FluidBlock {
    Vec3 min{0, 0, 0}, max{0, 0, 0};
    Vec3 velocity{0, 0, 0};
    std::optional<double> surface;
};

// Prescribed motion of a solid (docs/scenes.md, motion): segments in time, in increasing order and
// not overlapping. Each segment moves the solid from where the segments before it left it; before
// the first, between segments and after the last the solid rests. Over a segment [start, end),
// with tau = t - start and w = 2 pi / period:
//   linear          x += velocity tau
//   sine            x += amplitude (sin(w tau + phase) - sin(phase))      (a piston)
//   sine_rotation   about the axis through axis_point along axis, by the angle
//                   angle (sin(w tau + phase) - sin(phase))  (radians; a flap, a sloshing tank)
//   rotation        about the axis, by the angle angular_velocity tau  (rad/s, right-handed)
//   linear_rotation both at once: x += velocity tau, and about the axis through
//                   axis_point + velocity tau (the axis moves with the solid) by angular_velocity tau
//                   (a CSV motion's interval between two rows)
//   ramped_sine     x += amplitude r(tau) sin(w tau)  (a piston wave maker)
//   ramped_sine_rotation about the axis by the angle angle r(tau) sin(w tau)  (a flap wave maker)
//                   with the ramp r(tau) = (1 - cos(pi tau / ramp)) / 2 for tau < ramp, else 1
struct MotionSegment {
    enum class Type { linear, sine, sine_rotation, rotation, linear_rotation, ramped_sine, ramped_sine_rotation } type = Type::linear;
    double start = 0, end = 0;        // s
    Vec3 velocity{0, 0, 0};           // linear (m/s)
    Vec3 amplitude{0, 0, 0};          // sine (m)
    double period = 1, phase = 0;     // sine, sine_rotation (s, rad)
    Vec3 axis_point{0, 0, 0};         // sine_rotation, rotation (m)
    Vec3 axis{0, 0, 1};               // the rotation axis' direction (any non-zero length)
    double angle = 0;                 // sine_rotation's amplitude (rad)
    double angular_velocity = 0;      // rotation, linear_rotation (rad/s)
    double ramp = 0;                  // ramped_sine, ramped_sine_rotation: the ramp-up's length (s, 0: none)
};

// A regular-wave maker (docs/scenes.md, motion.wave_maker): first-order wave-maker theory
// (Biesel's transfer functions) gives the stroke that makes waves of `height` and `period` in
// water of `depth`; the solid moves as one ramped segment. The last three are computed.
struct WaveMaker {
    enum class Kind { piston, flap } kind = Kind::piston;
    double height = 0, period = 1, depth = 0;  // m, s, m
    double ramp = 0;                           // s of ramp-up (the amplitude rises smoothly from 0)
    double start = 0, end = 0;                 // s
    Vec3 direction{1, 0, 0};                   // the waves' direction (horizontal)
    Vec3 hinge{0, 0, 0};                       // flap: a point on its hinge line
    double hinge_height = 0;                   // flap: the hinge's height above the bed (m, in [0, depth))
    double k = 0, wavelength = 0, stroke = 0;  // computed: wave number (1/m), wavelength (m), stroke (m)
};

struct Motion {
    std::vector<MotionSegment> segments;  // empty: the solid does not move
    std::optional<WaveMaker> wave_maker;  // set: segments is its one segment
    bool moves() const { return !segments.empty(); }
};

// Faces of a box: bit k*2 is the min face of axis k, bit k*2+1 the max face (x-, x+, y-, y+, z-, z+).
enum BoxFaces : unsigned { x_min = 1, x_max = 2, y_min = 4, y_max = 8, z_min = 16, z_max = 32, all_faces = 63 };

// The walls of a container whose inner faces are `min`/`max`; `layers` layers of boundary
// particles at offsets 0, dp, 2dp ... outward.
struct BoxWalls {
    Vec3 min{0, 0, 0}, max{1, 1, 1};
    unsigned faces = all_faces;
    int layers = 3;
    Motion motion;
};

// A floating rigid body (docs/scenes.md, floating): the fluid's force and torque on the solid's
// particles and gravity move it as a rigid body. Exactly one of density (kg/m^3, of the solid's
// volume: a box's extent plus dp/2 on every side) and mass (kg) is positive. Centre (the centre of
// mass) and inertia (kg m^2 about it, row-major) default to those of the solid's particles, each
// carrying mass / count.
struct Floating {
    bool enabled = false;
    std::string name;             // body_NAME.csv; default "box<i>"
    double density = 0, mass = 0;
    std::optional<Vec3> centre;
    std::optional<std::array<double, 9>> inertia;
    // The axes (x, y, z, world frame) along which it may move and about which it may turn: a body
    // in a slice periodic in y that spans the slice moves in x and z and turns about y only.
    std::array<bool, 3> free_translation{true, true, true}, free_rotation{true, true, true};
    // The body's velocity (m/s) and angular velocity (rad/s, world frame) at t = 0, its particles
    // moving with V + W x r from the first force pass: a decay test started with a push or a spin
    // from its rest pose (the fluid around it stays as the scene builds it). Zero along held axes.
    Vec3 velocity{0, 0, 0}, angular_velocity{0, 0, 0};
};

// A solid box of boundary particles: layers inward from its faces (0 layers: filled).
struct SolidBox {
    Vec3 min{0, 0, 0}, max{0, 0, 0};
    int layers = 3;
    Motion motion;
    Floating floating;
};

// A closed triangle mesh (OBJ, STL or PLY, by the file's extension): boundary layers inward from
// its surface, or filled with fluid. Placed by scale, then rotate, then translate.
struct MeshObject {
    std::string path;
    double scale = 1.0;
    Vec3 translate{0, 0, 0};
    bool fluid = false;  // true: the inside is fluid; false: `layers` of boundary particles
    int layers = 3;
    Vec3 rotate{0, 0, 0};  // degrees about the x, then the y, then the z axis (fixed axes, right-handed)
    Motion motion;         // a boundary mesh only
};

// A gauge (docs/scenes.md, probes). height: the water depth on the vertical line at (x, y), the
// first fall of the fluid fraction through 1/2 from the domain's bottom up. pressure: at `point`,
// or with a `normal`, a sensor: the disc of diameter `size` on the wall plane through `point`
// (its centre) facing along `normal` (from the wall into the fluid), the mean pressure over it.
struct Probe {
    enum class Kind { pressure, height } kind = Kind::pressure;
    std::string name;
    Vec3 point{0, 0, 0};          // for height: x, y (z ignored)
    std::optional<Vec3> normal;   // pressure only; any non-zero length (the direction is used)
    double size = 0.009;          // m, the sensor's diameter (with a normal)
};

// Open boundaries (docs/scenes.md, inlets and outlets).
// A quantity in time given by rows (time s, value): linear between two rows, the first row's value
// before it and the last row's after it (an inlet's speed, an outlet's water level).
struct TimeSeries {
    std::vector<double> time, value;
    bool empty() const { return time.empty(); }
};
// An inlet is a box of buffer particles moving along one axis (`velocity`: m/s, one non-zero
// component): the fluid particles in the box are given that velocity every step; the box's
// upstream face (along the velocity) gets a new layer of particles each time the layers have moved
// one dp, with ids from a counter every device and rank holds alike (scene/open_boundaries.hpp).
// The new particles are in hydrostatic equilibrium below `surface` (default: the box's top).
// With `speed` the speed along the velocity's direction follows those rows (m/s, >= 0; `velocity`
// then gives only the direction, a unit vector); with a profile each lattice point across the
// section moves at factor(coordinate) times the speed (linear between the points, the end factors
// beyond them).
struct InletProfile {
    int axis = -1;                              // 0 = x, 1 = y, 2 = z; -1: none (a uniform section)
    std::vector<std::array<double, 2>> points;  // (coordinate m, factor >= 0), coordinates increasing
};
struct Inlet {
    Vec3 min{0, 0, 0}, max{0, 0, 0};
    Vec3 velocity{0, 0, 0};
    std::optional<double> surface;
    TimeSeries speed;  // empty: |velocity| at all times
    InletProfile profile;
};
// An outlet is a face of the domain ("x+", "x-", ...) through which fluid leaves: particles past
// it are removed (and counted in StepInfo::removed), as past any face without walls. With a zone
// (`zone`: the box min, max) the face is the zone's side fluid leaves by: fluid particles past
// that face (within the box's extent across it) are removed and counted, and every step the fluid
// particles in the box get the density Tait's equation gives for `pressure` (Pa) or for the
// hydrostatic pressure below `level` (m; `level_series`: in time), when one is given.
struct Outlet {
    int axis = 0;       // 0 = x, 1 = y, 2 = z
    bool upper = true;  // the max face (true) or the min face
    bool zone = false;  // min, max below are the zone's
    Vec3 min{0, 0, 0}, max{0, 0, 0};
    std::optional<double> pressure{};  // Pa
    std::optional<double> level{};     // m (the water level, z)
    TimeSeries level_series{};         // (time s, level m) rows; non-empty: the level in time
};

struct RunControl {
    double end_time = 1.0;       // simulated seconds
    double output_every = 0.01;  // simulated seconds between output frames
    int probe_every = 10;        // steps between probe samples
    double fixed_dt = 0.0;       // > 0: use this time step instead of the adaptive CFL step
    Interaction interaction = Interaction::automatic;  // the interaction form (clsph/interaction.hpp)
    CellOrder cell_order = CellOrder::automatic;       // the order within cells (clsph/interaction.hpp)
    // The cell tables and cluster lists kept over steps (docs/interaction.md, "Lists kept over
    // steps"): cells this fraction of the support wider, and the particles sorted again only when
    // one may have moved more than half of that margin since the last sort. 0: sorted every step.
    double list_buffer = 0.0;
};

// How water is drawn (render.method): the free surface meshed and rasterised, or the fluid
// particles splatted as spheres and shaded in screen space (no mesh; docs/scenes.md, render).
enum class RenderMethod { surface, splat };

// How frames are rendered (clsph/render.hpp). Without a camera the view frames the domain.
struct RenderSettings {
    RenderMethod method = RenderMethod::surface;
    bool has_camera = false;
    Vec3 eye{0, 0, 0}, target{0, 0, 0}, up{0, 0, 1};
    double fov_deg = 40.0;
    std::uint32_t width = 1280, height = 720;
    // The method "surface": the free surface's sample spacing in an image, m; 0: as fine as a pixel
    // at the camera's target but no finer than dp / 2 (finer triangles than pixels cost and do not show).
    double surface_spacing = 0.0;
};

struct Scene {
    std::string name = "scene";
    PhysicsParams physics;
    Domain domain;
    std::vector<FluidBlock> fluids;
    std::vector<BoxWalls> walls;
    std::vector<SolidBox> solids;
    std::vector<MeshObject> meshes;
    BoundaryMethod boundary_method = BoundaryMethod::dbc;  // JSON: boundaries.method (files: mdbc, see below)
    WallSlip wall_slip = WallSlip::wall;                   // JSON: boundaries.slip
    std::vector<Probe> probes;
    std::vector<Inlet> inlets;
    std::vector<Outlet> outlets;
    RunControl run;
    RenderSettings render;
    // What a scene file left out and its reader chose in its place, for the user to read (clsph run
    // prints each once): the walls' method for a scene with floating bodies.
    std::vector<std::string> notes;

    // Reads a JSON scene (schema: docs/scenes.md). Errors name the file and the key path.
    static Scene from_file(const std::string& path);
    static Scene from_json_text(const std::string& text, const std::string& source_name = "scene");
    std::string to_json() const;  // the resolved scene, every default filled in

    // Checks that need no device (dp > 0, fluid inside the domain, ...); throws SceneError.
    void validate() const;
    // The particles of the scene on the dp lattice: boundaries first, then fluid kept at least dp
    // from every boundary particle; fluid in hydrostatic equilibrium. Ids are 0..n-1.
    Particles build_particles() const;
    // The speed of sound the run uses (c0, or coefsound * sqrt(g H)).
    double sound_speed() const;
    // How many particles build_particles() gives; without building them when the scene has no
    // meshes (counted from its lattice, so a billion-particle scene is counted in seconds).
    struct Count {
        std::uint64_t fluid = 0, boundary = 0;
        std::uint64_t total() const { return fluid + boundary; }
    };
    Count count_particles() const;
    // Whether any solid has a prescribed motion.
    bool has_motion() const;
    // Whether any solid floats (Floating).
    bool has_floating() const;
};

}  // namespace clsph
