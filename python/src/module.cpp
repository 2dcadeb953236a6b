// The `clsph._clsph` extension: the public C++ API (clsph/*.hpp) as a Python module. Scenes come
// from dicts or JSON files; particles, probes and step statistics come back as NumPy arrays and
// small records, never one Python object per particle. The GIL is released while the devices step.
#include "clsph/devices.hpp"
#include "clsph/error.hpp"
#include "clsph/io.hpp"
#include "clsph/render.hpp"
#include "clsph/scene.hpp"
#include "clsph/scene_io.hpp"
#include "clsph/simulation.hpp"
#include "clsph/version.hpp"

#include <pybind11/functional.h>
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <cmath>
#include <cstring>
#include <limits>
#include <memory>
#include <string>
#include <vector>

namespace py = pybind11;
using namespace clsph;

namespace {

// A NumPy array of shape `shape` that owns a copy of `count` elements from `data`.
template <class T>
py::array_t<T> array_copy(const T* data, std::vector<py::ssize_t> shape) {
    py::array_t<T> a(shape);
    std::size_t count = 1;
    for (auto s : shape) count *= static_cast<std::size_t>(s);
    if (count) std::memcpy(a.mutable_data(), data, count * sizeof(T));
    return a;
}

// Particles as a dict of arrays: id (uint32), type (uint8: 0 fluid, 1 boundary), position (n, 3)
// float64 (m), velocity (n, 3) float32 (m/s), density and pressure (float32).
py::dict particles_dict(const Particles& p) {
    const auto n = static_cast<py::ssize_t>(p.size());
    static_assert(sizeof(ParticleType) == 1, "type is one byte");
    py::dict d;
    d["id"] = array_copy(p.id.data(), {n});
    d["type"] = array_copy(reinterpret_cast<const std::uint8_t*>(p.type.data()), {n});
    d["position"] = array_copy(p.position.empty() ? nullptr : p.position[0].data(), {n, 3});
    d["velocity"] = array_copy(p.velocity.empty() ? nullptr : p.velocity[0].data(), {n, 3});
    d["density"] = array_copy(p.density.data(), {n});
    d["pressure"] = array_copy(p.pressure.data(), {n});
    return d;
}

Options make_options(const std::string& devices, const std::string& interaction, bool profile,
                     const std::string& cell_order) {
    Options o;
    o.devices = devices;
    o.interaction = interaction_from_name(interaction);
    o.cell_order = cell_order_from_name(cell_order);
    o.profile = profile;
    return o;
}

// Simulation::run_until (which lands on t exactly) without the GIL; after every step the GIL is
// taken back for the callback (if any) and for pending signals, so Ctrl-C raises KeyboardInterrupt
// at the end of the step in progress, and an exception in the callback stops the run and reaches
// the caller.
void run_until(Simulation& sim, double t, const py::object& callback) {
    py::gil_scoped_release unlocked;
    sim.run_until(t, [&](const StepInfo& s) {
        py::gil_scoped_acquire locked;
        if (!callback.is_none()) callback(s);
        if (PyErr_CheckSignals() != 0) throw py::error_already_set();
    });
}

}  // namespace

PYBIND11_MODULE(_clsph, m) {
    m.doc() = "clsph: multi-device SPH on OpenCL (the C++ library's public API)";
    m.attr("__version__") = version();

    // Errors: clsph.Error and its subclasses, messages unchanged.
    static py::exception<Error> error(m, "Error");
    static py::exception<SceneError> scene_error(m, "SceneError", error.ptr());
    static py::exception<DeviceSelectionError> selection_error(m, "DeviceSelectionError", error.ptr());
    static py::exception<DeviceError> device_error(m, "DeviceError", error.ptr());
    static py::exception<BuildError> build_error(m, "BuildError", device_error.ptr());  // a DeviceError, as in C++
    static py::exception<OutOfDeviceMemory> memory_error(m, "OutOfDeviceMemory", error.ptr());
    static py::exception<SimulationError> simulation_error(m, "SimulationError", error.ptr());
    for (PyObject* e : {error.ptr(), scene_error.ptr(), selection_error.ptr(), device_error.ptr(), build_error.ptr(),
                        memory_error.ptr(), simulation_error.ptr()})
        py::handle(e).attr("__module__") = "clsph";  // shown as clsph.SceneError, as users import it
    py::register_exception_translator([](std::exception_ptr p) {
        try {
            if (p) std::rethrow_exception(p);
        } catch (const SceneError& e) {
            scene_error(e.what());
        } catch (const DeviceSelectionError& e) {
            selection_error(e.what());
        } catch (const BuildError& e) {
            build_error(e.what());
        } catch (const DeviceError& e) {
            device_error(e.what());
        } catch (const OutOfDeviceMemory& e) {
            memory_error(e.what());
        } catch (const SimulationError& e) {
            simulation_error(e.what());
        } catch (const Error& e) {
            error(e.what());
        }
    });

    m.def("devices", [] {
        py::list out;
        for (const auto& d : list_devices()) {
            py::dict e;
            e["index"] = d.index;
            e["platform"] = d.platform;
            e["vendor"] = d.vendor;
            e["name"] = d.name;
            e["type"] = d.type;
            e["driver_version"] = d.driver_version;
            e["compute_units"] = d.compute_units;
            e["global_memory"] = d.global_memory;
            out.append(e);
        }
        return out;
    }, "Every OpenCL device, in the order `clsph devices` lists them (dicts: index, platform, name, type, ...).");

    m.def("read_frame", [](const std::string& path) {
        Particles p;
        {
            py::gil_scoped_release unlocked;
            const auto dot = path.rfind('.');
            const std::string ext = dot == std::string::npos ? "" : path.substr(dot);
            if (ext == ".csv") {
                p = read_csv(path);
            } else if (ext == ".vtu" || ext == ".pvtu") {
                FrameFields present;
                p = read_vtu(path, &present);
            } else {
                throw Error(path + ": not a frame clsph writes (.vtu, .pvtu or .csv)");
            }
        }
        return particles_dict(p);
    }, py::arg("path"),
          "One frame as clsph writes it (a .vtu, raw or compressed, a .pvtu index of pieces, or a .csv)\n"
          "as Simulation.particles() returns particles: a dict of NumPy arrays id, type, position,\n"
          "velocity, density, pressure. Arrays a --fields frame left out are zeros.");

    py::class_<Scene>(m, "Scene", "A scene: physics, domain, fluid, boundaries, probes, run control (docs/scenes.md).")
        .def_static("from_json", [](const std::string& text, const std::string& name, const std::vector<std::string>& overrides) {
                        return load_scene_text(text, name, overrides);
                    },
                    py::arg("text"), py::arg("source_name") = "scene", py::arg("overrides") = std::vector<std::string>{},
                    "A scene from JSON text (errors name `source_name`), KEY=VALUE overrides applied as\n"
                    "`clsph run --set` does; relative mesh paths are taken from the working directory.")
        .def_static("from_file", [](const std::string& path, const std::vector<std::string>& overrides) { return load_scene(path, overrides); },
                    py::arg("path"), py::arg("overrides") = std::vector<std::string>{},
                    "Reads a JSON scene file and applies KEY=VALUE overrides, as `clsph run --set` does.")
        .def("to_json", &Scene::to_json, "The resolved scene, every default filled in.")
        .def_property_readonly("name", [](const Scene& s) { return s.name; })
        .def_property_readonly("dp", [](const Scene& s) { return s.physics.dp; })
        .def_property_readonly("end_time", [](const Scene& s) { return s.run.end_time; })
        .def("particles", [](const Scene& s) { return particles_dict(s.build_particles()); },
             "The scene's initial particles (dict of NumPy arrays).");

    py::class_<StepInfo>(m, "StepInfo", "Statistics of the step just taken.")
        .def_readonly("step", &StepInfo::step)
        .def_readonly("time", &StepInfo::time)
        .def_readonly("dt", &StepInfo::dt)
        .def_readonly("particles", &StepInfo::particles)
        .def_readonly("fluid", &StepInfo::fluid)
        .def_readonly("removed", &StepInfo::removed)
        .def_readonly("created", &StepInfo::created)
        .def_readonly("kinetic_energy", &StepInfo::kinetic_energy)
        .def_readonly("max_speed", &StepInfo::max_speed)
        .def_readonly("wall_seconds", &StepInfo::wall_seconds)
        .def("__repr__", [](const StepInfo& s) {
            return "StepInfo(step=" + std::to_string(s.step) + ", time=" + std::to_string(s.time) + ")";
        });

    py::class_<Simulation>(m, "Simulation", "A scene running on OpenCL devices.")
        .def(py::init([](const Scene& scene, const std::string& devices, const std::string& interaction, bool profile,
                         const std::string& cell_order) {
                 Options o = make_options(devices, interaction, profile, cell_order);
                 py::gil_scoped_release unlocked;  // set-up builds kernels and uploads particles
                 return std::make_unique<Simulation>(scene, o);
             }),
             py::arg("scene"), py::arg("devices") = "", py::arg("interaction") = "auto", py::arg("profile") = false,
             py::arg("cell_order") = "auto")
        .def("step", [](Simulation& s) {
            {
                py::gil_scoped_release unlocked;
                s.step();
            }
            return s.info();
        }, "One time step; returns its StepInfo.")
        .def("run_until", &run_until, py::arg("time"), py::arg("callback") = py::none(),
             "Steps until simulated time `time`; callback(StepInfo) after every step.")
        .def("particles", [](Simulation& s) {
            Particles p;
            {
                py::gil_scoped_release unlocked;
                p = s.particles();
            }
            return particles_dict(p);
        }, "Host copy of the particles: dict of NumPy arrays id, type, position, velocity, density, pressure.")
        .def("probes", [](Simulation& s) {
            py::dict out;
            for (const auto& p : s.sample_probes()) out[py::str(p.name)] = p.value;
            return out;
        }, "Each probe's value now: {name: Pa or m} (NaN where no fluid is).")
        .def("image", [](Simulation& s, const py::object& camera, std::uint32_t width, std::uint32_t height, const std::string& colour) {
            CameraView view = camera_for(s.scene());
            if (width) view.width = width;
            if (height) view.height = height;
            if (!camera.is_none()) {
                const auto d = camera.cast<py::dict>();
                for (const auto& item : d) {
                    const auto key = item.first.cast<std::string>();
                    auto vec = [&](Vec3& out) {
                        const auto v = item.second.cast<std::vector<double>>();
                        if (v.size() != 3) throw Error("image: camera['" + key + "'] must be 3 numbers");
                        out = {v[0], v[1], v[2]};
                    };
                    if (key == "eye") vec(view.eye);
                    else if (key == "target") vec(view.target);
                    else if (key == "up") vec(view.up);
                    else if (key == "fov") view.fov_deg = item.second.cast<double>();
                    else throw Error("image: unknown camera key '" + key + "' (eye, target, up, fov)");
                }
            }
            for (double x : {view.eye[0], view.eye[1], view.eye[2], view.target[0], view.target[1], view.target[2], view.fov_deg})
                if (!std::isfinite(x)) throw Error("image: the camera's numbers must be finite");
            if (!(view.fov_deg > 0 && view.fov_deg < 180)) throw Error("image: fov must be within (0, 180) degrees");
            if (view.width == 0 || view.height == 0 || view.width > 8192 || view.height > 8192)
                throw Error("image: width and height must be within 1..8192 pixels");
            ImageStyle style;
            if (colour == "device") style.surface = SurfaceColour::by_device;
            else if (colour == "speed") style.surface = SurfaceColour::by_speed;
            else if (colour == "pressure") style.surface = SurfaceColour::by_pressure;
            else if (colour != "uniform")
                throw Error("image: colour must be \"uniform\", \"device\", \"speed\" or \"pressure\", got \"" + colour + "\"");
            Image im;
            {
                py::gil_scoped_release unlocked;
                im = s.image(view, style);
            }
            py::array_t<std::uint8_t> out({static_cast<py::ssize_t>(im.height), static_cast<py::ssize_t>(im.width), py::ssize_t{3}});
            std::memcpy(out.mutable_data(), im.rgb.data(), im.rgb.size());
            return out;
        }, py::arg("camera") = py::none(), py::arg("width") = 0, py::arg("height") = 0, py::arg("colour") = "uniform",
           "An image of the state now, as the scene's render.method draws it: (height, width, 3) uint8, rows from the "
           "top. camera: None (the scene's) or {'eye', 'target', 'up': [x, y, z], 'fov': degrees}; width, height: "
           "pixels (0: the scene's render.size); colour: 'uniform', 'device' (each device's slab its own), 'speed' or "
           "'pressure' (a colour map over the field's range now).")
        .def_property_readonly("time", &Simulation::time)
        .def_property_readonly("info", &Simulation::info)
        .def_property_readonly("scene", &Simulation::scene)
        .def("devices", &Simulation::device_names)
        .def("interaction_forms", [](const Simulation& s) {
            std::vector<std::string> out;
            for (const auto& d : s.shares()) out.push_back(interaction_name(d.interaction));
            return out;
        })
        .def("cell_order", [](const Simulation& s) { return std::string(cell_order_name(s.cell_order())); },
             "The order within cells the run resolved to: \"arrival\" or \"morton\" (docs/interaction.md).")
        .def("table_builds", [](const Simulation& s) {
            const TableBuilds t = s.table_builds();
            py::dict out;
            out["builds"] = t.builds;
            out["age"] = t.age;
            out["moved"] = t.moved;
            return out;
        }, "The cell tables' builds since the start, the steps since the last and the bound on any particle's move "
           "since then (m): every step, or fewer with run.list_buffer (docs/interaction.md).")
        .def("profile", [](Simulation& s) {
            py::dict out;
            for (const auto& k : s.profile()) out[py::str(k.name)] = out.contains(k.name) ? out[py::str(k.name)].cast<double>() + k.seconds : k.seconds;
            return out;
        }, "Seconds per kernel since the start (profile=True).");
}
