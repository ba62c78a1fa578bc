"""Type stubs of the native extension (``viscoslide._native``, built from
``python/src/`` with pyo3). Private: use the ``viscoslide`` package."""

from typing import Any, Callable, Dict, List, Optional, Tuple

import numpy as np
import numpy.typing as npt

VERSION: str

class Material:
    @staticmethod
    def from_section(section_json: str, base_dir: str) -> "Material": ...
    @staticmethod
    def from_toml(path: str) -> "Material": ...
    @staticmethod
    def fit_dma(
        omega: List[float],
        storage: List[float],
        loss: List[float],
        temperatures: Optional[List[float]],
        wlf: Optional[Tuple[float, float, float]],
        temperature: Optional[float],
        terms: int,
        ratio: float,
        poisson: float,
    ) -> Tuple["Material", Dict[str, Any]]: ...
    def complex_modulus(self, omega: npt.NDArray[np.float64]) -> npt.NDArray[np.complex128]: ...
    @property
    def relaxed_modulus(self) -> float: ...
    @property
    def glassy_modulus(self) -> float: ...
    @property
    def poisson(self) -> float: ...
    @property
    def wlf(self) -> Optional[Tuple[float, float, float]]: ...
    @property
    def wlf_range(self) -> Optional[Tuple[float, float]]: ...
    @property
    def frequency_range(self) -> Optional[Tuple[float, float]]: ...
    @property
    def creep_spectrum(self) -> List[Tuple[float, float]]: ...
    def section_json(self) -> str: ...

class Surface:
    @staticmethod
    def generate(generate_json: str, base_dir: str) -> "Surface": ...
    @staticmethod
    def from_file(
        path: str,
        length: Optional[float] = None,
        length_y: Optional[float] = None,
        format: Optional[str] = None,
        fill_missing: bool = False,
        detrend: Optional[str] = None,
        window: Optional[str] = None,
        periodic: bool = False,
    ) -> "Surface": ...
    @staticmethod
    def from_array(
        heights: npt.NDArray[np.float64],
        length: float,
        length_y: Optional[float] = None,
        detrend: Optional[str] = None,
        window: Optional[str] = None,
        periodic: bool = False,
        fill_missing: bool = False,
    ) -> "Surface": ...
    def preprocessing_json(self) -> Optional[str]: ...
    @property
    def heights(self) -> npt.NDArray[np.float64]: ...
    @property
    def shape(self) -> Tuple[int, int]: ...
    @property
    def cell_size(self) -> float: ...
    @property
    def lengths(self) -> Tuple[float, float]: ...
    @property
    def seed(self) -> Optional[int]: ...
    def section_json(self) -> Optional[str]: ...
    def psd(
        self, window_name: Optional[str] = None
    ) -> Tuple[npt.NDArray[np.float64], npt.NDArray[np.float64], npt.NDArray[np.uint64]]: ...
    def stats_json(self, window_name: Optional[str] = None) -> str: ...

class Result:
    @property
    def friction_coefficient(self) -> float: ...
    @property
    def friction_coefficient_dissipation(self) -> float: ...
    @property
    def contact_area_fraction(self) -> float: ...
    @property
    def approach(self) -> float: ...
    @property
    def pressure(self) -> npt.NDArray[np.float64]: ...
    @property
    def gap(self) -> npt.NDArray[np.float64]: ...
    @property
    def displacement(self) -> npt.NDArray[np.float64]: ...
    @property
    def contact(self) -> npt.NDArray[np.float64]: ...
    @property
    def grid(self) -> Tuple[int, int]: ...
    @property
    def backend_line(self) -> str: ...
    def summary_json(self) -> str: ...
    def convergence_json(self) -> str: ...
    def analysis_json(self) -> Optional[str]: ...
    def heating_json(self) -> Optional[str]: ...
    @property
    def temperature_rise(self) -> Optional[npt.NDArray[np.float64]]: ...
    @property
    def temperature_depth(self) -> Optional[List[Tuple[float, float, float, float]]]: ...
    def heat(
        self,
        conductivity: float,
        diffusivity: float,
        block_length: Optional[float],
        source: Optional[str],
        refined_layers: bool,
    ) -> Tuple[str, npt.NDArray[np.float64]]: ...
    def write(self, directory: str) -> List[str]: ...

Progress = Optional[Callable[[Dict[str, Any]], None]]

def solve(
    surface: Surface,
    material: Material,
    loading_json: str,
    solver_json: str,
    layer_json: Optional[str],
    heating_json: Optional[str],
    backend: Optional[str],
    progress: Progress = None,
) -> Result: ...
class SweepPlan:
    def __init__(
        self,
        surface: Surface,
        material: Material,
        loading_json: str,
        solver_json: str,
        layer_json: Optional[str],
        heating_json: Optional[str],
        backend: Optional[str],
        sliding: str,
        speeds: List[float],
        load: str,
        loads: List[float],
        vary: List[Tuple[str, List[Any]]],
    ) -> None: ...
    def __len__(self) -> int: ...
    def points_json(self) -> str: ...
    def solve(self, index: int, backend: Optional[str], progress: Progress = None) -> Result: ...

def solve_config(path: str, overrides: List[str], backend: Optional[str], progress: Progress = None) -> Result: ...
def persson(
    surface: Surface, material: Material, loading_json: str, speeds: List[float]
) -> Tuple[
    npt.NDArray[np.float64],
    npt.NDArray[np.float64],
    npt.NDArray[np.float64],
    str,
    float,
    Optional[str],
    Optional[Tuple[float, float]],
    List[str],
    List[str],
]: ...
def kernel_table(
    material: Material,
    nx: int,
    ny: int,
    cell_size: float,
    speed: float,
    direction_deg: float,
    layer_json: Optional[str],
    derivative: bool,
    cell_size_y: Optional[float] = None,
    temperature: Optional[float] = None,
) -> Tuple[npt.NDArray[np.float64], Optional[str]]: ...
def magnification(
    path: str,
    overrides: List[str],
    q1: Optional[List[float]],
    scales: Optional[List[float]],
    cells_per_wavelength: float,
    speeds: Optional[List[float]],
    backend: Optional[str],
    shard: Optional[str],
    out: Optional[str],
) -> Optional[str]: ...
def surface_temperature(
    flux: npt.NDArray[np.float64],
    cell_size: float,
    speed: float,
    conductivity: float,
    diffusivity: float,
    periodic: bool,
    block_length: Optional[float],
    direction_deg: float,
    cell_size_y: Optional[float] = None,
) -> Tuple[npt.NDArray[np.float64], List[str]]: ...
