#!/usr/bin/env python3
"""A prototype outside the product (docs/friction-damper.md, "Trained on an earthquake record"): is the earthquake
records' miss a matter of richer rate-independent hysteresis? The force is modelled as a sum of nonlinear functions
of stop operators (the friction-gap operator's relative displacement e = v - z, one per play half-width r_i) plus a
parallel stiffness and a constant,

    F = sum_i G_i(e_i) + k v + c,    e_i = stop_{r_i}(v),

with each G_i on 21 hat functions over [-r_i, r_i], fitted by (ridge 1e-3) least squares. One stop of half-width
0.18 in is the friction-gap operator of the 36 lb files (G fitted by least squares here, by per-bin medians in
lashid). Each stop starts at the same fraction a of its play, a on 41 values in [-1, 1] chosen to match the file's
first force sample (nearest a = 0): the only use of a test file's force, as in lashid. Prints, per set of
half-widths, the fit of the Kocaeli and Imperial Valley DBE records (36 lb) when trained on the three 36 lb
training sines; with the other earthquake's MCE record added to the training files; and in-sample (trained on the
record itself: a bound on the model class, not a score). Needs numpy (Debian: python3-numpy). Run from anywhere:
    python3 docs/friction-damper-multistop.py
"""
import csv
import os

import numpy as np

DATA = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "tests", "data", "friction_damper")
RIDGE = 1e-3
NODES = 21


def load(name):
    with open(os.path.join(DATA, name), newline="") as f:
        rows = list(csv.DictReader(f))
    return np.array([float(r["x_in"]) for r in rows]), np.array([float(r["F_kip"]) for r in rows])


def stop(v, r, a):
    """The stop operator's output e = v - z of a play of half-width r, starting at e = a r."""
    e = np.empty_like(v)
    z = v[0] - a * r
    for t, x in enumerate(v):
        if x - z > r:
            z = x - r
        elif x - z < -r:
            z = x + r
        e[t] = x - z
    return e


def design(v, widths, a):
    columns = []
    for r in widths:
        nodes = np.linspace(-r, r, NODES)
        h = nodes[1] - nodes[0]
        columns.append(np.clip(1 - np.abs(stop(v, r, a)[:, None] - nodes[None, :]) / h, 0, None))
    return np.hstack(columns + [v[:, None], np.ones((len(v), 1))])


def fit(files, widths):
    records = [load(f) for f in files]
    x = np.vstack([design(v, widths, 0.0) for v, _ in records])
    y = np.concatenate([force for _, force in records])
    return np.linalg.solve(x.T @ x + RIDGE * np.eye(x.shape[1]), x.T @ y)


def score(name, theta, widths):
    v, force = load(name)
    starts = np.linspace(-1, 1, 41)
    first = [abs((design(v[:1], widths, a) @ theta)[0] - force[0]) + 1e-6 * abs(a) for a in starts]
    simulated = design(v, widths, starts[int(np.argmin(first))]) @ theta
    return 100 * (1 - np.linalg.norm(force - simulated) / np.linalg.norm(force - force.mean()))


SINES_36 = ["char_0.25Hz36lbtension1amplitude.csv", "char_0.5Hz36lbtension0.5amplitude.csv",
            "char_1Hz36lbtension1.5amplitude.csv"]
KOCAELI, IMPERIAL = "eq_KocaeliDBE.csv", "eq_ImperialValleyDBE.csv"
WIDTHS = {"1 stop (0.18)": [0.18], "2 stops": [0.05, 0.18], "4 stops": [0.02, 0.05, 0.1, 0.18],
          "6 stops": [0.01, 0.02, 0.05, 0.1, 0.18, 0.3]}

print("stops | trained on the 36 lb sines: Kocaeli, Imperial Valley | + Imperial Valley MCE: Kocaeli "
      "| + Kocaeli MCE: Imperial Valley | in-sample: Kocaeli, Imperial Valley")
for label, widths in WIDTHS.items():
    sines = fit(SINES_36, widths)
    with_im = fit(SINES_36 + ["eq_ImperialValleyMCE.csv"], widths)
    with_km = fit(SINES_36 + ["eq_KocaeliMCE.csv"], widths)
    own_k, own_i = fit([KOCAELI], widths), fit([IMPERIAL], widths)
    print(f"{label} | {score(KOCAELI, sines, widths):.1f} %, {score(IMPERIAL, sines, widths):.1f} % "
          f"| {score(KOCAELI, with_im, widths):.1f} % | {score(IMPERIAL, with_km, widths):.1f} % "
          f"| {score(KOCAELI, own_k, widths):.1f} %, {score(IMPERIAL, own_i, widths):.1f} %", flush=True)
