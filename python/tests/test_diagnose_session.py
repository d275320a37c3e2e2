"""diagnose_session() against `tactile diagnose --joint ... --json`."""

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
def session(scratch: Path) -> Path:
    """A folder of three short recordings of one chip turned by 6°, at azimuths 0, 45 and 90°."""
    folder = scratch / "session"
    folder.mkdir()
    for azimuth in (0, 45, 90):
        df = tactile.simulate(
            contact_angle=20, azimuth=azimuth, peak_load=2, rate=250, recovery_s=20,
            noise_v=0.0005, noise_load_n=0.002, seed=azimuth + 1, effect="crosstalk:angle_deg=6",
        )
        tactile.write_recording(df, folder / f"az{azimuth}.csv")
    return folder


@pytest.fixture(scope="module")
def cli_report(cli, scratch: Path, session: Path) -> dict:
    out = scratch / "session.json"
    cli.run("diagnose", "--joint", session, "--json", out, "--quiet")
    return json.loads(out.read_text())


def test_diagnose_session_equals_the_clis_json(session: Path, cli_report: dict) -> None:
    got = tactile.diagnose_session([session])
    assert got["format"] == "tactile-session-diagnosis/1"
    assert without_seconds(got) == without_seconds(dict(cli_report))
    assert [r["file"] for r in got["recordings"]] == ["az0.csv", "az45.csv", "az90.csv"]
    assert any(s["name"] == "crosstalk" for s in got["shared"]), got["shared"]


def test_one_path_alone_is_the_session(session: Path, cli_report: dict) -> None:
    # A list of files is the next test's; a folder in a list the first one's.
    got = tactile.diagnose_session(session)
    assert without_seconds(got) == without_seconds(dict(cli_report))


def test_a_bad_file_is_its_rows_error_and_no_good_file_is_the_clis_error(
    cli, scratch: Path, session: Path
) -> None:
    bad = scratch / "not-a-recording.csv"
    bad.write_text("t_s,load_N\n0,1\n")
    got = tactile.diagnose_session([session / "az0.csv", bad, session / "az90.csv"])
    rows = got["recordings"]
    assert [r["file"] for r in rows] == ["az0.csv", "not-a-recording.csv", "az90.csv"]
    assert "error" in rows[1] and "error" not in rows[0], rows
    with pytest.raises(tactile.TactileDataError) as e:
        tactile.diagnose_session([bad])
    assert str(e.value) == cli.error("diagnose", "--joint", bad, "--json", scratch / "x.json")


def test_inputs_that_go_wrong_raise_before_any_work_with_the_clis_message(
    cli, scratch: Path, session: Path
) -> None:
    out = scratch / "never.json"
    missing = scratch / "missing.csv"
    with pytest.raises(tactile.TactileFileError) as e:
        tactile.diagnose_session([session / "az0.csv", missing])
    assert isinstance(e.value, OSError)
    assert str(missing) in str(e.value)
    assert str(e.value) == cli.error("diagnose", "--joint", session / "az0.csv", missing, "--json", out)
    assert cli.run("diagnose", "--joint", missing, "--json", out, ok=False).returncode == 66
    with pytest.raises(tactile.TactileDataError, match="no recording given"):
        tactile.diagnose_session([])
    twice = [session / "az0.csv", session / "." / "az0.csv"]
    with pytest.raises(tactile.TactileDataError) as e:
        tactile.diagnose_session(twice)
    assert "each recording is given once" in str(e.value)
    assert str(e.value) == cli.error("diagnose", "--joint", *twice, "--json", out)
    assert not out.exists()
