import os
from typing import Any, Dict, Optional, Sequence, Union

import pandas as pd

from ._errors import TactileDataError as TactileDataError
from ._errors import TactileError as TactileError
from ._errors import TactileFileError as TactileFileError

PathLike = Union[str, os.PathLike[str]]

def read_recording(path: PathLike) -> pd.DataFrame: ...
def write_recording(df: pd.DataFrame, path: PathLike) -> None: ...
def simulate(
    *,
    contact_angle: float,
    azimuth: float,
    peak_load: float,
    rate: Optional[float] = None,
    recovery_s: Optional[float] = None,
    modulus_pa: Optional[float] = None,
    then_peak_load: Union[None, float, Sequence[float]] = None,
    noise_v: float = 0.0,
    noise_load_n: float = 0.0,
    seed: int = 1,
    effect: Union[None, str, Sequence[str]] = None,
    gain: Optional[Sequence[float]] = None,
    smoother_alpha: Optional[float] = None,
    ambient_swing: Optional[Sequence[float]] = None,
    excitation_v: Optional[float] = None,
    rod_speed: Optional[float] = None,
) -> pd.DataFrame: ...
def diagnose(
    recording: Union[PathLike, pd.DataFrame],
    name: str = "DataFrame",
    simulation: Optional[PathLike] = None,
) -> Dict[str, Any]: ...
def diagnose_session(
    paths: Union[PathLike, Sequence[PathLike]],
    simulations: Union[None, PathLike, Sequence[PathLike]] = None,
) -> Dict[str, Any]: ...
def chip() -> Dict[str, Any]: ...
