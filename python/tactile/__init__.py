"""Tactile fingertip recordings in Python: read and write the recording format
(``docs/recording-format.md``) as pandas DataFrames, simulate the standard compression test,
diagnose a recording (``docs/diagnosis-format.md``) or a session of them jointly
(``tactile-session-diagnosis/1``) and show the chip's figures.

Every function calls the same Rust libraries as the ``tactile`` command, so a file written here
is byte for byte the one ``tactile`` writes, ``diagnose`` returns what ``tactile diagnose --json``
writes, ``diagnose_session`` what ``tactile diagnose --joint --json`` writes, and errors carry the message ``tactile`` prints (:class:`TactileError`).
"""

from __future__ import annotations

import json
import os
from typing import Any, Dict, Iterable, Optional, Sequence, Tuple, Union

import numpy as np
import pandas as pd

from . import _tactile
from ._errors import TactileDataError, TactileError, TactileFileError

__all__ = [
    "read_recording",
    "write_recording",
    "simulate",
    "diagnose",
    "diagnose_session",
    "chip",
    "TactileError",
    "TactileDataError",
    "TactileFileError",
]

PathLike = Union[str, "os.PathLike[str]"]


def _frame(table: Tuple[list, dict]) -> pd.DataFrame:
    """A DataFrame of the compiled module's columns (native float64 bytes) and metadata."""
    columns, attrs = table
    df = pd.DataFrame(
        {name: np.frombuffer(values, dtype=np.float64).copy() for name, values in columns},
        columns=[name for name, _ in columns],
    )
    df.attrs.update(attrs)
    return df


def _columns(df: pd.DataFrame) -> list:
    """The DataFrame's columns as the compiled module takes them."""
    out = []
    for name in df.columns:
        if not isinstance(name, str):
            raise TactileDataError(f"DataFrame: column name {name!r} is not text")
        try:
            values = df[name].to_numpy(dtype=np.float64, na_value=np.nan)
        except (TypeError, ValueError) as e:
            raise TactileDataError(f"DataFrame: column `{name}` is not numeric: {e}") from None
        out.append((name, np.ascontiguousarray(values).tobytes()))
    return out


def read_recording(path: PathLike) -> pd.DataFrame:
    """Read a recording: one float64 column per column of the file, in the file's order and
    with its names; a missing value (an empty field, ``nan``) is NaN, and a column that was not
    measured is NaN on every row. The metadata are in ``df.attrs`` in the file's order: the
    typed keys (``sample_rate_hz``, ``gain_fz``, ``excitation_V``, ...) as floats, the others
    (``format``, ``source``, unknown keys) as text."""
    return _frame(_tactile.read_recording(os.fspath(path)))


def write_recording(df: pd.DataFrame, path: PathLike) -> None:
    """Write ``df`` as a recording, its metadata from ``df.attrs`` (as :func:`read_recording`
    gives them), exactly as ``tactile`` writes it: the required columns, ``temp_C``, then the
    other columns in the DataFrame's order; NaN as an empty field. A DataFrame the format
    refuses raises :class:`TactileDataError` naming the line and field of the file it would
    make."""
    _tactile.write_recording(_columns(df), dict(df.attrs), os.fspath(path))


def _list(value: Union[None, Any, Iterable[Any]], kind: type) -> Optional[list]:
    """A repeatable flag's values: one value or a sequence of them."""
    if value is None:
        return None
    if isinstance(value, (str, int, float)):
        return [kind(value)]
    return [kind(v) for v in value]


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
) -> pd.DataFrame:
    """The recording ``tactile simulate`` writes for the same options (one keyword per flag,
    same defaults; ``None`` takes the value of ``hardware/``). ``then_peak_load`` and
    ``effect`` take one value or a list, like the repeatable flags; ``gain`` is (Fz, Mx, My)
    and ``ambient_swing`` (amplitude degC, period s); ``rod_speed`` is ``--rod-speed``, mm/min.
    ``peak_load`` is the recorded load's peak, whatever the effects on the load."""
    table = _tactile.simulate(
        float(contact_angle),
        float(azimuth),
        float(peak_load),
        rate=rate,
        recovery_s=recovery_s,
        modulus_pa=modulus_pa,
        then_peak_load=_list(then_peak_load, float),
        noise_v=noise_v,
        noise_load_n=noise_load_n,
        seed=seed,
        effect=_list(effect, str),
        gain=None if gain is None else tuple(float(g) for g in gain),
        smoother_alpha=smoother_alpha,
        ambient_swing=None if ambient_swing is None else tuple(ambient_swing),
        excitation_v=excitation_v,
        rod_speed=rod_speed,
    )
    return _frame(table)


def diagnose(
    recording: Union[PathLike, pd.DataFrame],
    name: str = "DataFrame",
    simulation: Optional[PathLike] = None,
    accept_scale: bool = False,
) -> Dict[str, Any]:
    """The diagnosis of a recording file or DataFrame, as the dict of the JSON
    ``tactile diagnose --json`` writes (``docs/diagnosis-format.md``). A file is named in the
    report by its path as given; a DataFrame by ``name``. ``simulation``: the user's own
    simulation of the test as the baseline instead of ours (``tactile diagnose --simulation``,
    ``docs/simulation-format.md``): a recording of the simulated test or a static response
    table; the result's ``baseline.simulation`` says how it was aligned. A simulation whose
    fitted load or output scale, or rod travel, is more than 10x the recording's is refused
    (:class:`TactileDataError`, a unit read as another) unless ``accept_scale`` (as
    ``--accept-scale``)."""
    sim = None if simulation is None else os.fspath(simulation)
    if isinstance(recording, pd.DataFrame):
        text = _tactile.diagnose_frame(
            _columns(recording), dict(recording.attrs), name, sim, accept_scale
        )
    else:
        text = _tactile.diagnose_file(os.fspath(recording), sim, accept_scale)
    return json.loads(text)


def diagnose_session(
    paths: Union[PathLike, Sequence[PathLike]],
    simulations: Union[None, PathLike, Sequence[PathLike]] = None,
    accept_scale: bool = False,
) -> Dict[str, Any]:
    """The joint diagnosis of a session of recordings, one model of the sensor and the gel for
    all of them, as the dict of the JSON ``tactile diagnose --joint ... --json`` writes
    (``tactile-session-diagnosis/1``). ``paths``: recording files, and folders standing for
    every ``*.csv`` in them (sorted), in order; one path alone is a session of itself. A file
    that cannot be analysed is reported in its row of ``recordings`` with ``"error"``, as the
    command does (which then exits 65); when none can, :class:`TactileDataError` is raised
    with the command's message. Before any work, as the command: a missing file raises
    :class:`TactileFileError`; an empty list, a recording given twice (the same file, a link
    to it, a byte-identical copy) or recordings of another sensor or fingertip (their
    ``fingertip_radius_mm``, or where given ``chip_serial``, ``sensor`` or ``sensor_unit``) raise :class:`TactileDataError` naming them.
    ``simulations``: the user's own simulations as the baselines, as ``--simulation`` takes
    them: one file for every recording, one per recording in the recordings' order, or a folder
    holding a simulation named as each recording; ``accept_scale`` as in :func:`diagnose`."""
    if isinstance(paths, (str, os.PathLike)):
        paths = [paths]
    if isinstance(simulations, (str, os.PathLike)):
        simulations = [simulations]
    sims = None if simulations is None else [os.fspath(s) for s in simulations]
    return json.loads(
        _tactile.diagnose_session_json([os.fspath(p) for p in paths], sims, accept_scale)
    )


def chip() -> Dict[str, Any]:
    """The chip's figures ``tactile chip --json`` prints: sensitivities, calibration and
    crosstalk matrices, strengths, stiffnesses, Table I of the paper and the frame-FE check."""
    return json.loads(_tactile.chip_json())
