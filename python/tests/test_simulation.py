"""diagnose(..., simulation=) and diagnose_session(..., simulations=): the user's own simulation
as the baseline (docs/simulation-format.md), as `tactile diagnose --simulation` takes it."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest

import tactile

META = {
    "contact_angle_deg": 20, "azimuth_deg": 60, "fingertip_radius_mm": 20,
    "gain_fz": 1100, "gain_mx": 110, "gain_my": 110, "excitation_V": 3.3,
}


def law(k: float, d: np.ndarray) -> np.ndarray:
    return k * np.clip(d, 0.0, None) ** 1.8


def write_pair(folder: Path, name: str, k: float) -> tuple:
    """A recording of the law with a gel k (load and Fz, no moments) and the lab's table at
    k = 1."""
    t = np.arange(0.0, 60.0, 0.01)
    d = np.interp(t, [0, 2, 2 + 6.5 * 3, 4 + 6.5 * 3, 4.65 + 6.5 * 3, 60], [-0.5, -0.5, 6, 6, -0.5, -0.5])
    rng = np.random.default_rng(len(name))
    f = law(k, d)
    df = pd_frame(t, d, f + rng.normal(0, 0.02, len(t)), 0.015 * f + rng.normal(0, 0.002, len(t)))
    rec = folder / name
    tactile.write_recording(df, rec)
    rows = np.arange(0.0, 6.25, 0.1)
    table = folder / f"sim-{name}"
    with open(table, "w") as out:
        out.write("# format = tactile-response/1\n# source = the lab's law\nrod_mm,load_N,fz_V\n")
        np.savetxt(out, np.column_stack([rows, law(1.0, rows), 0.015 * law(1.0, rows)]),
                   delimiter=",", fmt="%.9g")
    return rec, table


def pd_frame(t, d, f, fz):
    import pandas as pd

    nan = np.full(len(t), np.nan)
    df = pd.DataFrame({"t_s": t, "rod_mm": d, "load_N": f, "fz_V": fz, "mx_V": nan, "my_V": nan})
    df.attrs.update({"format": "tactile-recording/1", "sample_rate_hz": 100.0, **META})
    return df


def test_diagnose_against_a_simulation_is_the_clis_json(cli, scratch: Path) -> None:
    rec, table = write_pair(scratch, "simrec.csv", 1.1)
    got = tactile.diagnose(rec, simulation=table)
    assert got["verdict"] == "no_significant_mismatch"
    assert abs(got["baseline"]["params"]["load_scale"] - 1.1) < 0.01
    sim = got["baseline"]["simulation"]
    assert sim["form"] == "static_response" and sim["metadata"]["source"] == "the lab's law"
    assert set(sim["not_compared"]) == {"mx_V", "my_V"}
    out = scratch / "simrec.json"
    cli.run("diagnose", rec, "--simulation", table, "--json", out)
    want = json.loads(out.read_text())
    for r in (got, want):
        r.pop("seconds")
    assert got == want


def test_a_session_takes_one_simulation_per_recording(scratch: Path) -> None:
    folder = scratch / "simsession"
    folder.mkdir()
    pairs = [write_pair(folder, n, k) for n, k in (("a.csv", 1.0), ("b.csv", 1.2))]
    got = tactile.diagnose_session([p[0] for p in pairs], simulations=[p[1] for p in pairs])
    assert len(got["recordings"]) == 2 and all("error" not in r or r["error"] is None for r in got["recordings"])


def test_a_missing_simulation_is_a_file_error(scratch: Path) -> None:
    rec, _ = write_pair(scratch, "lonely.csv", 1.0)
    with pytest.raises(tactile.TactileFileError, match="nowhere.csv"):
        tactile.diagnose(rec, simulation=scratch / "nowhere.csv")
