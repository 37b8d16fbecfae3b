"""gonio.tolerance: gonio tolerance's own run (tools/run/tolerance_run.h)
from Python: the Monte Carlo trials as numpy arrays per figure, the
sensitivity table and the noise floor equal to the command's report.json
for the same inputs and seeds, and errors naming the file (ctest label
`python`)."""
import json

import numpy as np
import pytest

import gonio
from conftest import run_gonio

# A conic dish over an isotropic point emitter "LED".
DESIGN = """length_unit = "mm"
[materials.mirror]
reflectance = 0.9
[[emitters]]
name = "LED"
position = [0, 0, 0]
flux_lm = 1000
[[reflectors]]
name = "dish"
material = "mirror"
profile = "conic"
radius = 10
conic = -1.5
vertex = 5
aperture = [2, 30]
"""

TOLERANCES = """[emitter.LED]
x = { uniform = 0.5 }
z = { normal = 0.2 }

[material.mirror]
reflectance = { uniform = 5 }
"""

# Small budgets: a few seconds a run.
RUN = dict(trials=4, spec="beam_c0=0..200,flux=850..", seed=3, noise_seeds=2, sampling_seed=5, photons=5000,
           threads=1)
CLI = ["--trials", "4", "--spec", "beam_c0=0..200,flux=850..", "--seed", "3", "--noise-seeds", "2",
       "--sampling-seed", "5", "--photons", "5000", "--threads", "1"]


@pytest.fixture(scope="module")
def setup(tmp_path_factory):
    d = tmp_path_factory.mktemp("tolerance")
    (d / "dish.design.toml").write_text(DESIGN)
    (d / "t.toml").write_text(TOLERANCES)
    return d


def test_equals_the_command(setup, gonio_exe):
    d = setup
    code, _, err = run_gonio(gonio_exe, "tolerance", d / "dish.design.toml", "--tolerances", d / "t.toml", "--out",
                             d / "cli", *CLI)
    assert code == 0, err
    report = json.loads((d / "cli" / "report.json").read_text())

    result = gonio.tolerance(d / "dish.design.toml", d / "t.toml", **RUN)
    trials = report["monte_carlo"]["trials"]
    assert len(trials) == 4
    assert set(result["trials"]) == set(report["nominal"])
    for key, values in result["trials"].items():
        assert isinstance(values, np.ndarray) and values.shape == (4,)
        # null in report.json (a figure the model does not define: CCT in a grey run) is NaN here.
        expected = [np.nan if t["figures"][key] is None else t["figures"][key] for t in trials]
        np.testing.assert_array_equal(values, expected, err_msg=key)
    for name, values in result["values"].items():
        np.testing.assert_array_equal(values, [t["values"][name] for t in trials], err_msg=name)
    # The trials differ: the tolerances were applied.
    assert np.ptp(result["trials"]["flux"]) > 0
    assert result["noise_floor"] == report["noise"]["floor"]
    assert result["nominal"] == report["nominal"]
    assert result["yield"] == report["monte_carlo"]["yield"]
    rows = [dict(r, figure=key, unit=f["unit"]) for key, f in report["sensitivity"].items() for r in f["rows"]]
    assert result["sensitivity"] == rows
    defined = [k for k, v in report["nominal"].items() if v is not None]
    assert len(result["sensitivity"]) == 3 * len(defined)
    # The figures beside the photometric ones: UGR 4H×8H, BUG, the beam axis; CCT and Δu′v′ only in
    # spectral runs (NaN here).
    for key in ("ugr", "bug_b", "bug_u", "bug_g", "axis_c0", "axis_c90"):
        assert key in defined, key
    assert np.all(np.isnan(result["trials"]["cct"])) and np.all(np.isnan(result["trials"]["duv_max"]))
    assert set(result["trials"]["bug_g"]) <= {0.0, 1.0, 2.0, 3.0, 4.0, 5.0}
    assert result["timing"]["traces"] == len(result["timing"]["seconds"])
    assert result["table"] == (d / "cli" / "sensitivity.txt").read_text()


def test_errors_name_the_file(setup, tmp_path):
    d = setup
    bad = tmp_path / "bad.toml"
    bad.write_text("[emitter.LED]\n\nx = { uniform = 1, normal = 1 }\n")
    with pytest.raises(gonio.GonioError, match=r"bad\.toml:3: emitter\.LED\.x: give exactly one of"):
        gonio.tolerance(d / "dish.design.toml", bad, **RUN)
    bad.write_text("[emitter.lamp]\nx = { uniform = 1 }\n")
    with pytest.raises(gonio.GonioError, match=r"bad\.toml:2: the model has no emitter 'lamp'"):
        gonio.tolerance(d / "dish.design.toml", bad, **RUN)
    with pytest.raises(ValueError, match="unknown figure"):
        gonio.tolerance(d / "dish.design.toml", d / "t.toml", spec="beam=1..2")


def test_design_tolerances_and_traced_inverse(setup, tmp_path):
    """A design's own [tolerances] (tolerances None), and the traced inverse sensitivity's new values."""
    design = DESIGN.replace("radius = 10", "radius = { value = 10 }") + (
        '\n[tolerances]\n"reflectors[0].radius" = { uniform = 0.5 }\n[tolerances.material.mirror]\n'
        "reflectance = { uniform = 5 }\n")
    (tmp_path / "own.design.toml").write_text(design)
    result = gonio.tolerance(tmp_path / "own.design.toml", None, trials=2, spec="flux>=880", seed=3, noise_seeds=1,
                             photons=5000, threads=1, inverse_steps=2, parallel_trials=2)
    names = [t["name"] for t in result["report"]["tolerances"]]
    assert sorted(names) == ["mirror.reflectance", "reflectors[0].radius"]
    assert result["values"]["reflectors[0].radius"].shape == (2,)
    flux = [e for e in result["inverse_sensitivity"] if e["tolerance"] == "mirror.reflectance"][0]
    assert flux["scale"] is not None and "traced_scale" in flux
    assert flux["traced_fails_at"] is None or flux["traced_scale"] <= flux["traced_fails_at"]


def test_percentile_trials_equal_the_command(setup, gonio_exe, tmp_path):
    """percentile: the same trials as the command's --percentile, nearest rank of their figure, with their files."""
    d = setup
    code, _, err = run_gonio(gonio_exe, "tolerance", d / "dish.design.toml", "--tolerances", d / "t.toml", "--out",
                             tmp_path / "cli", *CLI, "--percentile", "50,flux:25")
    assert code == 0, err
    report = json.loads((tmp_path / "cli" / "report.json").read_text())
    result = gonio.tolerance(d / "dish.design.toml", d / "t.toml", **RUN, percentile="50,flux:25",
                             out=tmp_path / "py")
    assert result["percentile_trials"] == report["monte_carlo"]["percentile_trials"]
    # Nearest rank of 4 trials: 50 % is rank 2 by the RMS difference, 25 % rank 1 by flux.
    for entry, figure, rank in zip(result["percentile_trials"], ["rms", "flux"], [2, 1]):
        order = np.argsort(result["trials"][figure], kind="stable")
        assert entry["figure"] == figure and entry["rank"] == rank
        assert entry["trial"] == order[rank - 1] + 1
        for name in entry["files"]:
            assert (tmp_path / "py" / name).read_bytes() == (tmp_path / "cli" / name).read_bytes()
    with pytest.raises(ValueError, match="--percentile '101'"):
        gonio.tolerance(d / "dish.design.toml", d / "t.toml", **RUN, percentile="101")


def test_luminance_image_gives_the_commands_cie232_figures(setup, gonio_exe, tmp_path):
    """luminance_image: every trace's CIE 232 dugr and ugr_cie232, the same as the command's --luminance-image;
    without it they are not defined (NaN)."""
    d = setup
    code, _, err = run_gonio(gonio_exe, "tolerance", d / "dish.design.toml", "--tolerances", d / "t.toml", "--out",
                             tmp_path / "cli", *CLI, "--luminance-image", "ugr")
    assert code == 0, err
    report = json.loads((tmp_path / "cli" / "report.json").read_text())
    result = gonio.tolerance(d / "dish.design.toml", d / "t.toml", **RUN, luminance_image="ugr")
    for figure in ("dugr", "ugr_cie232"):
        expected = np.array([t["figures"][figure] for t in report["monte_carlo"]["trials"]], dtype=float)
        assert np.isfinite(expected).all()
        np.testing.assert_array_equal(result["trials"][figure], expected)
    plain = gonio.tolerance(d / "dish.design.toml", d / "t.toml", **RUN)
    assert np.isnan(plain["trials"]["dugr"]).all()
    with pytest.raises(ValueError, match="--luminance-image"):
        gonio.tolerance(d / "dish.design.toml", d / "t.toml", **RUN, luminance_image="C0")
