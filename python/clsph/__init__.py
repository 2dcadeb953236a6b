"""clsph: multi-device SPH fluid simulation on OpenCL, from Python.

    import clsph
    sim = clsph.Simulation("scenes/dam_break.json", overrides={"run.output_every": 0.05}, devices="cpu")
    sim.run_until(0.1, lambda s: print(s.step, s.time))
    p = sim.particles()          # dict of NumPy arrays: id, type, position (n, 3), ...
    q = clsph.read_frame("out/dam_break/frame_00001.vtu")   # the same dict, from a frame on disk

Scenes follow the JSON schema of docs/scenes.md (docs/python.md: the Python interface), as a file,
a dict or a Scene; overrides are KEY=VALUE strings as `clsph run --set` takes them, or a dict
{KEY: value}. Errors are clsph.Error and its subclasses (SceneError, DeviceSelectionError,
DeviceError, BuildError, OutOfDeviceMemory, SimulationError), with the C++ library's messages.
"""
import json as _json
import os as _os

from . import _clsph
from ._clsph import (  # noqa: F401  (the public names)
    BuildError,
    DeviceError,
    DeviceSelectionError,
    Error,
    OutOfDeviceMemory,
    Scene,
    SceneError,
    SimulationError,
    StepInfo,
    __version__,
    devices,
    read_frame,
)


def _assignments(overrides):
    """Overrides as the KEY=VALUE strings `clsph run --set` takes: from a dict {KEY: value} (the
    value written as JSON) or from an iterable of strings."""
    if overrides is None:
        return []
    if isinstance(overrides, str):
        raise TypeError("clsph: overrides are a list of KEY=VALUE strings or a dict, not one string")
    if isinstance(overrides, dict):
        out = []
        for key, value in overrides.items():
            if not isinstance(key, str):
                raise TypeError("clsph: override keys are strings such as 'physics.dp', not %r" % (key,))
            out.append("%s=%s" % (key, _json.dumps(value)))
        return out
    return [str(o) for o in overrides]


def scene(source, overrides=None, name=None):
    """A Scene from a dict (the JSON schema of docs/scenes.md), a path to a JSON scene file, or a
    Scene (returned as it is). `overrides`, as KEY=VALUE strings or a dict {KEY: value}, are applied
    to a file or a dict as `clsph run --set` applies them (e.g. {"physics.dp": 0.01},
    ["fluid[0].max=[1, 1, 0.5]"]); errors name the file (or `name`, "scene" for a dict) and the key."""
    assignments = _assignments(overrides)
    if isinstance(source, Scene):
        if assignments:
            raise Error("overrides apply to scene files and dicts, not to a Scene already made")
        return source
    if isinstance(source, dict):
        return Scene.from_json(_json.dumps(source), name or "scene", assignments)
    if isinstance(source, (str, _os.PathLike)):
        return Scene.from_file(_os.fspath(source), assignments)
    raise TypeError("clsph.scene: expected a dict, a path or a Scene, got %s" % type(source).__name__)


def scene_dict(scene_obj):
    """The resolved scene (every default filled in) as a dict."""
    return _json.loads(scene_obj.to_json())


class Simulation(_clsph.Simulation):
    """A scene running on OpenCL devices.

    Simulation(scene, overrides=None, devices="", interaction="auto", profile=False, cell_order="auto")

    scene: a Scene, a dict (docs/scenes.md) or a path to a JSON scene file; overrides as for
    clsph.scene(). devices: as `clsph run --devices` ("" every GPU, else every device; "cpu",
    "gpu", "all", indices "0,2"). interaction: the force pass's form ("auto", "fine", "lanes",
    "coarse", "clusters"). profile: time every kernel (Simulation.profile()). cell_order: the
    order of the particles within each cell ("auto", "arrival", "morton"; cell_order() says
    which the run took).

    step() takes one step, run_until(t, callback) steps to simulated time t; particles() and
    probes() read the state back as NumPy arrays, image(camera=...) renders it."""

    def __init__(self, scene_source, overrides=None, devices="", interaction="auto", profile=False,
                 cell_order="auto"):
        super().__init__(scene(scene_source, overrides), devices, interaction, profile, cell_order)
