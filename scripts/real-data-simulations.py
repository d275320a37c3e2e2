"""A lab's simulation of each real dev recording (shared/real-data/), as static responses for
`tactile diagnose --simulation` (docs/simulation-format.md): what the issue-42 report compares
with our own baseline. Numpy only.

    T=target/release/tactile; R=shared/real-data; D=real-sims; mkdir -p $D
    unzip -o $R/mach1/examples.zip        # Hayes_data.txt, Static_data.txt, Dynamic_data.txt
    $T import Hayes_data.txt --block 3 --radius-mm R -o $D/hayes1.csv  # --block 6 hayes2, 9 hayes3
    $T import Static_data.txt --radius-mm R -o $D/static.csv    # R: the indenter's radius, mm
    $T import Dynamic_data.txt --block 1 --radius-mm R -o $D/dynamic.csv
    $T import $R/ecoflex/EF10_0T_A1.csv --format csv --time-col 1 --disp-col 2 --force-col 3 \
        --skip-rows 7 --radius-mm 25 -o $D/EF10_0T_A1.csv  # and EF30_0T_A2, EF50_0T_A1
    # eflesh.csv: the eFlesh pair imported (docs/recording-format.md, importing a pair of logs)
    python3 scripts/real-data-simulations.py $D
    $T diagnose $D/hayes1.csv --simulation $D/hayes1-hertz.csv --json hayes1.json

Each simulation is a law a lab would fit: a Hertz law F = k d^1.5 to the first ramp (Mach-1),
a linear law F = F0 + k d to it (the tests that start under a preload), a neo-Hookean and a
one-term Ogden cylinder (EcoFlex, 50 x 30 mm), and for the magnetic skin the load cubic in the
travel with the skin quadratic in the load, both fitted on the first press.
"""

import os
import sys

import numpy as np


def read(path):
    meta, rows = {}, []
    with open(path) as f:
        for line in f:
            if line.startswith('#'):
                if '=' in line:
                    k, v = line[1:].split('=', 1); meta[k.strip()] = v.strip()
                continue
            if line.startswith('t_s'):
                header = line.strip().split(','); continue
            rows.append([float(x) if x.strip() else np.nan for x in line.strip().split(',')])
    a = np.array(rows)
    return meta, {h: a[:, i] for i, h in enumerate(header)}

def first_ramp(c):
    """Indices of the first loading ramp: from the start to the first peak of the travel."""
    d = c['rod_mm']
    top = np.argmax(d >= 0.999 * np.nanmax(d))
    return np.arange(0, top + 1)

def write(path, meta, source, rod, cols):
    with open(path, 'w') as f:
        f.write('# format = tactile-response/1\n')
        for k in ('contact_angle_deg', 'azimuth_deg', 'fingertip_radius_mm'):
            f.write(f'# {k} = {meta[k]}\n')
        f.write(f'# source = {source}\n')
        f.write('rod_mm,' + ','.join(cols) + '\n')
        for i in range(len(rod)):
            f.write(f'{rod[i]:.6g},' + ','.join(f'{cols[k][i]:.9g}' for k in cols) + '\n')

def grid(c):
    d = c['rod_mm']
    lo, hi = min(0.0, np.nanmin(d)), np.nanmax(d)
    return np.linspace(max(lo, np.nanmin(d)) if np.nanmin(d) > 0 else 0.0, hi * 1.01, 400)

def hertz(name):
    meta, c = read(name + '.csv')
    i = first_ramp(c)
    d, f = c['rod_mm'][i], c['load_N'][i]
    f0 = np.nanmedian(c['load_N'][c['rod_mm'] <= 0]) if np.any(c['rod_mm'] <= 0) else 0.0
    m = (d > 0) & np.isfinite(f)
    k = np.sum((f[m] - f0) * d[m] ** 1.5) / np.sum(d[m] ** 3)
    rod = grid(c)
    write(name + '-hertz.csv', meta, f'Hertz law F = {k:.4g} d^1.5 fitted to the first ramp', rod,
          {'load_N': k * np.clip(rod, 0, None) ** 1.5})

def linear(name):
    meta, c = read(name + '.csv')
    i = first_ramp(c)
    d, f = c['rod_mm'][i], c['load_N'][i]
    m = np.isfinite(f)
    A = np.column_stack([np.ones(m.sum()), d[m]])
    (f0, k), *_ = np.linalg.lstsq(A, f[m], rcond=None)
    rod = grid(c)
    write(name + '-linear.csv', meta, f'linear law F = {f0:.4g} + {k:.4g} d fitted to the first ramp', rod,
          {'load_N': f0 + k * rod})

def neo_hookean(name, height_mm=30.0, diameter_mm=50.0):
    meta, c = read(name + '.csv')
    d, f = c['rod_mm'], c['load_N']
    area = np.pi * diameter_mm ** 2 / 4
    shape = lambda d: area * ((1 - d / height_mm) ** -2 - (1 - d / height_mm))
    m = (d > 0) & np.isfinite(f)
    mu = np.sum(f[m] * shape(d[m])) / np.sum(shape(d[m]) ** 2)
    rod = np.linspace(0.0, np.nanmax(d) * 1.01, 400)
    write(name + '-neohookean.csv', meta, f'neo-Hookean cylinder 50 x 30 mm, mu = {mu*1e3:.4g} kPa fitted to the ramp', rod,
          {'load_N': mu * shape(rod)})

def eflesh(name='eflesh'):
    meta, c = read(name + '.csv')
    t, d, f, b = c['t_s'], c['rod_mm'], c['load_N'], c['fz_V']
    # One press: from the start to the first return to rest after the first peak.
    top = np.nanargmax(np.where(t < 40, d, -np.inf))
    press = np.arange(0, top + 1)
    m = np.isfinite(f[press]) & (d[press] > 0)
    dd, ff = d[press][m], f[press][m]
    law = np.polyfit(dd, ff, 3)                       # load against the travel, cubic
    resp = np.polyfit(f[press][np.isfinite(f[press])], b[press][np.isfinite(f[press])], 2)  # the skin against the load
    rod = np.linspace(0.0, np.nanmax(d) * 1.01, 400)
    load = np.clip(np.polyval(law, rod), 0, None)
    write(name + '-response.csv', meta, 'load cubic in the travel and skin quadratic in the load, fitted on the first press', rod,
          {'load_N': load, 'fz_V': np.polyval(resp, load) - np.polyval(resp, 0.0)})


def ogden(name, height_mm=30.0, diameter_mm=50.0):
    meta, c = read(name + '.csv')
    d, f = c['rod_mm'], c['load_N']
    area = np.pi * diameter_mm ** 2 / 4
    m = (d > 0) & np.isfinite(f)
    def shape(d, a):
        lam = 1 - d / height_mm
        return -area * (2 / a) * (lam ** (a - 1) - lam ** (-a / 2 - 1))
    best = None
    for a in np.linspace(-10, 10, 401):
        if abs(a) < 1e-6: continue
        s = shape(d[m], a)
        mu = np.sum(f[m] * s) / np.sum(s * s)
        r = np.sum((f[m] - mu * s) ** 2)
        if best is None or r < best[0]: best = (r, a, mu)
    _, a, mu = best
    rod = np.linspace(0.0, np.nanmax(d) * 1.01, 400)
    write(name + '-ogden.csv', meta, f'one-term Ogden cylinder 50 x 30 mm, mu = {mu*1e3:.4g} kPa, alpha = {a:.3g}, fitted to the ramp', rod,
          {'load_N': mu * shape(rod, a)})

def main(folder):
    os.chdir(folder)
    for n in ('hayes1', 'hayes2', 'hayes3'):
        hertz(n)
    for n in ('static', 'dynamic'):
        linear(n)
        hertz(n)
    for n in ('EF10_0T_A1', 'EF30_0T_A2', 'EF50_0T_A1'):
        neo_hookean(n)
        ogden(n)
    if os.path.exists('eflesh.csv'):
        eflesh()


if __name__ == '__main__':
    main(sys.argv[1] if len(sys.argv) > 1 else '.')
