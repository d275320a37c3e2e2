"""read_recording / write_recording against the files `tactile` writes."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest

import tactile

SIMULATE = ["--contact-angle", "15", "--azimuth", "40", "--peak-load", "4", "--rate", "100"]


@pytest.fixture(scope="module")
def simulated(cli, scratch: Path) -> Path:
    out = scratch / "sim.csv"
    cli.run("simulate", *SIMULATE, "--noise-v", "0.001", "--smoother-alpha", "0.3", "--out", out)
    return out


def header(path: Path) -> list:
    lines = path.read_text().splitlines()
    return next(line for line in lines if not line.startswith("#")).split(",")


def test_read_keeps_the_files_columns_and_metadata(simulated: Path) -> None:
    df = tactile.read_recording(simulated)
    assert list(df.columns) == header(simulated)
    assert all(df[c].dtype == np.float64 for c in df.columns)
    assert df.attrs["format"] == "tactile-recording/1"
    assert df.attrs["contact_angle_deg"] == 15.0
    assert df.attrs["sample_rate_hz"] == 100.0
    assert df.attrs["firmware_smoother_alpha"] == "0.3"
    meta = [line[2:].split(" = ", 1) for line in simulated.read_text().splitlines() if line[0] == "#"]
    assert list(df.attrs) == [k for k, _ in meta]
    rows = [line for line in simulated.read_text().splitlines() if line[0].isdigit()]
    assert len(df) == len(rows)
    first = [float(x) if x else math.nan for x in rows[-1].split(",")]
    np.testing.assert_array_equal(df.iloc[-1].to_numpy(), np.array(first))


def test_round_trip_reproduces_the_clis_file(simulated: Path, scratch: Path) -> None:
    back = scratch / "sim-back.csv"
    tactile.write_recording(tactile.read_recording(simulated), back)
    assert back.read_bytes() == simulated.read_bytes()


def test_material_only_import_keeps_unmeasured_columns_empty(cli, scratch: Path) -> None:
    machine = scratch / "machine.csv"
    cli.run("simulate", *SIMULATE, "--out", scratch / "unused.csv", "--machine-csv", machine)
    imported = scratch / "imported.csv"
    cli.run("import", machine, "--format", "csv", "--radius-mm", "2", "--out", imported)
    df = tactile.read_recording(imported)
    for sensor in ("fz_V", "mx_V", "my_V"):
        assert df[sensor].isna().all(), sensor
    assert df["load_N"].notna().any()
    back = scratch / "imported-back.csv"
    tactile.write_recording(df, back)
    assert back.read_bytes() == imported.read_bytes()


def test_columns_in_another_order_and_extra_columns_are_kept(scratch: Path) -> None:
    path = scratch / "order.csv"
    meta = "".join(
        f"# {k} = {v}\n"
        for k, v in [
            ("format", "tactile-recording/1"),
            ("sample_rate_hz", "1000"),
            ("contact_angle_deg", "20"),
            ("azimuth_deg", "60"),
            ("fingertip_radius_mm", "20"),
            ("gain_fz", "3000"),
            ("gain_mx", "1000"),
            ("gain_my", "1000"),
            ("excitation_V", "3.3"),
            ("lab", "B2"),
        ]
    )
    path.write_text(meta + "my_V,seq,t_s,temp_C,rod_mm,load_N,fz_V,mx_V\n5,7,0,25.5,1,2,,4\n6,8,0.001,,1,2,,4\n")
    df = tactile.read_recording(path)
    assert list(df.columns) == ["my_V", "seq", "t_s", "temp_C", "rod_mm", "load_N", "fz_V", "mx_V"]
    assert df["seq"].tolist() == [7.0, 8.0]
    assert df["fz_V"].isna().all() and math.isnan(df["temp_C"][1])
    assert df.attrs["lab"] == "B2"
    out = scratch / "order-back.csv"
    tactile.write_recording(df, out)
    again = tactile.read_recording(out)
    assert list(again.columns) == ["t_s", "rod_mm", "load_N", "fz_V", "mx_V", "my_V", "temp_C", "seq"]
    assert again[list(df.columns)].equals(df)
