"""gonio.simulate against `gonio simulate` (the same bytes for the same
seed), its result (far field, candela table, ledger, estimate), and how it
stops: the callback, Ctrl-C, an exception (ctest label `python`)."""
import base64
import json
import math
import os
import pathlib
import signal
import struct
import subprocess
import sys
import threading
import time

import numpy as np
import pytest

import gonio
from conftest import run_gonio

RUN = dict(photons=30000, iterations=2, seed=7)


@pytest.fixture(scope="module")
def bell(samples):
    path = samples / "bell" / "bell.gltf"
    if not path.exists():
        pytest.fail(f"{path} missing (the gonio_samples target writes it)")
    return path


def command(gonio_exe, model, out, *extra):
    return run_gonio(gonio_exe, "simulate", model, "--out", out, "--photons", RUN["photons"], "--iterations",
                     RUN["iterations"], "--seed", RUN["seed"], *extra)


def test_the_same_seed_writes_the_commands_bytes(bell, gonio_exe, tmp_path):
    code, _, err = command(gonio_exe, bell, tmp_path / "cmd", "--threads", "2")
    assert code == 0, err
    result = gonio.simulate(bell, out=tmp_path / "py", threads=1, **RUN)
    assert result.exit_code == 0
    written = sorted(p.name for p in (tmp_path / "cmd").iterdir())
    assert sorted(p.name for p in (tmp_path / "py").iterdir()) == written
    for name in written:
        if name != "report.json":  # it holds times
            assert (tmp_path / "cmd" / name).read_bytes() == (tmp_path / "py" / name).read_bytes(), name
    a = json.loads((tmp_path / "cmd" / "report.json").read_text())
    for key in ("photons_emitted", "photons_escaped", "photons_absorbed", "emitted_lm", "escaped_lm"):
        assert result.report[key] == a[key], key
    # report.json's figures that hold no time, path or thread count: the
    # same loop (app::simulate) wrote both. (Python always makes the
    # estimate, for its callback; the command only for --target-error.)
    assert a["estimated_rms_error_pct"] is None and result.report["estimated_rms_error_pct"] > 0
    for key in ("emitters", "materials", "meshes", "far_field", "iterations_done", "stopped_by", "ledger",
                "next_event"):
        assert result.report[key] == a[key], key
    for key in ("grid", "symmetry", "escaped_lm"):
        assert result.report["outputs"][key] == a["outputs"][key], key
    for mine, theirs in zip(result.report["outputs"]["files"], a["outputs"]["files"]):
        assert {k: v for k, v in mine.items() if k != "path"} == {k: v for k, v in theirs.items() if k != "path"}
    assert sorted(pathlib.Path(f).name for f in result.files) == sorted(n for n in written if n != "report.json")


def test_the_result_holds_the_far_field_the_table_and_closed_books(bell, tmp_path):
    r = gonio.simulate(bell, out=tmp_path, **RUN)
    led = r.ledger
    assert led["photons_close"]
    assert led["emitted"]["photons"] == led["escaped"]["photons"] + led["absorbed"]["photons"] + led["cutoff"]["photons"]
    assert r.photons == RUN["photons"] * RUN["iterations"] == led["emitted"]["photons"]
    ff = r.far_field
    n = ff.face_size
    assert ff.flux_lm.shape == ff.photons.shape == (6, n, n)
    assert not ff.flux_lm.flags.writeable and not ff.flux_lm.flags.owndata  # a view of the result
    # The cube map holds every escaped photon and its flux.
    assert int(ff.photons.sum()) == led["escaped"]["photons"]
    assert ff.flux_lm.sum() == pytest.approx(led["escaped"]["flux_lm"], rel=1e-12)
    assert ff.solid_angle_sr.sum() == pytest.approx(4 * np.pi, rel=1e-12)
    assert np.allclose(ff.intensity_cd * ff.solid_angle_sr, ff.flux_lm, rtol=1e-12, atol=0)
    # The candela table is the one the IES file holds (read back at the
    # file's printed precision).
    table = r.photometry
    ies = gonio.read(tmp_path / "bell.ies")
    assert table.format is None and table.candela.shape == ies.candela.shape
    assert np.allclose(table.candela, ies.candela, rtol=1e-5, atol=1e-6)
    assert table.summary()["flux_lm"] == pytest.approx(r.report["outputs"]["files"][0]["flux_lm"], rel=1e-6)
    assert 0 < r.estimated_rms_error_pct < 100 and r.stopped_by == "iterations"
    # Without `out`: the same far field, nothing written.
    bare = gonio.simulate(bell, **RUN)
    assert bare.files == [] and bare.report is None
    assert np.array_equal(bare.far_field.photons, ff.photons)
    assert np.array_equal(bare.photometry.candela, table.candela)


def sealed_white_box(path, reflectance):
    """A closed box 0.2 m a side, Lambertian white (extras.gonio kd) inside
    and out, with a 1000 lm point light at its centre: a glTF with its
    buffer in a data URI. No light leaves it."""
    h = 0.1
    corners = [(x, y, z) for x in (-h, h) for y in (-h, h) for z in (-h, h)]
    # Two triangles per face, wound so that the front faces outwards.
    quads = [(0, 1, 3, 2), (4, 6, 7, 5), (0, 4, 5, 1), (2, 3, 7, 6), (0, 2, 6, 4), (1, 5, 7, 3)]
    indices = [i for a, b, c, d in quads for i in (a, b, c, a, c, d)]
    blob = struct.pack(f"<{3 * len(corners)}f", *[v for c in corners for v in c]) + struct.pack(
        f"<{len(indices)}I", *indices)
    positions = 12 * len(corners)
    g = {
        "asset": {"version": "2.0"},
        "extensionsUsed": ["KHR_lights_punctual"],
        "extensions": {"KHR_lights_punctual": {"lights": [{"type": "point", "intensity": 1000.0 / (4 * math.pi)}]}},
        "scene": 0,
        "scenes": [{"nodes": [0, 1]}],
        "nodes": [{"name": "box", "mesh": 0}, {"name": "lamp", "extensions": {"KHR_lights_punctual": {"light": 0}}}],
        "meshes": [{"name": "box", "primitives": [{"attributes": {"POSITION": 0}, "indices": 1, "material": 0}]}],
        "materials": [{"name": "white", "extras": {"gonio": {"kd": reflectance}}}],
        "buffers": [{"byteLength": len(blob),
                     "uri": "data:application/octet-stream;base64," + base64.b64encode(blob).decode()}],
        "bufferViews": [{"buffer": 0, "byteOffset": 0, "byteLength": positions},
                        {"buffer": 0, "byteOffset": positions, "byteLength": len(blob) - positions}],
        "accessors": [{"bufferView": 0, "componentType": 5126, "count": len(corners), "type": "VEC3",
                       "min": [-h, -h, -h], "max": [h, h, h]},
                      {"bufferView": 1, "componentType": 5125, "count": len(indices), "type": "SCALAR"}],
    }
    path.write_text(json.dumps(g))
    return path


def test_the_ledger_tells_cut_off_from_absorbed(tmp_path):
    """Issue 45, case 9: in a sealed box of reflectance ρ a photon survives
    each hit with chance ρ and is cut off at hit B + 1: with B = 2 bounces
    allowed, ρ² = 0.64 of the photons are cut off and 0.36 absorbed, by
    photon and by flux, in total, for the lamp, and at the box (mesh and
    material). `absorbed` and `cutoff` swapped in the module would read
    0.36 and 0.64; four standard deviations here are 0.008."""
    rho, bounces, photons = 0.8, 2, 40000
    model = sealed_white_box(tmp_path / "sealed.gltf", rho)
    r = gonio.simulate(model, photons=photons, iterations=1, seed=3, max_bounces=bounces)
    led = r.ledger
    assert led["photons_close"]
    assert led["emitted"]["photons"] == photons and led["escaped"]["photons"] == 0
    cut, absorbed = rho**bounces, 1 - rho**bounces
    tol = 4 * math.sqrt(cut * absorbed / photons)
    for books in (led, led["emitters"][0]):
        assert books["cutoff"]["photons"] / photons == pytest.approx(cut, abs=tol)
        assert books["absorbed"]["photons"] / photons == pytest.approx(absorbed, abs=tol)
        assert books["cutoff"]["flux_lm"] / books["emitted"]["flux_lm"] == pytest.approx(cut, abs=tol)
        assert books["absorbed"]["flux_lm"] / books["emitted"]["flux_lm"] == pytest.approx(absorbed, abs=tol)
    for part in (led["meshes"][0], led["materials"][0]):
        assert part["cutoff"]["photons"] == led["cutoff"]["photons"]
        assert part["absorbed"]["photons"] == led["absorbed"]["photons"]


def test_threads_do_not_change_a_photon(bell):
    one = gonio.simulate(bell, threads=1, **RUN)
    two = gonio.simulate(bell, threads=2, **RUN)
    assert np.array_equal(one.far_field.photons, two.far_field.photons)
    assert np.array_equal(one.far_field.flux_lm, two.far_field.flux_lm)


def test_the_callback_sees_each_iteration_and_can_stop_the_run(bell, tmp_path):
    seen = []

    def each(it):
        seen.append((it.iteration, it.iterations, it.photons_done, it.estimated_rms_error_pct))
        return it.iteration < 3  # stop after the third

    r = gonio.simulate(bell, photons=20000, iterations=10, seed=3, on_iteration=each, out=tmp_path / "out")
    assert [s[0] for s in seen] == [1, 2, 3]
    assert [s[2] for s in seen] == [20000, 40000, 60000]
    # The estimate falls as photons add up (here 1/√N within noise).
    assert seen[2][3] < seen[0][3]
    assert r.stopped_by == "cancelled" and r.iterations_done == 3 and r.photons == 60000
    # What was traced is kept, and written where asked.
    assert r.report["photons_emitted"] == 60000
    assert r.report["stopped_by"] == "cancelled"


def test_a_run_the_callback_stopped_writes_the_bytes_of_that_many_iterations(bell, gonio_exe, tmp_path):
    """Stopped after 3 of 10 iterations, the files are those of `gonio
    simulate --iterations 3` with the same seed (app::simulate's
    keep_when_stopped: photon i draws from (seed, i) alone)."""
    code, _, err = run_gonio(gonio_exe, "simulate", bell, "--out", tmp_path / "cmd", "--photons", 20000,
                             "--iterations", 3, "--seed", 3)
    assert code == 0, err
    r = gonio.simulate(bell, photons=20000, iterations=10, seed=3, out=tmp_path / "py",
                       on_iteration=lambda it: it.iteration < 3)
    assert r.stopped_by == "cancelled" and r.iterations_done == 3 and r.exit_code == 0
    written = sorted(p.name for p in (tmp_path / "cmd").iterdir())
    assert sorted(p.name for p in (tmp_path / "py").iterdir()) == written
    for name in written:
        if name != "report.json":
            assert (tmp_path / "cmd" / name).read_bytes() == (tmp_path / "py" / name).read_bytes(), name


def test_a_model_with_errors_raises_its_first_error(tmp_path):
    """The error app::simulate stops on is raised with its file (on_failed)."""
    bad = tmp_path / "bad.gltf"
    bad.write_text('{"asset": {"version": "2.0"}, "scenes": [{"nodes": [0]}], "nodes": [{"mesh": 7}]}')
    with pytest.raises(gonio.GonioError) as caught:
        gonio.simulate(bad, photons=1000, iterations=1)
    assert caught.value.file == str(bad)


def test_an_exception_in_the_callback_stops_the_run_and_propagates(bell, tmp_path):
    def each(it):
        raise RuntimeError("enough")

    with pytest.raises(RuntimeError, match="enough"):
        gonio.simulate(bell, photons=20000, iterations=10, on_iteration=each, out=tmp_path / "out")
    assert not any((tmp_path / "out").iterdir())  # nothing written


def test_target_error_stops_where_the_command_stops(bell, gonio_exe, tmp_path):
    code, _, err = run_gonio(gonio_exe, "simulate", bell, "--out", tmp_path / "cmd", "--photons", 20000,
                             "--iterations", 50, "--target-error", 2, "--seed", 5)
    assert code == 0, err
    report = json.loads((tmp_path / "cmd" / "report.json").read_text())
    r = gonio.simulate(bell, photons=20000, iterations=50, target_error=2, seed=5)
    assert r.stopped_by == report["stopped_by"] == "target-error"
    assert r.iterations_done == report["iterations_done"] < 50
    assert r.estimated_rms_error_pct <= 2.0


def test_ctrl_c_stops_the_run_cleanly(bell, tmp_path):
    """A real SIGINT to a Python process tracing a long run: it raises
    KeyboardInterrupt within a slice of photons, not after the run, and
    writes nothing."""
    out = tmp_path / "out"
    script = (
        "import sys, gonio\n"
        "def each(it):\n"
        "    print('iteration', it.iteration, flush=True)\n"
        f"gonio.simulate({str(bell)!r}, photons=200000, iterations=1000, out={str(out)!r}, on_iteration=each)\n"
    )
    p = subprocess.Popen([sys.executable, "-c", script], stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True,
                         env=os.environ)
    assert p.stdout.readline().startswith("iteration 1")  # tracing, past the setup
    p.send_signal(signal.SIGINT)
    try:
        _, err = p.communicate(timeout=120)
    except subprocess.TimeoutExpired:
        p.kill()
        pytest.fail("Ctrl-C did not stop the run")
    assert p.returncode != 0
    assert "KeyboardInterrupt" in err
    assert not any(out.iterdir())


def test_the_gil_is_released_while_tracing(bell):
    """Another Python thread runs while simulate traces. With a switch
    interval of 100 s a waiting thread gets the GIL only when its holder
    gives it up, so the ticks counted between the first and the last
    iteration's callback are the GIL given up while tracing (none if simulate
    held it)."""
    old = sys.getswitchinterval()
    sys.setswitchinterval(100.0)
    done = threading.Event()
    ticks = [0]

    def tick():
        while not done.is_set():
            ticks[0] += 1
            time.sleep(0.001)  # gives the GIL up, and waits for it after

    t = threading.Thread(target=tick)
    marks = []
    try:
        t.start()
        r = gonio.simulate(bell, photons=100000, iterations=4, threads=1, on_iteration=lambda it: marks.append(ticks[0]))
    finally:
        done.set()
        t.join()
        sys.setswitchinterval(old)
    assert r.iterations_done == 4 and len(marks) == 4
    assert marks[-1] - marks[0] >= 20, marks


def test_errors_name_the_model_and_arguments_are_checked(tmp_path, bell):
    with pytest.raises(gonio.GonioError) as caught:
        gonio.simulate(tmp_path / "none.gltf", photons=1000, iterations=1)
    assert caught.value.file == str(tmp_path / "none.gltf")
    for bad in (dict(sampler="halton"), dict(c_step=7.0), dict(symmetry="hexagonal"), dict(formats="ies,png"),
                dict(photons=0), dict(ies_version="1995")):
        with pytest.raises(ValueError):
            gonio.simulate(bell, **{**dict(photons=1000, iterations=1), **bad})
