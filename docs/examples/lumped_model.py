"""A lab's lumped model of its fingertip, written as simulations for
`tactile diagnose --simulation` (docs/simulation-walkthrough.md walks through it).

    python3 docs/examples/lumped_model.py OUT_DIR

writes into OUT_DIR:
- rec.csv            a stand-in for the lab's measurement: the lumped model with a gel 10 % stiffer
                     than the lab thought, a relaxation the model lacks, offsets and noise;
- lumped-table.csv   the model as a static response (rod travel -> load and outputs);
- lumped-test.csv    the model as a simulated test at 200 Hz on its own clock, from first contact;
- lumped-qlv.csv     the same test with the relaxation added to the model (one Prony term).
Only numpy: the files are plain text in the formats of docs/simulation-format.md.
"""

import os
import sys

import numpy as np

# The lab's fingertip: a spring and a stiffening spring, F = k1 d + k3 d^3 (N, d in mm); the Fz
# bridge reads a share of the load that falls as the contact spreads, the moments grow with the
# lever arm, the travel (volts at the recording's amplifier gains).
K1, K3 = 2.0, 0.09
S_FZ, S_MX, S_MY = 0.016, 0.0012, -0.0007
JIG = dict(contact_angle_deg=20, azimuth_deg=60, fingertip_radius_mm=20)
FRONT = dict(gain_fz=1100, gain_mx=110, gain_my=110, excitation_V=3.3)


def load(d):
    d = np.clip(d, 0.0, None)
    return K1 * d + K3 * d**3


def outputs(f, d):
    d = np.clip(d, 0.0, None)
    return S_FZ * f**0.95, S_MX * f * d, S_MY * f * d


def model(stiffness, d):
    """Load and outputs at travels d, the gel `stiffness` times the lab's."""
    f = stiffness * load(d)
    return (f, *outputs(f, d))


def relaxing(t, stiffness, d, tau_s=4.0, share=0.3):
    """The model with a relaxing gel: each channel's history relaxes as the load's does; the rod
    cannot pull, so the load stays at or above zero when the gel lags a fast return."""
    f, fz, mx, my = [relaxed(t, c, tau_s, share) for c in model(stiffness, d)]
    return np.clip(f, 0.0, None), fz, mx, my


def relaxed(t, f, tau_s, share):
    """Quasi-linear viscoelasticity: the history f through G(t) = 1 - share (1 - exp(-t / tau))."""
    h, out = 0.0, np.empty_like(f)
    for i in range(len(f)):
        dt = t[i] - t[i - 1] if i else 0.0
        step = f[i] - f[i - 1] if i else f[0]
        h = h * np.exp(-dt / tau_s) + step * np.exp(-dt / (2 * tau_s))
        out[i] = (1 - share) * f[i] + share * h
    return out


def rod_path(rate_hz, peaks_mm=(9.0, 7.5)):
    """The standard test: 2 s at rest, in at 20 mm/min, 2 s hold, out at 600 mm/min, 40 s."""
    t, d, points = 0.0, -0.5, [(0.0, -0.5)]
    for peak in peaks_mm:
        for target, speed, wait in ((peak, 20 / 60, 2.0), (-0.5, 600 / 60, 40.0)):
            t += 2.0 if target == peak else 0.0
            points.append((t, d))
            t += abs(target - d) / speed
            d = target
            points.append((t, d))
            t += wait
    points.append((t, d))
    tp, dp = np.array(points).T
    ts = np.arange(0.0, tp[-1], 1.0 / rate_hz)
    return ts, np.interp(ts, tp, dp)


def write(path, meta, header, columns):
    lines = [f"# {k} = {v}" for k, v in meta.items()] + [",".join(header)]
    rows = np.column_stack(columns)
    lines += [",".join("" if np.isnan(v) else f"{v:.9g}" for v in row) for row in rows]
    with open(path, "w") as f:
        f.write("\n".join(lines) + "\n")


def test_file(path, rate_hz, t, d, columns, source):
    f, fz, mx, my = columns
    meta = {"format": "tactile-recording/1", "sample_rate_hz": rate_hz, **JIG, **FRONT,
            "source": source}
    write(path, meta, ["t_s", "rod_mm", "load_N", "fz_V", "mx_V", "my_V"], [t, d, f, fz, mx, my])


def main(out):
    os.makedirs(out, exist_ok=True)
    rng = np.random.default_rng(7)
    # The measurement: a gel 10 % stiffer that relaxes 30 % with tau = 4 s (the load and all it
    # presses on: each output's history relaxes as the load's does), offsets, noise.
    t, d = rod_path(500.0)
    f, fz, mx, my = relaxing(t, 1.1, d)
    noisy = [f + 0.01 + rng.normal(0, 0.02, len(t))]
    noisy += [v + o + rng.normal(0, 0.002, len(t)) for v, o in ((fz, 0.01), (mx, -0.005), (my, 0.002))]
    meta = {"format": "tactile-recording/1", "sample_rate_hz": 500, **JIG, **FRONT,
            "rod_speed_mm_per_min": 20, "source": "stand-in for a measurement"}
    write(os.path.join(out, "rec.csv"), meta, ["t_s", "rod_mm", "load_N", "fz_V", "mx_V", "my_V"],
          [t, d] + noisy)
    # The lab's model as a static response, a row every 0.1 mm.
    rows = np.arange(0.0, 9.3, 0.1)
    meta = {"format": "tactile-response/1", **JIG, "source": "lumped k1 d + k3 d^3"}
    write(os.path.join(out, "lumped-table.csv"), meta,
          ["rod_mm", "load_N", "fz_V", "mx_V", "my_V"], [rows, load(rows), *outputs(load(rows), rows)])
    # The same model in time at 200 Hz, its own clock starting at first contact.
    ts, ds = rod_path(200.0)
    start = np.argmax(ds > 0) - 1
    ts, ds = ts[start:] - ts[start], ds[start:]
    test_file(os.path.join(out, "lumped-test.csv"), 200, ts, ds, model(1.0, ds), "lumped, elastic")
    # ... and with the relaxation the lab then adds to its model.
    test_file(os.path.join(out, "lumped-qlv.csv"), 200, ts, ds, relaxing(ts, 1.0, ds),
              "lumped, QLV tau 4 s, 30 %")


if __name__ == "__main__":
    main(sys.argv[1] if len(sys.argv) > 1 else ".")
