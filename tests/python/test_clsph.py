"""The Python module against the C++ library and tool (run by CTest: PYTHONPATH points at the build
tree's package, CLSPH_TOOL at the clsph tool, CLSPH_SOURCE_DIR at the checkout)."""
import csv
import json
import os
import subprocess
import sys
import threading
import time

import numpy as np
import pytest

import clsph

SOURCE = os.environ.get("CLSPH_SOURCE_DIR", os.path.join(os.path.dirname(__file__), "..", ".."))
TOOL = os.environ.get("CLSPH_TOOL", "clsph")
HYDROSTATIC = os.path.join(SOURCE, "scenes", "hydrostatic.json")
DAM_BREAK = os.path.join(SOURCE, "scenes", "dam_break.json")


def first_device():
    """One device: pocl's threaded CPU device where there is one (the fastest CPU device in CI),
    else the first."""
    devs = clsph.devices()
    assert devs, "no OpenCL device"
    for d in devs:
        if d["name"].startswith("pthread"):
            return str(d["index"])
    return str(devs[0]["index"])


def test_a_dict_scene_and_the_same_file_resolve_alike():
    with open(DAM_BREAK) as f:
        doc = json.load(f)
    from_file = clsph.scene(DAM_BREAK)
    from_dict = clsph.scene(doc)
    assert clsph.scene_dict(from_dict) == clsph.scene_dict(from_file)
    # and an override on the file equals the same change in the dict
    doc["physics"]["dp"] = 0.0146
    assert clsph.scene_dict(clsph.scene(doc)) == clsph.scene_dict(clsph.scene(DAM_BREAK, ["physics.dp=0.0146"]))


def test_bad_keys_raise_scene_error_naming_the_key():
    with pytest.raises(clsph.SceneError, match=r"physics\.bogus"):
        clsph.scene({"physics": {"dp": 0.01, "bogus": 1}, "domain": {"min": [0, 0, 0], "max": [1, 1, 1]}})
    with pytest.raises(clsph.SceneError, match=r"physics\.dp"):
        clsph.scene(DAM_BREAK, ["physics.dp=-1"])
    assert issubclass(clsph.SceneError, clsph.Error)
    assert issubclass(clsph.DeviceSelectionError, clsph.Error)
    with pytest.raises(clsph.DeviceSelectionError):
        clsph.Simulation(clsph.scene(HYDROSTATIC), devices="99")


def test_the_order_within_cells_is_asked_for_by_name_and_reported():
    for order in ("arrival", "morton"):
        sim = clsph.Simulation(clsph.scene(HYDROSTATIC), devices=first_device(), cell_order=order)
        assert sim.cell_order() == order
    # auto: morton where every device runs lanes (pocl's CPU form), arrival elsewhere.
    sim = clsph.Simulation(clsph.scene(HYDROSTATIC), devices=first_device())
    forms = sim.interaction_forms()
    assert sim.cell_order() == ("morton" if forms and all(f == "lanes" for f in forms) else "arrival")
    with pytest.raises(clsph.Error, match="morton"):
        clsph.Simulation(clsph.scene(HYDROSTATIC), devices=first_device(), cell_order="hilbert")


def test_kept_cell_tables_are_built_less_often_than_every_step():
    steps = 20
    sim = clsph.Simulation(clsph.scene(HYDROSTATIC), devices=first_device())
    for _ in range(steps):
        sim.step()
    assert sim.table_builds()["builds"] == steps + 1  # the first, then every step
    kept = clsph.Simulation(clsph.scene(HYDROSTATIC, ["run.list_buffer=0.2"]), devices=first_device())
    for _ in range(steps):
        kept.step()
    t = kept.table_builds()
    assert 1 <= t["builds"] < steps
    assert t["age"] <= steps and t["moved"] >= 0


def test_particles_are_numpy_arrays():
    sim = clsph.Simulation(clsph.scene(HYDROSTATIC), devices=first_device())
    p = sim.particles()
    n = sim.info.particles
    assert p["position"].shape == (n, 3) and p["position"].dtype == np.float64
    assert p["velocity"].shape == (n, 3) and p["velocity"].dtype == np.float32
    for key, dtype in (("id", np.uint32), ("type", np.uint8), ("density", np.float32), ("pressure", np.float32)):
        assert p[key].shape == (n,) and p[key].dtype == dtype, key
    assert len(np.unique(p["id"])) == n
    assert int((p["type"] == 0).sum()) == sim.info.fluid
    probes = sim.probes()
    assert set(probes) == {pr["name"] for pr in clsph.scene_dict(sim.scene)["probes"]}


def test_an_image_is_a_numpy_array_and_the_camera_moves_it():
    sim = clsph.Simulation(clsph.scene(HYDROSTATIC), devices=first_device())
    im = sim.image(width=160, height=120)
    assert im.shape == (120, 160, 3) and im.dtype == np.uint8
    # The background as the image has it: its corners, where the framing camera draws nothing.
    background = im[0, 0]
    for corner in (im[0, -1], im[-1, 0], im[-1, -1]):
        assert (corner == background).all(), (corner, background)
    drawn = int((im != background).any(axis=2).sum())
    assert drawn > 500, drawn  # the water and the tank's outline
    lo, hi = clsph.scene_dict(sim.scene)["domain"]["min"], clsph.scene_dict(sim.scene)["domain"]["max"]
    centre = [(a + b) / 2 for a, b in zip(lo, hi)]
    above = sim.image(camera={"eye": [centre[0], centre[1] - 3.0, centre[2] + 2.0], "target": centre, "fov": 30},
                      width=160, height=120)
    assert above.shape == im.shape and (above != im).any()
    by_device = sim.image(width=160, height=120, colour="device")
    assert (by_device != im).any()
    for bad in ({"eye": [float("nan"), 0, 0]}, {"fov": 0}, {"zoom": 2}, {"eye": [1, 2]}):
        with pytest.raises(clsph.Error):
            sim.image(camera=bad, width=160, height=120)
    by_speed = sim.image(width=160, height=120, colour="speed")
    assert by_speed.shape == im.shape and (by_speed != im).any()
    with pytest.raises(clsph.Error):
        sim.image(colour="heat")


def test_the_python_page_example_runs(monkeypatch):
    """docs/python.md's first block, as written (issue 29: it had drifted and raised SceneError)."""
    page = open(os.path.join(SOURCE, "docs", "python.md")).read()
    block = page.split("```python\n", 1)[1].split("```", 1)[0]
    monkeypatch.chdir(SOURCE)
    namespace = {}
    exec(compile(block, "docs/python.md", "exec"), namespace)
    assert namespace["sim"].time >= 0.02
    assert namespace["im"].shape == (360, 640, 3)


def read_csv_frame(path):
    rows = {}
    with open(path) as f:
        for r in csv.DictReader(f):
            rows[int(r["id"])] = r
    return rows


def test_fifty_steps_from_python_and_from_the_cpp_tool_are_identical(tmp_path):
    device = first_device()
    sim = clsph.Simulation(clsph.scene(HYDROSTATIC), devices=device)
    for _ in range(50):
        sim.step()
    p = sim.particles()
    out = tmp_path / "cpp"
    subprocess.run([TOOL, "run", HYDROSTATIC, "--steps", "50", "--csv", "--every", "1000", "--devices", device,
                    "--out", str(out)], check=True, stdout=subprocess.DEVNULL)
    frames = sorted(out.glob("frame_*.csv"))
    ref = read_csv_frame(frames[-1])
    assert len(ref) == len(p["id"])
    for k in range(len(p["id"])):
        r = ref[int(p["id"][k])]
        # the CSV holds exact decimals: equality is bitwise
        assert [float(r["x"]), float(r["y"]), float(r["z"])] == p["position"][k].tolist()
        assert np.array([float(r["vx"]), float(r["vy"]), float(r["vz"])], dtype=np.float32).tolist() == p["velocity"][k].tolist()
        assert np.float32(float(r["rho"])) == p["density"][k]


def test_a_python_thread_runs_while_the_devices_step():
    sim = clsph.Simulation(clsph.scene(HYDROSTATIC), devices=first_device())
    ticks = []
    stop = threading.Event()

    def worker():
        while not stop.is_set():
            ticks.append(time.monotonic())
            time.sleep(0.001)

    t = threading.Thread(target=worker)
    t.start()
    try:
        begin = time.monotonic()
        sim.run_until(0.02)  # no callback: the GIL is taken back only at the end unless released
        end = time.monotonic()
    finally:
        stop.set()
        t.join()
    inside = [x for x in ticks if begin < x < end]
    assert sim.info.step > 10
    assert len(inside) >= 3, "the worker thread never ran while run_until stepped: the GIL was held"


def test_an_exception_in_the_callback_stops_the_run_and_reaches_the_caller():
    sim = clsph.Simulation(clsph.scene(HYDROSTATIC), devices=first_device())

    def callback(s):
        if s.step == 7:
            raise ValueError("stop at step 7")

    with pytest.raises(ValueError, match="stop at step 7"):
        sim.run_until(1.0, callback)
    assert sim.info.step == 7


def test_python_m_clsph_runs_the_tool():
    env = dict(os.environ, CLSPH_TOOL=TOOL)
    r = subprocess.run([sys.executable, "-m", "clsph", "devices", "--devices", "all"], env=env, capture_output=True, text=True)
    assert r.returncode == 0, r.stderr
    assert "selection 'all' picks" in r.stdout


def test_the_example_runs_at_a_coarse_resolution(tmp_path):
    example = os.path.join(SOURCE, "examples", "python", "dam_break.py")
    r = subprocess.run([sys.executable, example, "--coarse", "--until", "0.2", "--out", str(tmp_path),
                        "--devices", first_device()],
                       capture_output=True, text=True, cwd=SOURCE)
    assert r.returncode == 0, r.stdout + r.stderr
    assert (tmp_path / "surge_front.png").stat().st_size > 1000
    assert (tmp_path / "surge_front.csv").read_text().count("\n") > 5


def test_ctrl_c_stops_run_until_at_the_end_of_a_step():
    import signal
    sim = clsph.Simulation(clsph.scene(HYDROSTATIC), devices=first_device())
    sim.step()  # kernels built, so the interrupt lands while stepping
    timer = threading.Timer(0.3, lambda: os.kill(os.getpid(), signal.SIGINT))
    timer.start()
    try:
        with pytest.raises(KeyboardInterrupt):
            sim.run_until(1000.0)  # far more than the test would wait for
    finally:
        timer.cancel()
    assert 1 < sim.info.step and sim.time < 1000.0
    sim.step()  # the simulation is still usable after the interrupt


def by_id(p):
    """The particle dict's arrays in id order (frames and devices order particles differently)."""
    order = np.argsort(p["id"], kind="stable")
    return {k: v[order] for k, v in p.items()}


def assert_same_particles(a, b):
    a, b = by_id(a), by_id(b)
    assert sorted(a) == sorted(b)
    for k in a:
        assert a[k].shape == b[k].shape, k
        assert a[k].dtype == b[k].dtype, k
        assert np.array_equal(a[k], b[k]), k


def test_a_simulation_takes_a_path_a_dict_or_a_scene_with_overrides_as_dict_or_strings():
    device = first_device()
    with open(HYDROSTATIC) as f:
        doc = json.load(f)
    runs = [
        clsph.Simulation(HYDROSTATIC, devices=device),
        clsph.Simulation(doc, devices=device),
        clsph.Simulation(clsph.scene(HYDROSTATIC), devices=device),
    ]
    for sim in runs:
        assert isinstance(sim, clsph.Simulation)
        for _ in range(5):
            sim.step()
    first = runs[0].particles()
    assert len(first["id"]) > 0
    for sim in runs[1:]:
        assert_same_particles(first, sim.particles())
    # overrides: a dict and the same KEY=VALUE strings give the same scene, on a file and on a dict
    as_dict = {"physics.dp": 0.03, "run.end_time": 0.5}
    as_strings = ["physics.dp=0.03", "run.end_time=0.5"]
    a = clsph.scene_dict(clsph.scene(HYDROSTATIC, as_dict))
    assert a == clsph.scene_dict(clsph.scene(HYDROSTATIC, as_strings))
    assert a == clsph.scene_dict(clsph.scene(doc, as_dict))
    assert a["physics"]["dp"] == 0.03 and a["physics"]["dp"] != clsph.scene_dict(clsph.scene(doc))["physics"]["dp"]
    sim = clsph.Simulation(doc, overrides=as_dict, devices=device)
    assert sim.scene.dp == 0.03
    # a bad override names the key and says it came from the override, for a dict source too
    with pytest.raises(clsph.SceneError, match=r"physics\.dp.*physics\.dp=-1"):
        clsph.Simulation(doc, overrides={"physics.dp": -1}, devices=device)
    with pytest.raises(TypeError):
        clsph.Simulation(HYDROSTATIC, overrides="physics.dp=0.03")
    with pytest.raises(clsph.Error):
        clsph.scene(clsph.scene(HYDROSTATIC), {"physics.dp": 0.03})


def test_read_frame_reads_every_frame_clsph_writes_as_particles_gives_them(tmp_path):
    device = first_device()
    sim = clsph.Simulation(HYDROSTATIC, devices=device)
    for _ in range(20):
        sim.step()
    want = sim.particles()
    frames = {}
    for label, extra in [("raw", []), ("compressed", ["--compress"]), ("pieces", ["--pieces"]), ("csv", ["--csv"])]:
        out = tmp_path / label
        subprocess.run([TOOL, "run", HYDROSTATIC, "--steps", "20", "--every", "1000", "--devices", device,
                        "--out", str(out)] + extra, check=True, stdout=subprocess.DEVNULL)
        pattern = {"pieces": "*.pvtu", "csv": "frame_*.csv"}.get(label, "frame_*.vtu")
        found = sorted(out.glob(pattern))
        assert found, "%s: no %s in %s" % (label, pattern, out)
        frames[label] = found[-1]
    for label, path in frames.items():
        got = clsph.read_frame(str(path))
        # every format holds the state exactly: positions in float64, the rest in float32
        assert_same_particles(want, got)
    with pytest.raises(clsph.Error, match="not a frame"):
        clsph.read_frame(str(tmp_path / "raw" / "run.json"))
    with pytest.raises(clsph.Error):
        clsph.read_frame(str(tmp_path / "no_such_frame.vtu"))


def test_help_shows_the_docstrings():
    assert "dict" in clsph.Simulation.__doc__ and "overrides" in clsph.Simulation.__doc__
    assert "frame" in clsph.read_frame.__doc__
    assert "KEY=VALUE" in clsph.scene.__doc__
