"""gonio.Design (a design file in memory: variables by name, set, write,
STEP export) and gonio.simulate of a Design without writing a file
(ctest label `python`)."""
import pathlib

import numpy as np
import pytest

import gonio

RUN = dict(photons=20000, iterations=1, seed=3, threads=1, gamma_step=2.5)

# A paraboloid with its focus at an isotropic source, its radius a variable.
DESIGN = """length_unit = "mm"

[materials.mirror]
mirror = 1.0

[[emitters]]
name = "LED"
position = [0, 0, 0]
flux_lm = 1000

[[reflectors]]
name = "dish"
material = "mirror"
profile = "conic"
radius = { value = 20, min = 10, max = 40, name = "R" }
conic = -1
vertex = { value = 10, min = 5, max = 20 }
aperture = [4, 30]
"""


@pytest.fixture
def design_file(tmp_path):
    path = tmp_path / "lamp.design.toml"
    path.write_text(DESIGN)
    return path


def test_variables_bounds_set_and_write(design_file, tmp_path):
    d = gonio.Design(design_file)
    assert d.path == str(design_file)
    assert d.variables == {"R": 20.0, "reflectors[0].vertex": 10.0}
    assert d.bounds == {"R": (10.0, 40.0), "reflectors[0].vertex": (5.0, 20.0)}
    d.set("R", 25.0)
    assert d.variables["R"] == 25.0
    with pytest.raises(gonio.GonioError, match="outside its bounds"):
        d.set("R", 50.0)
    with pytest.raises(gonio.GonioError, match="no variable"):
        d.set("radius", 20.0)
    assert d.variables["R"] == 25.0  # a refused value changes nothing
    d.write(tmp_path / "written.design.toml")
    again = gonio.Design(tmp_path / "written.design.toml")
    assert again.variables == {"R": 25.0, "reflectors[0].vertex": 10.0}
    assert again.bounds == d.bounds


def test_bad_design_files_name_the_line(tmp_path):
    bad = tmp_path / "bad.design.toml"
    bad.write_text(DESIGN.replace("aperture = [4, 30]", "aperture = [4, 30]\ncolour = 1"))
    d = gonio.Design(bad)  # the parts are checked when simulated or exported
    with pytest.raises(gonio.GonioError) as e:
        gonio.simulate(d, **RUN)
    assert e.value.file == str(bad) and e.value.line == 19, str(e.value)
    with pytest.raises(gonio.GonioError, match="not a design file"):
        gonio.Design(tmp_path / "lamp.toml")
    with pytest.raises(gonio.GonioError):
        gonio.Design(tmp_path / "absent.design.toml")


def test_simulate_takes_the_design_in_memory(design_file, tmp_path):
    d = gonio.Design(design_file)
    from_file = gonio.simulate(design_file, **RUN)
    in_memory = gonio.simulate(d, **RUN)
    # The same scene, the same seed: the same candela.
    assert np.array_equal(in_memory.photometry.candela, from_file.photometry.candela)
    assert in_memory.model == str(design_file)
    # Set, not written: the run sees the new value, the file is unchanged.
    text = design_file.read_text()
    d.set("reflectors[0].vertex", 15.0)
    moved = gonio.simulate(d, **RUN)
    assert design_file.read_text() == text
    assert not np.array_equal(moved.photometry.candela, from_file.photometry.candela)
    # ... and it is what the file with that value gives.
    d.write(tmp_path / "moved.design.toml")
    written = gonio.simulate(tmp_path / "moved.design.toml", **RUN)
    assert np.array_equal(moved.photometry.candela, written.photometry.candela)
    # Nothing was written for the in-memory runs.
    assert sorted(p.name for p in tmp_path.iterdir()) == ["lamp.design.toml", "moved.design.toml"]


def test_export_step(design_file, tmp_path):
    d = gonio.Design(design_file)
    d.set("R", 24.0)
    try:
        info = d.export_step(tmp_path / "cad" / "lamp.step", tolerance_mm=0.0005)
    except gonio.GonioError as e:
        if "OpenCASCADE" in str(e) or "gonio-cad" in str(e):
            from conftest import missing
            missing(f"the STEP writer: {e}")
        raise
    assert info["parts"] == 1
    assert 0.0 <= info["max_deviation_mm"] <= 0.0005
    assert pathlib.Path(info["step"]).read_text().startswith("ISO-10303-21;")
    assert "match = \"dish\"" in pathlib.Path(info["sidecar"]).read_text()
    with pytest.raises(ValueError):
        d.export_step(tmp_path / "x.step", tolerance_mm=0.0)
