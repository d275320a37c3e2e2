"""simulate() against `tactile simulate`'s file for the same options."""

from __future__ import annotations

from pathlib import Path

import pytest

import tactile

CASES = [
    # (keywords, the same options as flags)
    (
        dict(contact_angle=10, azimuth=-30, peak_load=3, rate=100),
        ["--contact-angle", "10", "--azimuth", "-30", "--peak-load", "3", "--rate", "100"],
    ),
    (
        dict(
            contact_angle=25,
            azimuth=60,
            peak_load=5,
            rate=50,
            modulus_pa=150e3,
            then_peak_load=[2, 4],
            noise_v=0.002,
            noise_load_n=0.01,
            seed=7,
            effect=["viscoelastic_relaxation:tau_s=3,fraction=0.3", "thermal_drift:amplitude_V=0.01,tau_s=60"],
            gain=(2000, 900, 800),
            smoother_alpha=0.5,
            ambient_swing=(1.5, 30),
            excitation_v=3.0,
        ),
        [
            "--contact-angle", "25", "--azimuth", "60", "--peak-load", "5", "--rate", "50",
            "--modulus-pa", "150000", "--then-peak-load", "2", "--then-peak-load", "4",
            "--noise-v", "0.002", "--noise-load-n", "0.01", "--seed", "7",
            "--effect", "viscoelastic_relaxation:tau_s=3,fraction=0.3",
            "--effect", "thermal_drift:amplitude_V=0.01,tau_s=60",
            "--gain", "2000", "900", "800", "--smoother-alpha", "0.5", "--ambient-swing", "1.5", "30",
            "--excitation-v", "3.0",
        ],
    ),
]


@pytest.mark.parametrize("keywords,flags", CASES, ids=["defaults", "every-option"])
def test_simulate_equals_the_clis_file(cli, scratch: Path, keywords: dict, flags: list) -> None:
    expected = scratch / f"simulate-{len(flags)}.csv"
    cli.run("simulate", *flags, "--out", expected)
    df = tactile.simulate(**keywords)
    assert df.equals(tactile.read_recording(expected))
    assert df.attrs == tactile.read_recording(expected).attrs
    written = scratch / f"simulate-{len(flags)}-py.csv"
    tactile.write_recording(df, written)
    assert written.read_bytes() == expected.read_bytes()


def test_one_effect_or_load_may_be_given_alone() -> None:
    alone = tactile.simulate(contact_angle=0, azimuth=0, peak_load=2, rate=50, then_peak_load=1,
                             effect="highpass_coupling:tau_s=40")
    listed = tactile.simulate(contact_angle=0, azimuth=0, peak_load=2, rate=50, then_peak_load=[1],
                              effect=["highpass_coupling:tau_s=40"])
    assert alone.equals(listed)
    assert "highpass_coupling" in alone.attrs["source"]
