"""clsph: multi-device SPH fluid simulation on OpenCL, from Python.

    import clsph
    scene = clsph.scene("scenes/dam_break.json", overrides=["physics.dp=0.0146"])
    sim = clsph.Simulation(scene, devices="cpu")
    sim.run_until(0.1, lambda s: print(s.step, s.time))
    p = sim.particles()          # dict of NumPy arrays: id, type, position (n, 3), ...

Scenes follow the JSON schema of docs/scenes.md, as a file or as a dict; errors are clsph.Error
and its subclasses (SceneError, DeviceSelectionError, DeviceError, BuildError, OutOfDeviceMemory,
SimulationError), with the C++ library's messages.
"""
import json as _json
import os as _os

from ._clsph import (  # noqa: F401  (the public names)
    BuildError,
    DeviceError,
    DeviceSelectionError,
    Error,
    OutOfDeviceMemory,
    Scene,
    SceneError,
    Simulation,
    SimulationError,
    StepInfo,
    __version__,
    devices,
)


def scene(source, overrides=(), name=None):
    """A Scene from a dict (the JSON schema of docs/scenes.md), a path to a JSON scene file (with
    KEY=VALUE overrides applied as `clsph run --set` does), or a Scene (returned as it is)."""
    if isinstance(source, Scene):
        if overrides:
            raise Error("overrides apply to scene files; change the dict or the file instead")
        return source
    if isinstance(source, dict):
        if overrides:
            raise Error("overrides apply to scene files; set the keys in the dict instead")
        return Scene.from_json(_json.dumps(source), name or "scene")
    if isinstance(source, (str, _os.PathLike)):
        return Scene.from_file(_os.fspath(source), [str(o) for o in overrides])
    raise TypeError("clsph.scene: expected a dict, a path or a Scene, got %s" % type(source).__name__)


def scene_dict(scene_obj):
    """The resolved scene (every default filled in) as a dict."""
    return _json.loads(scene_obj.to_json())
