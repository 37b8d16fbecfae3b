"""gonio.optimize: gonio optimize's own run (tools/run/optimize_run.h) from
Python: the same best values, history and final figures as the command's
report.json for the same inputs and seed, a callback that stops it, and
errors naming the file (ctest label `python`)."""
import json

import numpy as np
import pytest

import gonio
from conftest import run_gonio

# A conic dish over an isotropic source; its conic constant the variable.
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
conic = CONIC
vertex = 5
aperture = [2, 30]
"""

# Small budgets: a few seconds a run.
RUN = dict(max_evals=6, stages=2, final_photons=20000, gamma_step=5, seed=2, threads=1)
CLI = ["--max-evals", "6", "--stages", "2", "--final-photons", "20000", "--gamma-step", "5", "--seed", "2",
       "--threads", "1"]


@pytest.fixture(scope="module")
def setup(tmp_path_factory, gonio_exe):
    d = tmp_path_factory.mktemp("optimize")
    (d / "truth.design.toml").write_text(DESIGN.replace("CONIC", "-1.5"))
    (d / "start.design.toml").write_text(DESIGN.replace("CONIC", "{ value = -2.6, min = -3, max = -1 }"))
    code, _, err = run_gonio(gonio_exe, "simulate", d / "truth.design.toml", "--out", d / "truth", "--photons",
                             "20000", "--iterations", "1", "--gamma-step", "5", "--format", "ies", "--no-cache")
    assert code == 0, err
    return d, d / "truth" / "truth.ies"


def test_equals_the_command(setup, gonio_exe):
    d, target = setup
    code, _, err = run_gonio(gonio_exe, "optimize", d / "start.design.toml", "--target", target, "--out",
                             d / "cli", *CLI)
    assert code == 0, err
    report = json.loads((d / "cli" / "report.json").read_text())["optimize"]
    history = json.loads((d / "cli" / "history.json").read_text())

    seen = []
    result = gonio.optimize(d / "start.design.toml", target, out=d / "py", callback=seen.append, **RUN)
    assert result["variables"] == {v["name"]: v["best"] for v in report["variables"]}
    assert result["final"] == report["final"]
    for key in ("best_merit", "start_merit", "independent_merit", "noise_floor", "evaluations", "stopped_by"):
        assert result["optimize"][key] == report[key], key
    def untimed(rows):
        return [{k: v for k, v in e.items() if k != "time_s"} for e in rows]

    assert untimed(result["history"]) == untimed(history)
    merits = [e["merit"] for e in history if e["stage"] != "noise"]
    assert isinstance(result["merit_history"], np.ndarray)
    np.testing.assert_array_equal(result["merit_history"], merits)
    # The callback saw every evaluation, the noise floor's too, as history.json's rows.
    assert untimed(seen) == untimed(history)
    assert (d / "py" / "start.design.toml").exists() and str(d / "py" / "report.json") in result["files"]
    # Without out: the same run in a temporary folder, which is gone afterwards.
    again = gonio.optimize(d / "start.design.toml", target, **RUN)
    assert again["variables"] == result["variables"] and again["files"] == []


def test_callback_returning_false_stops_and_keeps_the_best(setup):
    d, target = setup
    seen = []

    def stop_after_three(evaluation):
        seen.append(evaluation)
        return evaluation["index"] < 3

    result = gonio.optimize(d / "start.design.toml", target, callback=stop_after_three, **RUN)
    assert result["optimize"]["stopped_by"] == "cancelled"
    assert result["optimize"]["evaluations"] == 3
    assert len(result["merit_history"]) == 3
    best = min(range(3), key=lambda i: result["merit_history"][i])
    assert result["variables"]["reflectors[0].conic"] == seen[best]["values"]["reflectors[0].conic"]
    assert result["optimize"]["best_merit"] == result["merit_history"][best]


def test_errors_name_the_file(setup, tmp_path):
    d, target = setup
    bad = d / "bad.design.toml"
    bad.write_text(DESIGN.replace("CONIC", "{ value = -2, min = -3, max = -1 }") + "[merit]\ngamma_step = 7\n")
    with pytest.raises(gonio.GonioError, match=r"bad\.design\.toml:17: \[merit\]: gamma_step must divide 180"):
        gonio.optimize(bad, target, **RUN)
    with pytest.raises(gonio.GonioError, match="absent.ies"):
        gonio.optimize(d / "start.design.toml", tmp_path / "absent.ies", **RUN)
    with pytest.raises(gonio.GonioError, match=r"truth\.design\.toml.*no variables"):
        gonio.optimize(d / "truth.design.toml", target, **RUN)
    with pytest.raises(ValueError, match="target"):
        gonio.optimize(d / "start.design.toml", **RUN)
    with pytest.raises(ValueError, match="method"):
        gonio.optimize(d / "start.design.toml", target, method="newton")


def test_merit_is_the_commands_evaluation(setup, gonio_exe):
    d, target = setup
    code, _, err = run_gonio(gonio_exe, "optimize", d / "start.design.toml", "--target", target, "--out",
                             d / "cli_merit", *CLI)
    assert code == 0, err
    history = json.loads((d / "cli_merit" / "history.json").read_text())
    merit = gonio.Merit(d / "start.design.toml", target, seed=2, threads=1, gamma_step=5)
    assert merit.names == ["reflectors[0].conic"]
    assert merit.bounds == [(-3.0, -1.0)]
    np.testing.assert_array_equal(merit.x0, [-2.6])
    # Stage 1's evaluations: the same photons and seed, so the same merits.
    for e in history[:3]:
        assert e["stage"] == 1 and e["photons"] == merit.photons
        assert merit([e["values"]["reflectors[0].conic"]]) == e["merit"]
        assert merit(e["values"]) == e["merit"]
    # Common random numbers: a deterministic function, and not a constant one.
    assert merit([-1.5]) == merit(np.array([-1.5])) < merit([-2.9])
    terms = merit.terms([-1.5])
    assert terms["merit"] == merit([-1.5]) and 0 < terms["lor"] <= 1
    with pytest.raises(ValueError, match="give 1 values"):
        merit([-1.5, 0.0])
    with pytest.raises(ValueError, match="no value for the variable"):
        merit({"conic": -1.5})
    with pytest.raises(gonio.GonioError, match=r"bad\.design\.toml"):
        bad = d / "bad.design.toml"
        bad.write_text(DESIGN.replace("CONIC", "{ value = -2 }"))
        gonio.Merit(bad, target)


# merit=: a dict of the [merit] table's keys, replacing the design's table.
MERIT = {"field": 0.5, "max_cd_above": {"gamma": 50, "to": 90, "limit": 100.0}}
MERIT_TOML = "[merit]\nfield = 0.5\nmax_cd_above = { gamma = 50, to = 90, limit = 100.0 }\n"


def test_merit_argument_is_the_designs_table(setup):
    d, target = setup
    # The same table written in the design file gives the same merit, bit for bit.
    written = d / "written.design.toml"
    written.write_text(DESIGN.replace("CONIC", "{ value = -2.6, min = -3, max = -1 }") + MERIT_TOML)
    given = gonio.Merit(d / "start.design.toml", target, seed=2, threads=1, gamma_step=5, merit=MERIT)
    in_file = gonio.Merit(written, target, seed=2, threads=1, gamma_step=5)
    for x in ([-1.5], [-2.2]):
        assert given(x) == in_file(x)
    # It replaces the design's own table (here the written one's).
    plain = gonio.Merit(written, target, seed=2, threads=1, gamma_step=5, merit={})
    terms = given.terms([-1.5])
    assert plain([-1.5]) == terms["candela_rms_pct"]
    # Its terms: the field angle's miss at weight 0.5, the cut-off's penalty.
    [limit] = terms["limits"]
    assert limit["name"] == "max_cd_above" and limit["limit"] == 100.0
    assert limit["value"] == terms["max_cd_above"]
    assert limit["c"] == pytest.approx((limit["value"] - 100.0) / 100.0, rel=1e-12)
    assert terms["penalty"] == pytest.approx(100.0 * max(0.0, limit["c"]), rel=1e-12)
    np.testing.assert_array_equal(given.limits([-1.5]), [limit["c"]])
    assert plain.limits([-1.5]).shape == (0,)
    assert terms["merit"] == pytest.approx(
        terms["candela_rms_pct"] + 0.5 * abs(terms["field_angle_deg"] - terms["target_field_angle_deg"])
        + terms["penalty"], rel=1e-12)
    # gonio.optimize takes it too: COBYLA with the limit as a constraint.
    result = gonio.optimize(d / "start.design.toml", target, method="cobyla", merit=MERIT, **RUN)
    assert result["optimize"]["merit"]["limits"] == ["max_cd_above"]
    assert result["optimize"]["merit"]["limits_as"] == "constraints"
    assert result["optimize"]["merit"]["weights"]["field"] == 0.5
    assert result["final"]["limits"][0]["name"] == "max_cd_above"
    assert result["optimize"]["merit"]["limit_tables"]["max_cd_above"] == {"gamma": 50, "to": 90, "limit": 100,
                                                                           "weight": 1}


def test_merit_argument_mistakes(setup):
    d, target = setup
    with pytest.raises(gonio.GonioError, match=r"start\.design\.toml \(merit=\).*unknown key 'colour'"):
        gonio.Merit(d / "start.design.toml", target, merit={"colour": 1})
    with pytest.raises(gonio.GonioError, match=r"\(merit=\).*'bug\.b' must be a class 0"):
        gonio.optimize(d / "start.design.toml", target, merit={"bug": {"b": 7}}, **RUN)
    with pytest.raises(TypeError, match="'ugr.limit' must be a dict, list, bool, int, float or str"):
        gonio.Merit(d / "start.design.toml", target, merit={"ugr": {"limit": object()}})
    with pytest.raises(TypeError, match="merit must be a dict"):
        gonio.Merit(d / "start.design.toml", target, merit=[1])
    # A UGR term needs the target's luminous opening: a target without one (a
    # point: width, length and height 0) says so.
    point = d / "point.ies"
    point.write_text("IESNA:LM-63-2002\n[TEST] t\n[TESTLAB] t\n[ISSUEDATE] t\n[MANUFAC] t\nTILT=NONE\n"
                     "1 -1 1 3 1 1 2 0 0 0\n1 1 0\n0 45 90\n0\n300 200 0\n")
    with pytest.raises(gonio.GonioError, match=r"'ugr' without a limit.*'point\.ies' has none"):
        gonio.Merit(d / "start.design.toml", point, merit={"ugr": {"weight": 1}}, gamma_step=5)
    # With the simulated target's opening (gonio simulate writes the one it finds) it is defined.
    ugr = gonio.Merit(d / "start.design.toml", target, merit={"ugr": {"weight": 1}}, seed=2, threads=1, gamma_step=5)
    terms = ugr.terms([-1.5])
    assert np.isfinite(terms["ugr"]) and np.isfinite(terms["target_ugr"])
    assert terms["merit"] == pytest.approx(terms["candela_rms_pct"] + abs(terms["ugr"] - terms["target_ugr"]),
                                           rel=1e-12)


# The command's options that gonio.optimize takes too: each reaches the run.
CMAES = dict(method="cmaes", stages=1, final_photons=20000, gamma_step=5, seed=2, threads=1)


def untimed_rows(rows):
    return [{k: v for k, v in e.items() if k != "time_s"} for e in rows]


def test_population_sets_cmaes_points_per_generation(setup):
    """A stop inside the first generation ends with its λ points (1 start + λ):
    population=8 gives 9 evaluations, 10 gives 11, the default for one
    variable (pagmo's least, 5) gives 6."""
    d, target = setup
    for population, evaluations in ((8, 9), (10, 11), (0, 6)):
        result = gonio.optimize(d / "start.design.toml", target, jobs=1, population=population, max_evals=100,
                                callback=lambda e: e["index"] < 3, **CMAES)
        assert result["optimize"]["evaluations"] == evaluations, population
        assert result["optimize"]["stopped_by"] == "cancelled"


def test_jobs_give_the_same_run(setup):
    """jobs reaches the run (report.json's optimize.jobs) and leaves it as it is."""
    d, target = setup
    runs = [gonio.optimize(d / "start.design.toml", target, jobs=jobs, max_evals=14, **CMAES) for jobs in (1, 2)]
    assert [r["optimize"]["jobs"] for r in runs] == [1, 2]
    assert untimed_rows(runs[0]["history"]) == untimed_rows(runs[1]["history"])
    assert runs[0]["variables"] == runs[1]["variables"]
    assert runs[0]["final"] == runs[1]["final"]


def test_common_random_off_gives_each_evaluation_its_seed(setup):
    d, target = setup
    on = gonio.optimize(d / "start.design.toml", target, **RUN)
    off = gonio.optimize(d / "start.design.toml", target, common_random=False, **RUN)
    assert on["optimize"]["merit"]["common_random_numbers"] is True
    assert off["optimize"]["merit"]["common_random_numbers"] is False
    searched_on = [e for e in on["history"] if e["stage"] != "noise"]
    searched_off = [e for e in off["history"] if e["stage"] != "noise"]
    # With common random numbers a stage traces its seed's photons every time.
    assert len({(e["stage"], e["seed"]) for e in searched_on}) == len({e["stage"] for e in searched_on})
    assert len({e["seed"] for e in searched_off}) == len(searched_off)
    # The seed argument is the stage's seed.
    other = gonio.optimize(d / "start.design.toml", target, **{**RUN, "seed": 5})
    assert {e["seed"] for e in other["history"] if e["stage"] == 1} != {e["seed"] for e in searched_on if e["stage"] == 1}


def test_max_time_stops_the_search(setup):
    d, target = setup
    result = gonio.optimize(d / "start.design.toml", target, **{**RUN, "max_evals": 1000, "max_time": 1e-6})
    assert result["optimize"]["stopped_by"] == "time"
    assert result["optimize"]["evaluations"] < 10


def test_step_and_bad_arguments(setup, tmp_path):
    d, target = setup
    gonio.optimize(d / "start.design.toml", target, out=tmp_path / "nostep", step=False, **RUN)
    assert (tmp_path / "nostep" / "start.design.toml").exists()
    assert not (tmp_path / "nostep" / "start.step").exists()
    with pytest.raises(ValueError, match="step"):
        gonio.optimize(d / "start.design.toml", target, step=True, **RUN)
    for bad in (dict(jobs=-1), dict(population=-1), dict(max_time=-1.0), dict(jobs=5000)):
        with pytest.raises(ValueError):
            gonio.optimize(d / "start.design.toml", target, **{**RUN, **bad})


def test_cannot_improve_returns_and_a_failure_raises(setup, gonio_exe):
    """A user's loop over designs tells a run that cannot improve (the command's exit 3: it returns,
    every file written, improvable False and the reason) from one that failed (GonioError)."""
    d, target = setup
    flat = d / "flat.design.toml"  # a variable that moves nothing: an unused material's reflectance
    flat.write_text(DESIGN.replace("CONIC", "-1.5")
                    + "[materials.spare]\nreflectance = { value = 0.5, min = 0.1, max = 0.9 }\n")
    broken = d / "broken.design.toml"
    broken.write_text(DESIGN.replace("CONIC", "{ value = -2, min = -3, max = -1 }") + "[merit]\ngamma_step = 7\n")
    outcome = {}
    for design in (d / "start.design.toml", flat, broken):
        try:
            result = gonio.optimize(design, target, out=d / ("loop-" + design.name), **RUN)
        except gonio.GonioError as e:
            outcome[design.name] = ("failed", str(e))
            continue
        outcome[design.name] = ("improved" if result["improvable"] else result["cannot_improve_kind"], result)
    assert outcome["start.design.toml"][0] == "improved"
    assert outcome["start.design.toml"][1]["cannot_improve"] is None
    assert outcome["start.design.toml"][1]["cannot_improve_kind"] is None
    assert outcome["broken.design.toml"][0] == "failed"
    assert "gamma_step must divide 180" in outcome["broken.design.toml"][1]
    kind, result = outcome["flat.design.toml"]
    assert kind == "flat"
    assert result["improvable"] is False
    assert "the variables do not move the merit" in result["cannot_improve"]
    report = json.loads((d / "loop-flat.design.toml" / "report.json").read_text())["optimize"]
    assert result["cannot_improve"] == report["cannot_improve"]
    assert result["cannot_improve_kind"] == report["cannot_improve_kind"]
    assert str(d / "loop-flat.design.toml" / "report.json") in result["files"]
    # The command exits 3 for the same run.
    code, _, err = run_gonio(gonio_exe, "optimize", flat, "--target", target, "--out", d / "cli-flat", *CLI)
    assert code == 3, err


def test_mistakes_name_the_design_file_not_input(setup):
    """GonioError of a design's mistake: the design file and line, in str() and as .file and .line."""
    d, target = setup
    bad = d / "bad-merit.design.toml"
    bad.write_text(DESIGN.replace("CONIC", "{ value = -2, min = -3, max = -1 }") + "[merit]\ngamma_step = 7\n")
    with pytest.raises(gonio.GonioError) as e:
        gonio.optimize(bad, target, **RUN)
    assert str(e.value).startswith(str(bad) + ":17: [merit]: gamma_step must divide 180"), str(e.value)
    assert "<input>" not in str(e.value)
    assert (e.value.file, e.value.line) == (str(bad), 17)
    free = d / "free.design.toml"
    free.write_text(DESIGN.replace("CONIC", "{ value = -2, min = -3 }"))
    with pytest.raises(gonio.GonioError) as e:
        gonio.optimize(free, target, **RUN)
    assert str(e.value).startswith(str(free) + ":13: variable 'reflectors[0].conic' has no max"), str(e.value)
    assert (e.value.file, e.value.line) == (str(free), 13)
