"""diagnose() and chip() against `tactile diagnose --json` and `tactile chip --json`."""

from __future__ import annotations

import json
from pathlib import Path

import pytest

import tactile


def without_seconds(report: dict) -> dict:
    """The report without the wall time, the one field two runs may differ in."""
    assert isinstance(report.pop("seconds"), float)
    return report


@pytest.fixture(scope="module")
def recording(cli, scratch: Path) -> Path:
    out = scratch / "diag.csv"
    cli.run(
        "simulate", "--contact-angle", "20", "--azimuth", "60", "--peak-load", "10",
        "--rate", "50", "--noise-v", "0.002", "--noise-load-n", "0.02",
        "--effect", "viscoelastic_relaxation:tau_s=3,fraction=0.3", "--out", out,
    )
    return out


@pytest.fixture(scope="module")
def cli_report(cli, scratch: Path, recording: Path) -> dict:
    out = scratch / "diag.json"
    cli.run("diagnose", recording, "--json", out, "--quiet")
    return json.loads(out.read_text())


def test_diagnose_a_file_equals_the_clis_json(recording: Path, cli_report: dict) -> None:
    got = tactile.diagnose(str(recording))
    assert without_seconds(got) == without_seconds(dict(cli_report))
    assert got["recording"] == str(recording)


def test_diagnose_a_dataframe_equals_the_clis_json(recording: Path, cli_report: dict) -> None:
    df = tactile.read_recording(recording)
    got = tactile.diagnose(df, name=str(recording))
    assert without_seconds(got) == without_seconds(dict(cli_report))
    assert any(e["name"] == "viscoelastic_relaxation" for e in got["effects"]), got["effects"]


def test_chip_equals_the_clis_json_and_matches_table_one(cli) -> None:
    figures = tactile.chip()
    assert figures == json.loads(cli.run("chip", "--json").stdout)
    for row in figures["table_i"]:
        assert 0.9 < row["ratio"] < 1.1, row
    s = figures["sensitivity_matrix"]["value"]
    c = figures["calibration_matrix"]["value"]
    for i in range(3):
        for j in range(3):
            product = sum(c[i][k] * s[k][j] for k in range(3))
            assert abs(product - (1.0 if i == j else 0.0)) < 1e-9, (i, j, product)
