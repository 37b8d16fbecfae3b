"""Gonio from Python: read, check, convert and compare photometric files, and
simulate luminaire models, on the libraries the `gonio` command uses.

Type stubs of the compiled module (gonio/_gonio); docs/python.md has the
whole surface as one table and a worked example.
"""
from __future__ import annotations

import os
from typing import Any, Callable, Literal

import numpy as np
import numpy.typing as npt

__version__: str

PathLike = str | os.PathLike[str]

class GonioError(Exception):
    """An input Gonio refuses: its file, line and column where known."""

    message: str
    file: str | None
    line: int | None
    column: int | None

class UndefinedFigureWarning(UserWarning):
    """A planning figure that is undefined for this photometry (the reason is the message)."""

class Finding:
    """One observation of a reader or check: a stable code, a message, where."""

    severity: Literal["info", "warning", "error"]
    code: str
    message: str
    file: str | None
    line: int | None
    column: int | None

class Photometry:
    """A light distribution read from a file (or simulated), with what follows from it.

    The angle and candela arrays share the object's memory (no copy): writing
    into them changes what `write()` writes and what the figures are computed from.
    """

    path: str
    format: Literal["IES", "EULUMDAT", "TM-33", "TM-25"] | None  # None: simulated
    format_label: str
    version: str | None
    container: str | None
    container_entry: str | None
    container_id: str | None
    photometric_type: Literal["A", "B", "C"]
    symmetry: str
    vertical_deg: npt.NDArray[np.float64]
    horizontal_deg: npt.NDArray[np.float64]
    candela: npt.NDArray[np.float64]
    absolute: bool
    lamps: list[dict[str, Any]]
    alternative_lamps: list[dict[str, Any]]
    ballast_factor: float
    input_watts: float | None
    opening: dict[str, Any]
    luminaire_dimensions: dict[str, float | None]
    keywords: list[tuple[str, str]]
    findings: list[Finding]
    ray_set: dict[str, Any] | None

    def summary(self) -> dict[str, Any]: ...
    def ugr_table(self, background: Literal["cie190", "flux-transfer"] = "cie190") -> dict[str, Any] | None: ...
    def cu_table(self, floor_reflectance: float = 0.2) -> dict[str, Any] | None: ...
    def luminance_table(self) -> dict[str, Any] | None: ...
    def bug(self) -> dict[str, Any]: ...
    def spacing_criterion(self) -> dict[str, float | str | None]: ...
    def info(
        self, cu_floor: float = 0.2, ugr_background: Literal["cie190", "flux-transfer"] = "cie190"
    ) -> dict[str, Any]: ...
    def check(self) -> list[Finding]: ...
    def write(
        self,
        path: PathLike,
        version: Literal["2019", "2002"] | None = None,
        *,
        ldt_isym3: Literal["standard", "qlumedit"] = "standard",
        gldf_photometry: Literal["ldt", "ies", "tm33"] = "ldt",
    ) -> list[Finding]: ...

def read(
    path: PathLike,
    photometry: str | None = None,
    *,
    ldt_isym3: Literal["standard", "qlumedit"] = "standard",
) -> Photometry: ...
def read_all(path: PathLike, *, ldt_isym3: Literal["standard", "qlumedit"] = "standard") -> list[Photometry]: ...
def compare(
    a: Photometry | PathLike,
    b: Photometry | PathLike,
    *,
    c_step: float = 5.0,
    gamma_step: float = 2.5,
    normalize: bool = False,
) -> dict[str, Any]: ...

class FarField:
    """The simulated far field: a direction cube map, faces +X −X +Y −Y +Z −Z (world axes)."""

    face_size: int
    flux_lm: npt.NDArray[np.float64]
    photons: npt.NDArray[np.uint64]
    solid_angle_sr: npt.NDArray[np.float64]
    intensity_cd: npt.NDArray[np.float64]
    total_flux_lm: float

class Iteration:
    """What on_iteration receives after each iteration."""

    iteration: int
    iterations: int
    photons_done: int
    photons_total: int
    elapsed_s: float
    photons_per_s: float
    remaining_s: float
    estimated_rms_error_pct: float

class SimulationResult:
    """What gonio.simulate returns."""

    model: str
    far_field: FarField
    photometry: Photometry
    ledger: dict[str, Any]
    estimated_rms_error_pct: float
    stopped_by: Literal["iterations", "target-error", "cancelled"]
    iterations_done: int
    photons: int
    trace_s: float
    symmetry_reason: str
    model_findings: list[Finding]
    files: list[str]
    report: dict[str, Any] | None
    exit_code: int

class Design:
    """A design file (NAME.design.toml) held in memory; gonio.simulate(design) traces it as it stands."""

    def __init__(self, path: PathLike) -> None: ...
    path: str
    variables: dict[str, float]
    bounds: dict[str, tuple[float | None, float | None]]
    def set(self, name: str, value: float) -> None: ...
    def write(self, path: PathLike) -> None: ...
    def export_step(self, path: PathLike, *, tolerance_mm: float = 0.001) -> dict[str, Any]: ...

class Model:
    """A luminaire built in memory: meshes from numpy arrays, the CAD sidecar's materials and emitters as dicts."""

    def __init__(self, *, length_unit: str = "mm", frame: dict[str, Any] | None = None, name: str = "model") -> None: ...
    def material(self, name: str, keys: dict[str, Any]) -> None: ...
    def add_mesh(
        self, name: str, vertices: Any, triangles: Any, *, normals: Any | None = None, material: str
    ) -> None: ...
    def add_emitter(self, emitter: dict[str, Any]) -> None: ...
    @property
    def name(self) -> str: ...
    @property
    def meshes(self) -> list[str]: ...

class Merit:
    """The merit gonio optimize minimises, as a function of a design's variables (common random numbers)."""

    def __init__(
        self,
        design: PathLike | Design,
        target: PathLike | None = None,
        *,
        photons_per_bin: float | None = None,
        smooth: bool = True,
        photons: int | None = None,
        seed: int = 1,
        threads: int = 0,
        gamma_step: float = 1.0,
        merit: dict[str, Any] | None = None,
    ) -> None: ...
    def __call__(self, values: Any) -> float: ...
    def terms(self, values: Any) -> dict[str, Any]: ...
    def limits(self, values: Any) -> npt.NDArray[np.float64]: ...
    @property
    def names(self) -> list[str]: ...
    @property
    def x0(self) -> npt.NDArray[np.float64]: ...
    @property
    def bounds(self) -> list[tuple[float, float]]: ...
    @property
    def photons(self) -> int: ...
    @property
    def seed(self) -> int: ...

def optimize(
    design: PathLike | Design,
    target: PathLike | None = None,
    *,
    out: PathLike | None = None,
    method: str = "bobyqa",
    max_evals: int = 200,
    stages: int = 3,
    seed: int = 1,
    threads: int = 0,
    photons_per_bin: float | None = None,
    smooth: bool = True,
    gamma_step: float = 1.0,
    final_photons: int = 1_000_000,
    max_time: float = 0.0,
    name: str | None = None,
    callback: Callable[[dict[str, Any]], bool | None] | None = None,
    merit: dict[str, Any] | None = None,
    jobs: int = 0,
    population: int = 0,
    common_random: bool = True,
    step: bool | None = None,
) -> dict[str, Any]:
    """gonio optimize's run: {variables, merit_history, history, optimize, final, report, files,
    improvable, cannot_improve, cannot_improve_kind}; a run that cannot improve returns (improvable
    False), a failed one raises GonioError."""
    ...

def tolerance(
    model: PathLike | Design,
    tolerances: PathLike | None,
    *,
    trials: int = 20,
    spec: str | None = None,
    seed: int = 1,
    noise_seeds: int = 3,
    sampling_seed: int = 1,
    bins: int = 10,
    photons: int = 1_000_000,
    threads: int = 0,
    max_bounces: int = 100,
    c_step: float = 5.0,
    gamma_step: float = 2.5,
    out: PathLike | None = None,
    inverse_steps: int = 4,
    parallel_trials: int = 1,
    percentile: str | None = None,
    luminance_image: str | None = None,
) -> dict[str, Any]:
    """gonio tolerance's run: {trials, values, sensitivity, noise_floor, nominal, yield, inverse_sensitivity, table, report}."""
    ...

def simulate(
    model: PathLike | Design | Model,
    *,
    photons: int = 1_000_000,
    iterations: int = 10,
    seed: int = 1,
    sampler: Literal["sobol", "random"] = "sobol",
    threads: int = 0,
    out: PathLike | None = None,
    on_iteration: Callable[[Iteration], bool | None] | None = None,
    target_error: float = 0.0,
    c_step: float = 5.0,
    gamma_step: float = 2.5,
    symmetry: Literal["auto", "none", "C0-C180", "C90-C270", "quadrant", "rotational"] = "auto",
    formats: str = "all",
    ies_version: Literal["2019", "2002"] = "2019",
    name: str | None = None,
    max_bounces: int = 100,
    cache: bool = True,
) -> SimulationResult: ...
