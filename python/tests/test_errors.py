"""Errors are exceptions carrying the message `tactile` prints, naming the file, line and field."""

from __future__ import annotations

from pathlib import Path

import pandas as pd
import pytest

import tactile

GOOD_META = [
    ("format", "tactile-recording/1"),
    ("sample_rate_hz", "100"),
    ("contact_angle_deg", "0"),
    ("azimuth_deg", "0"),
    ("fingertip_radius_mm", "20"),
    ("gain_fz", "3000"),
    ("gain_mx", "1000"),
    ("gain_my", "1000"),
    ("excitation_V", "3.3"),
]


def write(path: Path, meta: list, rows: str = "0,0,0,0,0,0\n") -> Path:
    text = "".join(f"# {k} = {v}\n" for k, v in meta)
    path.write_text(text + "t_s,rod_mm,load_N,fz_V,mx_V,my_V\n" + rows)
    return path


def test_a_missing_file_is_a_file_error_with_the_clis_message(cli, scratch: Path) -> None:
    missing = scratch / "no-such.csv"
    with pytest.raises(tactile.TactileFileError) as e:
        tactile.read_recording(missing)
    assert isinstance(e.value, OSError)
    assert str(e.value) == cli.error("diagnose", missing, "--json", scratch / "x.json")
    with pytest.raises(tactile.TactileFileError):
        tactile.diagnose(missing)


def test_malformed_metadata_names_the_line_and_key(cli, scratch: Path) -> None:
    meta = [(k, "0" if k == "gain_mx" else v) for k, v in GOOD_META]
    bad = write(scratch / "bad-gain.csv", meta)
    with pytest.raises(tactile.TactileDataError) as e:
        tactile.read_recording(bad)
    assert isinstance(e.value, ValueError)
    message = str(e.value)
    assert "line 7, field `gain_mx`" in message, message
    assert message == cli.error("diagnose", bad, "--json", scratch / "x.json")


def test_a_bad_field_names_the_line_and_column(scratch: Path) -> None:
    bad = write(scratch / "bad-field.csv", GOOD_META, "0,0,0,0,0,0\n0.01,1,x,0,0,0\n")
    with pytest.raises(tactile.TactileDataError, match=r"line 12, field `load_N`: `x` is not a number"):
        tactile.read_recording(bad)


def test_a_dataframe_the_format_refuses_is_not_written(scratch: Path) -> None:
    good = tactile.read_recording(write(scratch / "good.csv", GOOD_META))
    out = scratch / "refused.csv"
    missing = good.copy()
    del missing.attrs["excitation_V"]
    with pytest.raises(tactile.TactileDataError, match="required metadata key `excitation_V` missing"):
        tactile.write_recording(missing, out)
    negative = good.copy()
    negative.attrs["sample_rate_hz"] = -5.0
    with pytest.raises(tactile.TactileDataError, match=r"line 2, field `sample_rate_hz`: `-5` is not a positive"):
        tactile.write_recording(negative, out)
    text = good.copy()
    text.attrs["gain_fz"] = "lots"
    with pytest.raises(tactile.TactileDataError, match=r"key `gain_fz`: 'lots' is not a number"):
        tactile.write_recording(text, out)
    no_column = good.drop(columns=["my_V"])
    with pytest.raises(tactile.TactileDataError, match="required column `my_V` missing"):
        tactile.write_recording(no_column, out)
    backwards = pd.concat([good, good.assign(t_s=-1.0)], ignore_index=True)
    backwards.attrs = dict(good.attrs)
    with pytest.raises(tactile.TactileDataError, match="field `t_s`"):
        tactile.write_recording(backwards, out)
    assert not out.exists()


def test_simulate_options_out_of_range_carry_the_clis_message(cli, scratch: Path) -> None:
    flags = ["--contact-angle", "0", "--azimuth", "0", "--out", scratch / "never.csv"]
    cases = [
        (dict(peak_load=0), ["--peak-load", "0"]),
        (dict(peak_load=2, smoother_alpha=1.5), ["--peak-load", "2", "--smoother-alpha", "1.5"]),
        (dict(peak_load=2, effect="no_such_effect"), ["--peak-load", "2", "--effect", "no_such_effect"]),
    ]
    for keywords, more in cases:
        with pytest.raises(tactile.TactileDataError) as e:
            tactile.simulate(contact_angle=0, azimuth=0, **keywords)
        assert str(e.value) == cli.error("simulate", *flags, *more)


def test_diagnose_too_short_a_recording_names_it(cli, scratch: Path) -> None:
    short = write(scratch / "short.csv", GOOD_META, "0,0,0,0,0,0\n0.01,0.1,0.1,0,0,0\n")
    with pytest.raises(tactile.TactileDataError) as e:
        tactile.diagnose(short)
    assert str(e.value) == cli.error("diagnose", short, "--json", scratch / "short.json")
    assert str(short) in str(e.value)
