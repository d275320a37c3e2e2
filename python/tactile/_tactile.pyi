# The compiled module (python/src/lib.rs); use the package's functions instead.
from typing import Dict, List, Optional, Tuple

_Columns = List[Tuple[str, bytes]]
_Table = Tuple[_Columns, Dict[str, object]]

def read_recording(path: str) -> _Table: ...
def write_recording(columns: _Columns, attrs: Dict[str, object], path: str) -> None: ...
def simulate(
    contact_angle: float,
    azimuth: float,
    peak_load: float,
    rate: Optional[float] = None,
    recovery_s: Optional[float] = None,
    modulus_pa: Optional[float] = None,
    then_peak_load: Optional[List[float]] = None,
    noise_v: Optional[float] = None,
    noise_load_n: Optional[float] = None,
    seed: Optional[int] = None,
    effect: Optional[List[str]] = None,
    gain: Optional[Tuple[float, float, float]] = None,
    smoother_alpha: Optional[float] = None,
    ambient_swing: Optional[Tuple[float, float]] = None,
    excitation_v: Optional[float] = None,
    rod_speed: Optional[float] = None,
) -> _Table: ...
def diagnose_file(path: str, simulation: Optional[str] = None) -> str: ...
def diagnose_frame(
    columns: _Columns, attrs: Dict[str, object], name: str, simulation: Optional[str] = None
) -> str: ...
def diagnose_session_json(paths: List[str], simulations: Optional[List[str]] = None) -> str: ...
def chip_json() -> str: ...
