"""navkf from Python: simulate, filter, study, diagnose and plan.

The same code as the ``navkf`` command runs underneath (the Rust crates of this workspace),
so a seed gives the same numbers, bit for bit, from either. Errors raise
:class:`NavkfError` (a ``ValueError``) with the command line's located messages: the file,
line and column, or the setting, and what was expected.

Long calls (``study``, ``diagnose``) release the GIL, take a ``progress`` callback
``progress(done, total)``, and stop on Ctrl-C as the command line does: the runs in flight
finish, nothing is written, and ``KeyboardInterrupt`` is raised.

    >>> import navkf
    >>> ds = navkf.simulate(seed=1, effects="odometer-scale=0.005")
    >>> f = navkf.Filter("ekf", ds, effects=["odometer-scale"])
    >>> while f.step() is not None:
    ...     pass
"""

from __future__ import annotations

import csv
import io
import json
import os
import tempfile
import warnings
from dataclasses import dataclass, field
from typing import Any, Callable, Dict, List, Mapping, Optional, Sequence, Union

import numpy as np

from . import _navkf
from ._navkf import Dataset, NavkfError, __version__, instruction_set

__all__ = [
    "Dataset",
    "Filter",
    "NavkfError",
    "StudyResult",
    "diagnose",
    "instruction_set",
    "plan",
    "simulate",
    "study",
    "__version__",
]

# NAVKF_SIMD set to a value the kernels ignore is said, not passed over (as the command line
# says it on start).
_ignored = _navkf.ignored_simd_setting()
if _ignored is not None:
    warnings.warn(_ignored, RuntimeWarning, stacklevel=2)

Progress = Callable[[int, int], Any]
PathLike = Union[str, "os.PathLike[str]"]


def _effects_text(effects: Union[str, Sequence[str], Mapping[str, Optional[float]], None]) -> str:
    """``"a,b=1"`` from a string, a list of names, or a dict of name -> value (None: drawn)."""
    if effects is None:
        return ""
    if isinstance(effects, str):
        return effects
    if isinstance(effects, Mapping):
        items = []
        for name, value in effects.items():
            items.append(str(name) if value is None else f"{name}={float(value)!r}")
        return ",".join(items)
    return ",".join(str(e) for e in effects)


def _study_source(study: Union[PathLike, Mapping[str, Any]]) -> Dict[str, Optional[str]]:
    """A study file's path (read by navkf, as the command line reads it), or a dict's tables
    as JSON (made a study file's text by navkf)."""
    if isinstance(study, Mapping):
        try:
            return {"path": None, "json": json.dumps(study, allow_nan=False)}
        except (TypeError, ValueError) as e:
            raise NavkfError(f"study: {e}; expected tables of numbers, text and lists") from None
    return {"path": os.fspath(study), "json": None}


def simulate(
    *,
    seed: int = 1,
    run: int = 0,
    effects: Union[str, Sequence[str], Mapping[str, Optional[float]], None] = None,
    model: str = "platform",
    out: Optional[PathLike] = None,
    trajectory: Optional[str] = None,
    duration: Optional[float] = None,
    attitude: Optional[str] = None,
    azimuth_sigma: Optional[float] = None,
    truth: bool = True,
    unit: Optional[str] = None,
    imu_rate: Optional[float] = None,
    nhc_sigma: Optional[float] = None,
    body_motion: Optional[float] = None,
    effects_file: Optional[PathLike] = None,
) -> Dataset:
    """Simulates a vehicle test, as ``navkf simulate`` does, and returns the dataset.

    ``effects`` are hidden in the truth: ``"gyro-fz,odometer-scale=0.002"``, a list of
    names (coefficients drawn), or a dict of name -> value. ``model`` is ``"platform"``
    (the paper's) or ``"strapdown"`` (then ``unit`` is ``"navigation"``, ``"tactical"`` or
    ``"mems"``, ``imu_rate`` in Hz, ``nhc_sigma`` in m/s and ``body_motion``, the body's
    sideslip and bounce in m/s rms, by default ``nhc_sigma``; 0 for a rigid vehicle, whose
    constraint holds exactly). ``trajectory`` is TOML text
    with a ``[trajectory]`` table; ``duration`` scales the test (s). ``azimuth_sigma`` is
    the initial azimuth (heading) error's one-sigma, rad. When ``out`` is given the dataset
    is also written there (a new folder, or one ``simulate`` wrote before).
    ``effects_file`` is a TOML file of ``[[effect]]`` tables (docs/declared-effects.md), of
    ``model``'s family, whose effects ``effects`` may then name; the dataset's
    ``dataset.toml`` carries the declarations of those it hides.
    """
    def go(folder: str) -> Dataset:
        return _navkf.simulate(
            out=folder,
            seed=int(seed),
            run_index=int(run),
            effects=_effects_text(effects),
            model=model,
            trajectory_toml=trajectory,
            duration=None if duration is None else float(duration),
            attitude=attitude,
            azimuth_sigma=None if azimuth_sigma is None else float(azimuth_sigma),
            truth=bool(truth),
            unit=unit,
            imu_rate=None if imu_rate is None else float(imu_rate),
            nhc_sigma=None if nhc_sigma is None else float(nhc_sigma),
            body_motion=None if body_motion is None else float(body_motion),
            effects_file=None if effects_file is None else os.fspath(effects_file),
        )

    for name, value in (("seed", seed), ("run", run)):
        if not isinstance(value, (int, np.integer)) or value < 0:
            raise NavkfError(f"{name} {value!r}: expected a whole number >= 0")
    if out is not None:
        return go(os.fspath(out))
    with tempfile.TemporaryDirectory(prefix="navkf-") as tmp:
        return go(os.path.join(tmp, "simulated"))


@dataclass
class StudyResult:
    """What ``navkf.study`` returns.

    ``summary`` is ``summary.json`` as Python data (RMS errors, NEES/NIS, step costs,
    divergences per filter); ``series`` maps each column of ``rms_over_time.csv`` to an
    array (``filter`` to the filter's name per row); ``runs`` holds one dict per run, each
    with per-filter final errors, sigmas, mean NEES, NIS and step cost, and whether the run
    diverged (and why).
    """

    summary: Dict[str, Any]
    series: Dict[str, np.ndarray]
    runs: List[Dict[str, Any]] = field(default_factory=list)


def _series(csv_text: str) -> Dict[str, np.ndarray]:
    rows = list(csv.reader(io.StringIO(csv_text)))
    if not rows:
        return {}
    header, body = rows[0], rows[1:]
    out: Dict[str, np.ndarray] = {}
    for k, name in enumerate(header):
        col = [r[k] for r in body]
        if name == "filter":
            out[name] = np.array(col, dtype=object)
        else:
            out[name] = np.array([float(v) if v != "" else np.nan for v in col])
    return out


def study(
    study: Union[PathLike, Mapping[str, Any]],
    *,
    runs: Optional[int] = None,
    out: Optional[PathLike] = None,
    progress: Optional[Progress] = None,
) -> StudyResult:
    """Runs a Monte Carlo study, as ``navkf study FILE`` does.

    ``study`` is a study file's path (``"studies/paper.toml"``) or its tables as a dict
    (``{"study": {"name": "mine", "runs": 20}}``; docs/study-files.md has every key).
    ``runs`` overrides the number of runs. With ``out`` the results folder is written as
    the command line writes it (report, figures, CSV). Same seed, same numbers as the
    command line, whatever the thread count.
    """
    source = _study_source(study)
    if runs is not None and (not isinstance(runs, (int, np.integer)) or runs < 1):
        raise NavkfError(f"runs {runs!r}: expected a whole number >= 1")
    summary, series, per_run = _navkf.study(
        **source,
        runs=None if runs is None else int(runs),
        out=None if out is None else os.fspath(out),
        progress=progress,
    )
    return StudyResult(json.loads(summary), _series(series), json.loads(per_run))


def plan(study: Union[PathLike, Mapping[str, Any]], *, out: Optional[PathLike] = None) -> Dict[str, Any]:
    """Predicts which coefficients a study's test identifies, as ``navkf plan FILE`` does:
    ``plan.json`` as Python data (per coefficient, the predicted sigma after the test and
    whether it is identified). With ``out`` the plan's folder is written too."""
    return json.loads(_navkf.plan(**_study_source(study), out=None if out is None else os.fspath(out)))


def diagnose(
    dataset: Union[Dataset, PathLike],
    *,
    with_: Union[str, Sequence[str], None] = None,
    priors: Optional[Mapping[str, float]] = None,
    level_sigma: Optional[float] = None,
    azimuth_sigma: Optional[float] = None,
    noise: str = "fit",
    filter: str = "ekf",
    attitude: Optional[str] = None,
    window: float = 300.0,
    max_rounds: int = 4,
    effects_file: Optional[PathLike] = None,
    out: Optional[PathLike] = None,
    progress: Optional[Progress] = None,
) -> Dict[str, Any]:
    """Compares the model with ``dataset`` and finds what is missing, as ``navkf diagnose``.

    ``with_`` switches effects on in the model under test (a manual first round);
    ``priors`` maps coefficient names to one-sigmas; ``noise`` is ``"fit"`` (check the
    stated noise and fit the levels that are off) or ``"stated"``. Returns
    ``diagnosis.json`` as Python data: the verdict, the effects named and suggested, the
    findings, every round with its candidates, the noise check and the fits' innovation
    summaries; and under ``"series"`` the final model's update-by-update series (``"model"``:
    ``t``, ``nis``, ``dims``, per channel the ``innovation`` and its ``innovation_sigma``)
    and, when effects were added, the base model's (``"before"``). ``effects_file`` is a TOML
    file of ``[[effect]]`` tables of the dataset's family (docs/declared-effects.md): its
    effects are candidates beside the catalogue's and ``with_`` may name them. With ``out``
    the report and figures are written too.
    """
    effects_file = None if effects_file is None else os.fspath(effects_file)
    if not isinstance(dataset, Dataset):
        dataset = Dataset.read(os.fspath(dataset), effects_file)
    # What looks like a unit mistake is said before any verdict, as the command line does.
    for w in dataset.warnings():
        warnings.warn(f"{dataset.name}: {w}", stacklevel=2)
    if noise not in ("fit", "stated"):
        raise NavkfError(f"noise {noise!r}: expected 'fit' or 'stated'")
    if isinstance(with_, str):
        with_ = [w.strip() for w in with_.split(",") if w.strip()]
    if not isinstance(max_rounds, (int, np.integer)) or max_rounds < 0:
        raise NavkfError(f"max_rounds {max_rounds!r}: expected a whole number >= 1")
    text, series = _navkf.diagnose(
        dataset,
        with_=list(with_ or []),
        priors={str(k): float(v) for k, v in (priors or {}).items()},
        level_sigma=None if level_sigma is None else float(level_sigma),
        azimuth_sigma=None if azimuth_sigma is None else float(azimuth_sigma),
        fit_noise=noise == "fit",
        filter=filter,
        attitude=attitude,
        window=float(window),
        max_rounds=int(max_rounds),
        effects_file=effects_file,
        out=None if out is None else os.fspath(out),
        progress=progress,
    )
    result = json.loads(text)
    result["series"] = series
    return result


# Each model family's files and their columns, as the reader expects them (the native
# module's registration of the families; the first listed for a refusal).
_FAMILIES = _navkf.families()
_COLUMNS = {f["name"]: (f["inputs"], f["measurements"]) for f in _FAMILIES}
_DEFAULT_MODEL = next(f["name"] for f in _FAMILIES if f["default"])


def _expected_models() -> str:
    """``'platform' or 'strapdown'``: the families' names, as a refusal lists them."""
    names = [repr(n) for n in _COLUMNS]
    return names[-1] if len(names) == 1 else ", ".join(names[:-1]) + " or " + names[-1]


def _cell(v: float) -> str:
    # repr gives the shortest text that reads back to the same float; NaN is an empty cell.
    return "" if v != v else repr(float(v))


def _write_columns(path: str, file: str, columns: Mapping[str, Any], names: Sequence[str]) -> None:
    what = file[:-4]
    missing = [n for n in names if n not in columns]
    extra = [n for n in columns if n not in names]
    if missing or extra:
        raise NavkfError(
            f"{what}: columns {list(columns)}; expected exactly {list(names)}"
            + (f" (missing {missing})" if missing else "")
            + (f" (unknown {extra})" if extra else "")
        )
    cols = [_float_array(f"{what}[{n!r}]", columns[n], 1) for n in names]
    lengths = {len(c) for c in cols}
    if len(lengths) != 1:
        raise NavkfError(f"{what}: columns of lengths {[len(c) for c in cols]}; expected one length")
    with open(os.path.join(path, file), "w", encoding="utf-8", newline="") as f:
        f.write(",".join(names) + "\n")
        for row in zip(*cols):
            f.write(",".join(_cell(v) for v in row) + "\n")


def _from_arrays(
    inputs: Mapping[str, Any],
    measurements: Mapping[str, Any],
    *,
    model: str = "platform",
    config: Optional[str] = None,
    truth: Optional[Mapping[str, Any]] = None,
    name: str = "dataset",
) -> Dataset:
    """A dataset built from columns in memory, checked as a folder on disk is.

    ``inputs`` and ``measurements`` map each column of the family's files to a 1-D array
    (docs/data-format.md: ``t, f_e, f_n, f_u`` and ``t, v_e, v_n, lat_deg, lon_deg`` for the
    platform; ``t, w_x, w_y, w_z, f_x, f_y, f_z`` and ``t, speed, lat_deg, lon_deg`` for a
    strapdown unit); NaN is an empty cell. ``config`` is ``dataset.toml``'s text (noise,
    priors, ``[initial]``); ``truth`` maps ``t`` and state names to arrays. Every check of
    the reader applies, and an error names the array and its row (row 0 is the first).
    """
    import re

    if model not in _COLUMNS:
        raise NavkfError(f"model {model!r}: expected {_expected_models()}")
    with tempfile.TemporaryDirectory(prefix="navkf-") as tmp:
        folder = os.path.join(tmp, name)
        os.mkdir(folder)
        (inp, inp_names), (meas, meas_names) = _COLUMNS[model]
        _write_columns(folder, inp, inputs, inp_names)
        _write_columns(folder, meas, measurements, meas_names)
        if truth is not None:
            _write_columns(folder, "truth.csv", truth, ["t"] + [k for k in truth if k != "t"])
        text = config or ""
        if model != _DEFAULT_MODEL and "[model]" not in text:
            text = f'[model]\nkind = "{model}"\n\n' + text
        if text:
            with open(os.path.join(folder, "dataset.toml"), "w", encoding="utf-8") as f:
                f.write(text)
        try:
            ds = Dataset.read(folder)
        except NavkfError as e:
            message = str(e).replace(folder + os.sep, "")

            def row(m: "re.Match[str]") -> str:
                return f"{m.group(1)} row {int(m.group(2)) - 2}"

            message = re.sub(r"\b(inputs|imu|measurements|truth)\.csv:(\d+)", row, message)
            message = message.replace("dataset.toml", "config")
            raise NavkfError(message) from None
        if ds.model != model:
            raise NavkfError(f"config: its [model] says {ds.model!r}; expected {model!r}, the model given")
        return ds


def _float_array(name: str, a: Any, ndim: int) -> np.ndarray:
    try:
        arr = np.ascontiguousarray(a, dtype=np.float64)
    except (TypeError, ValueError):
        raise NavkfError(f"{name}: {type(a).__name__} is not an array of numbers") from None
    if arr.ndim != ndim:
        raise NavkfError(f"{name}: {arr.ndim}-D array of shape {arr.shape}; expected {ndim}-D")
    return arr


class Filter:
    """One of navkf's filters on a dataset, stepped by hand.

    ``kind`` is ``"ekf"``, ``"standard_ukf"``, ``"simplified_ukf"`` or
    ``"square_root_ukf"``. The model is the dataset's family with ``effects`` switched on;
    the filter starts where a diagnosis fit starts (the first measurement with both sensors,
    the dataset's priors). After each ``update`` (or ``step``) it exposes ``x``, ``P``,
    ``innovation``, ``S``, ``nis`` and ``log_likelihood``.
    """

    def __init__(
        self,
        kind: str,
        dataset: Union[Dataset, PathLike],
        *,
        effects: Union[str, Sequence[str], None] = None,
        attitude: Optional[str] = None,
    ) -> None:
        if not isinstance(dataset, Dataset):
            dataset = Dataset.read(os.fspath(dataset))
        if isinstance(effects, str):
            effects = [e.strip() for e in effects.split(",") if e.strip()]
        self._f = _navkf.Filter(kind, dataset, list(effects or []), attitude)
        self.dataset = dataset

    kind = property(lambda self: self._f.kind, doc="The filter's name.")
    state_names = property(lambda self: self._f.state_names, doc="The states' names, in the order of x.")
    channel_names = property(lambda self: self._f.channel_names, doc="The measurement channels' names.")
    t = property(lambda self: self._f.t, doc="The time of the estimate, s.")
    step_index = property(lambda self: self._f.step_index, doc="Predictions since the last reset.")
    x = property(lambda self: self._f.x, doc="The estimate.")
    P = property(lambda self: self._f.P, doc="The estimate's covariance.")
    channels = property(lambda self: self._f.channels, doc="The channels the last update used.")
    innovation = property(lambda self: self._f.innovation, doc="The last update's z - z_hat.")
    S = property(lambda self: self._f.S, doc="The last update's innovation covariance.")
    nis = property(lambda self: self._f.nis, doc="The last update's normalised innovation squared.")
    log_likelihood = property(lambda self: self._f.log_likelihood, doc="The last update's log-likelihood.")

    def reset(self, x0: Any = None, P0: Any = None) -> None:
        """Restarts at the dataset's start, or from ``x0`` and ``P0`` at that time."""
        self._f.reset(
            None if x0 is None else _float_array("x0", x0, 1),
            None if P0 is None else _float_array("P0", P0, 2),
        )

    def predict_to(self, t: float) -> None:
        """Propagates to time ``t`` across the dataset's inputs."""
        self._f.predict_to(float(t))

    def predict(self, t: Any, u: Any) -> None:
        """Propagates across input knots ``t`` (the first the estimate's time) with inputs
        ``u`` (one row per knot: 3 specific forces for the platform, 3 body rates then 3
        specific forces for a strapdown unit)."""
        self._f.predict(_float_array("t", t, 1), _float_array("u", u, 2))

    def observation(self, index: int):
        """``(z, sigma, available)`` of the dataset's measurement ``index`` at the estimate."""
        return self._f.observation(int(index))

    def update(self, z: Any, sigma: Any, available: Any = None) -> None:
        """Corrects the estimate with ``z`` (one value per channel), its one-sigmas, and which
        channels are present (all when None; NaN values must be marked absent)."""
        avail = None if available is None else np.ascontiguousarray(available, dtype=bool)
        if avail is not None and avail.ndim != 1:
            raise NavkfError(f"available: shape {avail.shape}; expected 1-D")
        self._f.update(_float_array("z", z, 1), _float_array("sigma", sigma, 1), avail)

    def step(self) -> Optional[int]:
        """Predicts to the dataset's next measurement and updates with it; returns its index,
        or None at the end of the dataset."""
        return self._f.step()

    def __repr__(self) -> str:
        return repr(self._f)
