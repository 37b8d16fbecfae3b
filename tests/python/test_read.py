"""gonio.read and the Photometry object: arrays without copies, figures as
gonio info --json gives them, errors with file and line, writing and
comparing (ctest label `python`)."""
import ast
import gc
import math
import pathlib
import shutil
import warnings

import numpy as np
import pytest

import gonio
from conftest import info_json, run_gonio


def test_reads_angles_and_candela_as_the_command_does(curves, gonio_exe):
    p = gonio.read(curves / "downlight.ies")
    info = info_json(gonio_exe, curves / "downlight.ies")
    assert p.format == "IES" and p.version == "LM-63-2019" and p.photometric_type == "C"
    assert p.vertical_deg.tolist() == info["vertical_angles"]["angles_deg"]
    assert p.horizontal_deg.tolist() == info["horizontal_angles"]["angles_deg"]
    assert p.candela.shape == (len(p.horizontal_deg), len(p.vertical_deg))
    assert p.candela.dtype == np.float64
    # The peak of the table is the command's max_cd (info finds it in the same table).
    assert p.candela.max() == info["max_cd"]
    assert p.lamps[0]["flux_lm"] == info["lamps"][0]["flux_lm"]
    assert p.opening["shape"] == info["luminous_opening"]["shape"]
    assert ("LUMCAT", "DL-68") in p.keywords


def test_the_openings_length_and_width_are_the_files_and_the_commands(curves, gonio_exe):
    """Issue 45, case 9: the wall washer's opening is 0.12 m long (along
    C0-C180) and 0.09 m wide (C90-C270): the IES file's line holds width
    0.09, length 0.12 in metres, and the LDT the same. Length and width
    swapped in the module would still pass a square opening; this one is
    not."""
    for name in ("wall_washer.ies", "wall_washer.ldt"):
        p = gonio.read(curves / name)
        info = info_json(gonio_exe, curves / name)["luminous_opening"]
        assert p.opening["length_m"] != p.opening["width_m"], name
        for key in ("shape", "length_m", "width_m", "height_m"):
            assert p.opening[key] == info[key], (name, key)
        assert p.opening["length_m"] == pytest.approx(0.12, abs=1e-9), name
        assert p.opening["width_m"] == pytest.approx(0.09, abs=1e-9), name


def test_arrays_are_views_of_the_photometry_not_copies(curves, tmp_path):
    """A copy would not see the write, nor would write() write it."""
    p = gonio.read(curves / "downlight.ldt")
    table = p.candela
    assert not table.flags.owndata
    table[0, 0] = 12345.0
    assert p.candela[0, 0] == 12345.0
    assert np.shares_memory(p.candela, table)
    p.write(tmp_path / "changed.ldt")
    assert gonio.read(tmp_path / "changed.ldt").candela[0, 0] == pytest.approx(12345.0, rel=1e-3)
    # The view keeps the photometry alive after the last other reference.
    angles = p.vertical_deg
    expected = angles.tolist()
    del p, table
    gc.collect()
    assert angles.tolist() == expected


def test_a_scaled_copy_compares_as_its_scale(curves):
    """photometry/compare.h: B = s·A gives max_relative exactly |s − 1| and
    the flux ratio s, whatever the distribution."""
    a = gonio.read(curves / "wall_washer.ies")
    b = gonio.read(curves / "wall_washer.ies")
    b.candela[:] *= 1.25  # in place, through the view
    c = gonio.compare(a, b)
    assert c["max_relative"] == pytest.approx(0.25, abs=1e-12)
    assert c["flux_ratio"] == pytest.approx(1.25, rel=1e-12)
    assert gonio.compare(a, curves / "wall_washer.ies")["rms_relative"] == 0.0
    # normalize scales B back to A's flux: nothing left.
    assert gonio.compare(a, b, normalize=True)["max_relative"] == pytest.approx(0.0, abs=1e-12)


def test_compare_gives_the_commands_json(curves, gonio_exe):
    import json

    a, b = curves / "downlight.ies", curves / "downlight.ldt"
    code, out, err = run_gonio(gonio_exe, "compare", "--json", a, b)
    assert code == 0, err
    assert gonio.compare(a, b) == json.loads(out)


def test_summary_is_info_json(curves, gonio_exe):
    for name in ("downlight.ies", "downlight.ldt", "wall_washer.ies", "wall_washer.ldt"):
        p = gonio.read(curves / name)
        info = info_json(gonio_exe, curves / name)
        s = p.summary()
        assert s["flux_lm"] > 0
        for key, value in s.items():
            assert info[key] == value, (name, key)
        assert p.info() == info
        assert p.ugr_table() == info["ugr_table"]
        assert p.cu_table() == info["cu_table"]
        assert p.bug() == info["bug"]
        assert p.spacing_criterion() == info["spacing_criterion"]
        assert p.luminance_table() == info["luminance_table"]


def test_options_reach_the_figures(curves, gonio_exe):
    p = gonio.read(curves / "downlight.ldt")
    info = info_json(gonio_exe, curves / "downlight.ldt", "--cu-floor", "0.1", "--ugr-background", "flux-transfer")
    assert p.cu_table(floor_reflectance=0.1) == info["cu_table"]
    assert p.ugr_table(background="flux-transfer") == info["ugr_table"]
    assert p.cu_table(0.1) != p.cu_table(0.2)
    with pytest.raises(ValueError):
        p.cu_table(floor_reflectance=1.5)
    with pytest.raises(ValueError):
        p.ugr_table(background="dialux")


def test_an_undefined_figure_is_none_and_says_why(corpus):
    """A point opening has no luminous area: no luminance table (info's
    luminance_table_why)."""
    p = gonio.read(corpus / "photometric-viewer" / "point_opening.ies")
    with pytest.warns(gonio.UndefinedFigureWarning, match="luminance_table: "):
        assert p.luminance_table() is None


def test_a_malformed_file_raises_with_its_file_and_line(curves, gonio_exe, tmp_path):
    lines = (curves / "downlight.ies").read_text(encoding="latin-1").splitlines()
    bad_line = len(lines)  # the last candela line
    lines[-1] = lines[-1].replace(lines[-1].split()[3], "12x4", 1)
    bad = tmp_path / "bad.ies"
    bad.write_text("\r\n".join(lines) + "\r\n", encoding="latin-1")
    with pytest.raises(gonio.GonioError) as caught:
        gonio.read(bad)
    e = caught.value
    assert e.file == str(bad) and e.line == bad_line
    assert "12x4" in e.message
    # The command's message, word for word ("gonio: FILE:LINE: message").
    code, _, err = run_gonio(gonio_exe, "info", bad)
    assert code == 1 and f"gonio: {e}" in err


def test_missing_and_unknown_files_raise(tmp_path):
    with pytest.raises(gonio.GonioError) as caught:
        gonio.read(tmp_path / "none.ies")
    assert caught.value.file == str(tmp_path / "none.ies") and caught.value.line is None
    junk = tmp_path / "junk.dat"
    junk.write_text("hello\n")
    with pytest.raises(gonio.GonioError, match="junk.dat"):
        gonio.read(junk)
    with pytest.raises(TypeError):
        gonio.read(42)


def test_write_round_trips_and_refuses_what_the_command_refuses(curves, tmp_path):
    p = gonio.read(curves / "downlight.ies")
    notes = p.write(tmp_path / "d.ldt")
    assert all(isinstance(n, gonio.Finding) for n in notes)
    back = gonio.read(tmp_path / "d.ldt")
    assert back.format == "EULUMDAT"
    assert back.summary()["flux_lm"] == pytest.approx(p.summary()["flux_lm"], rel=1e-3)
    p.write(tmp_path / "d2002.ies", version="2002")
    assert gonio.read(tmp_path / "d2002.ies").version == "LM-63-2002"
    with pytest.raises(ValueError, match="applies to .ies"):
        p.write(tmp_path / "x.ldt", version="2002")
    with pytest.raises(ValueError, match="extension"):
        p.write(tmp_path / "x.txt")
    # An invalid table (made through the view) is refused, nothing written.
    p.candela[0, 0] = float("nan")
    with pytest.raises(gonio.GonioError, match="finite"):
        p.write(tmp_path / "nan.ies")
    assert not (tmp_path / "nan.ies").exists()
    with pytest.raises(gonio.GonioError, match="finite"):
        p.summary()
    p.candela[0, 0] = 1.0
    p.vertical_deg[1] = p.vertical_deg[0]  # angles no longer increasing
    with pytest.raises(gonio.GonioError, match="strictly increasing"):
        p.info()


def test_a_gldf_holds_photometries_by_id(curves, tmp_path):
    gonio.read(curves / "downlight.ldt").write(tmp_path / "lum.gldf")
    everything = gonio.read_all(tmp_path / "lum.gldf")
    assert len(everything) == 1
    one = everything[0]
    assert one.container == str(tmp_path / "lum.gldf") and one.format == "EULUMDAT"
    assert one.path == f"{tmp_path / 'lum.gldf'}:{one.container_entry}"
    by_id = gonio.read(tmp_path / "lum.gldf", photometry=one.container_id)
    assert np.array_equal(by_id.candela, one.candela)
    with pytest.raises(gonio.GonioError, match="no-such-id"):
        gonio.read(tmp_path / "lum.gldf", photometry="no-such-id")


def test_findings_carry_file_line_and_code(corpus):
    p = gonio.read(corpus / "photometric-viewer" / "dummy.ies")
    codes = {f.code for f in p.findings}
    assert "unknown-keyword" in codes
    f = next(f for f in p.findings if f.code == "unknown-keyword")
    assert f.severity == "warning" and f.line == 11 and f.file.endswith("dummy.ies")
    assert str(f).startswith(f"{f.file}:11: warning: ")


def test_the_stubs_name_what_the_module_has():
    """gonio/__init__.pyi against the compiled module: a stub that names a
    function the module lacks (or misses one it has) fails here."""
    stub = pathlib.Path(gonio.__file__).with_name("__init__.pyi")
    tree = ast.parse(stub.read_text())
    names = {n.name for n in tree.body if isinstance(n, (ast.FunctionDef, ast.ClassDef))}
    public = {n for n in dir(gonio) if not n.startswith("_")}
    assert names == public
    for cls in (n for n in tree.body if isinstance(n, ast.ClassDef)):
        members = {m.name for m in cls.body if isinstance(m, ast.FunctionDef) and not m.name.startswith("_")}
        members |= {m.target.id for m in cls.body if isinstance(m, ast.AnnAssign)}
        actual = {n for n in dir(getattr(gonio, cls.name)) if not n.startswith("_")}
        if issubclass(getattr(gonio, cls.name), BaseException):
            actual -= set(dir(Exception))
            continue  # attributes are set on instances
        assert members == actual, cls.name


def test_help_explains_each_call():
    for f in (gonio.read, gonio.read_all, gonio.compare, gonio.Photometry.summary, gonio.Photometry.write):
        assert f.__doc__ and len(f.__doc__) > 60, f
    assert "no copy" in gonio.Photometry.__doc__
