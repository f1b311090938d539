"""Type stubs of the native module (units as the names say)."""

from typing import Callable, Dict, List, Optional, Tuple, Union

import numpy as np

__version__: str

class Case:
    """A case: catenary, pantographs and run. Picklable by its TOML text."""

    @staticmethod
    def preset(name: str) -> "Case": ...
    @staticmethod
    def from_toml(text: str) -> "Case": ...
    @staticmethod
    def from_file(path: str) -> "Case": ...
    def with_overrides(self, overrides: Dict[str, Union[float, int, bool, str]]) -> "Case":
        """Values by dotted path, each in its field's unit (``run.speed_kmh``: km/h,
        ``catenary.contact_wire.tension_n``: N). Raises ValueError naming the field."""
    def get(self, path: str) -> object:
        """The value at a dotted path (``"run.start_m"``), in its field's unit."""
    def to_toml(self) -> str: ...
    def validate(self) -> List[str]:
        """The warnings; raises ValueError naming the field and value of an error."""

class RealtimeCatenary:
    """The moving-window catenary (HIL: force and position in, height and velocity out)."""

    def __init__(self, case: Case, window_m: float = 215.0, coupling: str = "hil",
                 pantograph: Optional[str] = None) -> None: ...
    def step(self, force_n: float, track_position_m: float) -> Tuple[float, float]:
        """One fixed step: contact force (N, up) and track position (m) in; contact-wire
        height (m) and vertical velocity (m/s) at the contact point out. A refused input or a
        rolled-back step raises ValueError with the reason; the catenary is then unchanged."""
    def try_step(self, force_n: float, track_position_m: float) -> Tuple[str, Optional[float], Optional[float]]:
        """step() without raising: ("ok", height_m, velocity_m_s) or (code, None, None)."""
    @property
    def start_position_m(self) -> float: ...
    @property
    def force_limit_n(self) -> float: ...
    @property
    def dt_s(self) -> float: ...
    @property
    def moves(self) -> int: ...
    @property
    def n_modes(self) -> int: ...

def run(case: Case, threads: int = 1, allow_dewirement: bool = False,
        allow_contact_loss: bool = False, verify: bool = False) -> Tuple[str, List[Tuple[str, np.ndarray]], Optional[str]]: ...
def run_many(cases: List[Case], jobs: Optional[int] = None, allow_dewirement: bool = False,
             allow_contact_loss: bool = False) -> List[Tuple[str, List[Tuple[str, np.ndarray]], Optional[str]]]: ...
def eva(case: Case, speeds_kmh: List[float], tensions_n: List[float], step_m: float = 1.0,
        tolerance_j: float = 0.01, fraction: float = 0.99, jobs: Optional[int] = None,
        seeds: Optional[int] = None, shard: Optional[Tuple[int, int]] = None, max_steps: Optional[int] = None,
        max_memory_gb: Optional[float] = None) -> str: ...
def window(case: Case, speeds_kmh: List[float], tensions_n: List[float], mean_tol_pct: float = 1.0,
           sigma_tol_pct: float = 3.0, max_tol_pct: float = 5.0, min_window_m: Optional[float] = None,
           max_window_m: float = 400.0, coarse_m: float = 20.0, resolution_m: float = 1.0,
           jobs: Optional[int] = None, seeds: Optional[int] = None, shard: Optional[Tuple[int, int]] = None,
           max_steps: Optional[int] = None, max_memory_gb: Optional[float] = None,
           full_scan: bool = True, pantograph: Optional[str] = None) -> str: ...
def validate(name: str, jobs: Optional[int] = None) -> str: ...
def assess(what_json: str, kind: str, system: Optional[str] = None, criteria_toml: Optional[str] = None) -> str: ...
def presets_list() -> List[str]: ...
def study(spec_toml: str, base_dir: str = ".") -> Tuple[str, str, List[Tuple[str, str]]]: ...
def design_header(spec_toml: str, base_dir: str) -> List[str]: ...
def design_evaluate(spec_toml: str, base_dir: str, x: List[float]) -> List[str]: ...
def design(spec_toml: str, base_dir: str, journal: List[List[str]] = ..., on_batch: Optional[Callable[[List[List[str]]], None]] = None,
           evaluate: Optional[Callable[[List[List[float]]], List[List[str]]]] = None,
           jobs: Optional[int] = None) -> Tuple[str, List[str]]: ...
