"""Type stubs of navkf's native module; the public API is navkf/__init__.py's."""

from os import PathLike
from typing import Any, Callable, Dict, List, Mapping, Optional, Tuple, Union

import numpy as np
import numpy.typing as npt

__version__: str

class NavkfError(ValueError):
    """An error of navkf's, with the file, line and column (or the setting) at fault."""

class Dataset:
    """A dataset: inputs, measurements, the stated noise and priors, and truth when simulated."""

    @staticmethod
    def read(
        path: Union[str, PathLike[str]],
        effects_file: Optional[Union[str, PathLike[str]]] = None,
    ) -> Dataset:
        """Reads and validates a dataset folder (docs/data-format.md); with ``effects_file``
        its priors and truth may name the coefficients of the platform effects declared there."""
    @staticmethod
    def from_arrays(
        inputs: Mapping[str, npt.ArrayLike],
        measurements: Mapping[str, npt.ArrayLike],
        *,
        model: str = "platform",
        config: Optional[str] = None,
        truth: Optional[Mapping[str, npt.ArrayLike]] = None,
        name: str = "dataset",
    ) -> Dataset:
        """A dataset from columns in memory (NaN: an empty cell), checked as a folder is."""
    def write(self, path: Union[str, PathLike[str]]) -> None:
        """Writes the dataset into a new folder, or one navkf wrote before (replaced whole)."""
    @property
    def name(self) -> str: ...
    @property
    def model(self) -> str:
        """``"platform"`` or ``"strapdown"``."""
    @property
    def inputs(self) -> Dict[str, npt.NDArray[np.float64]]:
        """The input file's columns by header name."""
    @property
    def measurements(self) -> Dict[str, npt.NDArray[np.float64]]:
        """``measurements.csv``'s columns by header name; NaN where a sensor gave nothing."""
    @property
    def truth(self) -> Optional[Dict[str, npt.NDArray[np.float64]]]:
        """``truth.csv``'s columns, or None."""
    @property
    def noise(self) -> Dict[str, Any]:
        """``dataset.toml``'s ``[noise]`` keys."""
    @property
    def noise_stated(self) -> bool:
        """Whether ``dataset.toml`` states the noise."""
    def summary(self) -> Dict[str, Any]:
        """``navkf inspect --json``'s summary."""
    def warnings(self) -> List[str]:
        """The plausibility warnings ``navkf inspect`` prints."""
    def __len__(self) -> int: ...

class Filter:
    def __init__(
        self, kind: str, dataset: Dataset, effects: List[str], attitude: Optional[str] = None
    ) -> None: ...
    kind: str
    state_names: List[str]
    channel_names: List[str]
    t: float
    step_index: int
    x: npt.NDArray[np.float64]
    P: npt.NDArray[np.float64]
    channels: List[int]
    innovation: npt.NDArray[np.float64]
    S: npt.NDArray[np.float64]
    nis: float
    log_likelihood: float
    def reset(
        self,
        x0: Optional[npt.NDArray[np.float64]] = None,
        P0: Optional[npt.NDArray[np.float64]] = None,
    ) -> None: ...
    def predict_to(self, t: float) -> None: ...
    def predict(self, t: npt.NDArray[np.float64], u: npt.NDArray[np.float64]) -> None: ...
    def observation(
        self, index: int
    ) -> Tuple[npt.NDArray[np.float64], npt.NDArray[np.float64], npt.NDArray[np.bool_]]: ...
    def update(
        self,
        z: npt.NDArray[np.float64],
        sigma: npt.NDArray[np.float64],
        available: Optional[npt.NDArray[np.bool_]] = None,
    ) -> None: ...
    def step(self) -> Optional[int]: ...

def simulate(
    *,
    out: str,
    seed: int,
    run_index: int,
    effects: str,
    model: str,
    trajectory_toml: Optional[str],
    duration: Optional[float],
    attitude: Optional[str],
    azimuth_sigma: Optional[float],
    truth: bool,
    unit: Optional[str],
    imu_rate: Optional[float],
    nhc_sigma: Optional[float],
    body_motion: Optional[float],
    effects_file: Optional[str],
) -> Dataset: ...
def study(
    *,
    path: Optional[str],
    json: Optional[str],
    runs: Optional[int],
    out: Optional[str],
    progress: Optional[Callable[[int, int], Any]],
) -> Tuple[str, str, str]: ...
def instruction_set() -> str: ...
def ignored_simd_setting() -> Optional[str]: ...
def families() -> List[Dict[str, Any]]: ...
def plan(*, path: Optional[str], json: Optional[str], out: Optional[str]) -> str: ...
def diagnose(
    dataset: Dataset,
    *,
    with_: List[str],
    priors: Mapping[str, float],
    level_sigma: Optional[float],
    azimuth_sigma: Optional[float],
    fit_noise: bool,
    filter: str,
    attitude: Optional[str],
    window: float,
    max_rounds: int,
    effects_file: Optional[str],
    out: Optional[str],
    progress: Optional[Callable[[int, int], Any]],
) -> Tuple[str, Dict[str, Dict[str, Any]]]: ...
