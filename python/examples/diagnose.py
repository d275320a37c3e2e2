"""Simulate a compression test with a missing piece of physics, diagnose it, and plot the
recording against the nominal baseline with the mismatch windows the diagnosis found.

    python python/examples/diagnose.py [RECORDING.csv] [--png OUT.png]

Without a recording it simulates one (viscoelastic relaxation and noise on top of the
baseline). Writes a PNG (headless: matplotlib's Agg backend) and prints the verdict.
"""

from __future__ import annotations

import argparse

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402  (after choosing the backend)

import tactile  # noqa: E402

CHANNELS = [("load_N", "load [N]"), ("fz_V", "Fz [V]"), ("mx_V", "Mx [V]"), ("my_V", "My [V]")]


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("recording", nargs="?", help="a recording CSV (default: simulate one)")
    parser.add_argument("--png", default="diagnosis.png", help="the plot to write")
    args = parser.parse_args()

    if args.recording:
        rec = tactile.read_recording(args.recording)
        name = args.recording
        peak_n = max(rec["load_N"].max(), 0.1)  # the test's peak load, as near as it shows
    else:
        peak_n = 10.0
        rec = tactile.simulate(contact_angle=20, azimuth=60, peak_load=peak_n, rate=50, noise_v=0.002,
                               noise_load_n=0.02, effect="viscoelastic_relaxation:tau_s=3,fraction=0.3")
        name = "simulated"
    a = rec.attrs
    # The nominal model's recording of the same test: what the sensor should have read.
    baseline = tactile.simulate(contact_angle=a["contact_angle_deg"], azimuth=a["azimuth_deg"],
                                peak_load=peak_n, rate=a["sample_rate_hz"],
                                gain=(a["gain_fz"], a["gain_mx"], a["gain_my"]),
                                excitation_v=a["excitation_V"])
    report = tactile.diagnose(rec, name=name)

    fig, axes = plt.subplots(len(CHANNELS), 1, sharex=True, figsize=(9, 9))
    for ax, (column, label) in zip(axes, CHANNELS):
        ax.plot(rec["t_s"], rec[column], lw=0.8, label="recording")
        ax.plot(baseline["t_s"], baseline[column], lw=0.8, ls="--", label="nominal baseline")
        for m in report["mismatches"]:
            if m["channel"] == column:
                ax.axvspan(m["t_start_s"], m["t_end_s"], color="tab:red", alpha=0.15)
        ax.set_ylabel(label)
    axes[0].legend(loc="upper right")
    axes[-1].set_xlabel("t [s]")
    found = ", ".join(e["name"] for e in report["effects"]) or "none"
    fig.suptitle(f"{name}: {report['verdict']}; effects: {found} (red: mismatch windows)")
    fig.tight_layout()
    fig.savefig(args.png, dpi=100)
    print(f"verdict {report['verdict']}, effects {found}; wrote {args.png}")


if __name__ == "__main__":
    main()
