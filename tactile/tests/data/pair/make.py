#!/usr/bin/env python3
"""Write the small synthetic pair of logs the import test reads (sensor.csv, states.csv).

Shaped like the eFlesh pair (/work/shared/real-data/eflesh/, see docs/recording-format.md):
headerless, Unix time in s first, both logs stamped by one host loop; a robot's z over the
sample (down presses in, contact at 287.0 mm) and a scale in grams that reads every other loop
and writes -1 on the others; a sensor of two 3-axis magnetometers in uT. The truth is closed
form so the test can check the import against it: load_N = 2.5 * max(0, 287.0 - z)^1.5, and
Bz1 and Bz2 move by -40 and +60 uT per N (so "-4+7" gives 100 uT per N over its rest value).
Run it again to regenerate the files; they are committed, so the test needs no Python.
"""
import math

T0 = 1_700_000_000.0
GF_PER_N = 1000 / 9.80665


def z_mm(t):
    """Two presses of 1.5 mm past contact, 10 s each, after 2 s at rest."""
    if t < 2.0:
        return 288.0
    return 288.0 - 2.5 * math.sin(math.pi * ((t - 2.0) % 10.0) / 10.0) ** 2


def load_n(t):
    return 2.5 * max(0.0, 287.0 - z_mm(t)) ** 1.5


def main():
    sensor, states = [], []
    t, i = 0.0, 0
    while t <= 22.0:
        ts = T0 + t
        f = load_n(t)
        b = [120.0, -35.0, 9400.0 - 40.0 * f, 1640.0, -260.0, 11390.0 + 60.0 * f]
        sensor.append(f"{ts:.6f}," + ",".join(f"{v:.4f}" for v in b))
        w = f"{f * GF_PER_N:.2f}" if i % 2 == 0 else "-1"
        states.append(f"{ts + 0.0014:.6f},315.0,-100.0,{z_mm(t):.6f},{w}")
        # The loop alternates 0.134 s (waiting for the scale) and 0.070 s.
        t += 0.134 if i % 2 == 0 else 0.070
        i += 1
    open("sensor.csv", "w").write("\n".join(sensor) + "\n")
    open("states.csv", "w").write("\n".join(states) + "\n")


main()
