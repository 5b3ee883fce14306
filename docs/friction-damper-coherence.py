#!/usr/bin/env python3
"""A prototype outside the product (docs/friction-damper.md, "The fast oscillation is in the displacement too"):
is the force's fast oscillation (5-80 Hz, peak 14 Hz on the 2 Hz sinusoid) something the measured displacement
predicts? Prints, per file, the magnitude-squared coherence between x_in and F_kip in four bands (Welch, 1 s Hann
windows, half overlap; each band's value weighted by the force's power), and the transfer function x -> F at a few
frequencies (gain in kip/in, phase); then, on the 30 lb files, a one-stop model (the friction-gap operator of
half-width 0.16 in, G on 21 hat functions, parallel stiffness and constant, least squares with ridge 1e-3) with
and without a parallel FIR on the displacement's velocity (lags -40..80 samples), trained on the three 30 lb
training files of docs/friction-damper.sh and scored on the 2 Hz file, and, as a bound, on the 2 Hz file itself.
Needs numpy (Debian: python3-numpy). Run from anywhere:
    python3 docs/friction-damper-coherence.py
"""
import csv
import os

import numpy as np

DATA = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "tests", "data", "friction_damper")
FS, WINDOW, NODES, RIDGE, R = 1024, 1024, 21, 1e-3, 0.16
TRAIN = ["char_0.25Hz30lbtension1amplitude.csv", "char_0.5Hz30lbtension0.5amplitude.csv",
         "char_1Hz30lbtension1.5amplitude.csv"]
TWO_HZ = "char_2Hz30lbtension0.5amplitude.csv"
LAGS = range(-40, 81)


def load(name):
    with open(os.path.join(DATA, name), newline="") as f:
        rows = list(csv.DictReader(f))
    return np.array([float(r["x_in"]) for r in rows]), np.array([float(r["F_kip"]) for r in rows])


def welch(a, b):
    w = np.hanning(WINDOW)
    sab, saa, sbb = 0, 0, 0
    for i in range(0, len(a) - WINDOW, WINDOW // 2):
        fa = np.fft.rfft(w * (a[i:i + WINDOW] - a[i:i + WINDOW].mean()))
        fb = np.fft.rfft(w * (b[i:i + WINDOW] - b[i:i + WINDOW].mean()))
        sab, saa, sbb = sab + fa.conj() * fb, saa + abs(fa) ** 2, sbb + abs(fb) ** 2
    return sab, saa, sbb


def stop(v, a):
    e, z = np.empty_like(v), v[0] - a * R
    for t, x in enumerate(v):
        z = x - R if x - z > R else x + R if x - z < -R else z
        e[t] = x - z
    return e


def design(v, a, fir):
    nodes = np.linspace(-R, R, NODES)
    columns = [np.clip(1 - np.abs(stop(v, a)[:, None] - nodes[None, :]) / (nodes[1] - nodes[0]), 0, None),
               v[:, None], np.ones((len(v), 1))]
    if fir:
        speed = np.gradient(v) * FS / 10
        columns.append(np.array([np.concatenate([np.full(j, speed[0]), speed[:len(v) - j]]) if j >= 0 else
                                 np.concatenate([speed[-j:], np.full(-j, speed[-1])]) for j in LAGS]).T)
    return np.hstack(columns)


def fit(files, fir):
    x = np.vstack([design(load(f)[0], 0.0, fir) for f in files])
    y = np.concatenate([load(f)[1] for f in files])
    return np.linalg.solve(x.T @ x + RIDGE * np.eye(x.shape[1]), x.T @ y)


def score(name, theta, fir):
    v, force = load(name)
    starts = np.linspace(-1, 1, 41)
    first = [abs((design(v[:200], a, fir) @ theta)[0] - force[0]) + 1e-6 * abs(a) for a in starts]
    simulated = design(v, starts[int(np.argmin(first))], fir) @ theta
    return 100 * (1 - np.linalg.norm(force - simulated) / np.linalg.norm(force - force.mean()))


print("file | coherence x-F in 5-10, 10-20, 20-40, 40-80 Hz | x -> F at 8, 14, 30, 60 Hz: gain kip/in (phase deg)")
for name in sorted(f for f in os.listdir(DATA) if f.endswith(".csv")):
    x, force = load(name)
    sxf, sxx, sff = welch(x, force)
    freq = np.fft.rfftfreq(WINDOW, 1 / FS)
    coherence = abs(sxf) ** 2 / (sxx * sff)
    bands = [(freq >= lo) & (freq < hi) for lo, hi in ((5, 10), (10, 20), (20, 40), (40, 80))]
    weighted = [(coherence[b] * sff[b]).sum() / sff[b].sum() for b in bands]
    transfer = [sxf[k] / sxx[k] for k in (8, 14, 30, 60)]  # 1 Hz bins
    print(f"{name} | " + ", ".join(f"{c:.2f}" for c in weighted) + " | " +
          ", ".join(f"{abs(h):.0f} ({np.degrees(np.angle(h)):+.0f})" for h in transfer), flush=True)
for fir in (False, True):
    label = "one stop + FIR on the speed" if fir else "one stop"
    print(f"{label}: 2 Hz file trained on the three 30 lb training files {score(TWO_HZ, fit(TRAIN, fir), fir):.1f} %, "
          f"trained on itself (a bound) {score(TWO_HZ, fit([TWO_HZ], fir), fir):.1f} %", flush=True)
