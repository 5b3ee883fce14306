#!/usr/bin/env python3
# Independent generator of `lashid` recordings with hidden effects, for measuring how `lashid diagnose`
# generalises. Written from the paper (Giri et al., sections 2-4), docs/data-format.md, the estimator's pulse
# schedule (estimator/include/lashid/estimator/design.hpp) and the cause table of docs/diagnose.md, WITHOUT
# reading the project's own generator (host_sim/sim/src/hidden_effect.cpp, host_sim/plant/) or its description.
# Pure Python 3, standard library only.
#
#   python3 generate.py --cause input_lag+sensor_drift --seed 3 --out rec.csv --config-out cfg.json \
#       --truth-out truth.json [--n 2|random] [--m 6|random]
#
# Plant, one continuous run over step_d, dis, step_a, ais, val (back to back, from rest):
#   v -> [input lag (1-lambda)/(1-lambda q^-1)] -> [dead time q^-d] -> switch/backlash -> u
#   A(q^-1) y = B(q^-1) u + xi (white),  measured y_m = y + sensor noise + D tau/(N-1)
import argparse
import json
import math
import random
import sys

import plant

CAUSES = ["none", "input_lag", "dead_time", "sensor_drift", "colored_noise", "operator_type"]
PAIRS = ["input_lag+sensor_drift", "dead_time+colored_noise", "dead_time+operator_type",
         "sensor_drift+colored_noise"]


def parse_causes(text):
    if text not in CAUSES and text not in PAIRS:
        raise SystemExit(f"generate.py: unknown cause '{text}' (one of {', '.join(CAUSES + PAIRS)})")
    return [] if text == "none" else text.split("+")


# ---------------------------------------------------------------- design: interval, levels, lengths


def draw_design(rng, n, m):
    v_min = round(rng.uniform(-5.0, 3.0), 2)
    v_max = round(v_min + rng.uniform(1.0, 12.0), 2)
    width = v_max - v_min

    def levels(start, sign):
        top = rng.uniform(0.6, 0.88) * width        # the last level stays clear of the other extreme
        gaps = [rng.uniform(0.5, 1.5) for _ in range(m - 1)]
        out, acc = [start], 0.0
        for g in gaps:
            acc += g / sum(gaps) * top
            out.append(round(start + sign * acc, 4))
        return out

    step_length = rng.randint(800, 2000)
    return {"n": n, "m": m, "v_min": v_min, "v_max": v_max,
            "V_d": levels(v_min, +1), "V_a": levels(v_max, -1),
            "step_length": step_length,
            "pulse_length_d": rng.randint(4500, 5500), "pulse_length_a": rng.randint(4500, 5500),
            "val_length": rng.randint(2500, 3500)}


def pulse_sequence(n, m, levels, held, length):
    """(3.1)/(4.2) with the estimator's schedule: s = max(n, 2), T = s(m+3), tau_1 = 2s, tau_j = (2+j)s."""
    s = max(n, 2)
    period = s * (m + 3)
    at = {2 * s: levels[0]}
    for j in range(2, m + 1):
        at[(2 + j) * s] = levels[j - 1]
    return [at.get(t % period, held) for t in range(length)]


def validation_input(rng, d, length):
    """Own design: random holds at random amplitudes, jumps between configured levels, ramps, small
    reversals (where a switch and a backlash differ) and slow sine sweeps, back to back."""
    lo, hi = d["v_min"], d["v_max"]
    w = hi - lo
    clip = lambda x: min(hi, max(lo, x))
    levels = sorted(set(d["V_d"] + d["V_a"]))
    out, cur = [], lo  # the ais phase ends held at v_min
    while len(out) < length:
        kind = rng.choices(["hold", "level", "ramp", "reversals", "sine"], [0.3, 0.15, 0.2, 0.2, 0.15])[0]
        if kind == "hold":
            cur = rng.uniform(lo, hi)
            out += [cur] * rng.randint(8, 120)
        elif kind == "level":
            cur = rng.choice(levels)
            out += [cur] * rng.randint(10, 60)
        elif kind == "ramp":
            target, k = rng.uniform(lo, hi), rng.randint(20, 200)
            out += [cur + (target - cur) * (i + 1) / k for i in range(k)]
            cur = target
            out += [cur] * rng.randint(0, 30)
        elif kind == "reversals":
            amp = rng.uniform(0.02, 0.10) * w
            sign = 1 if cur + amp <= hi else -1
            for _ in range(rng.randint(2, 5)):
                out += [clip(cur + sign * amp)] * rng.randint(5, 30)
                out += [cur] * rng.randint(5, 30)
        else:
            center, amp = rng.uniform(lo, hi), rng.uniform(0.1, 0.5) * w
            per, cycles = rng.randint(40, 300), rng.uniform(1.0, 2.0)
            seg = [clip(center + amp * math.sin(2 * math.pi * i / per)) for i in range(int(per * cycles))]
            out += seg
            cur = seg[-1]
    return out[:length]


# ---------------------------------------------------------------- effects and noise


def draw_effects(rng, causes):
    eff = {}
    if "input_lag" in causes:
        eff["lambda"] = rng.uniform(0.15, 0.5)
    if "dead_time" in causes:
        eff["delay"] = rng.randint(1, 3)
    if "sensor_drift" in causes:
        eff["drift_ratio"] = rng.choice([-1, 1]) * rng.uniform(0.3, 0.6)  # of the output's std
    if "colored_noise" in causes:
        eff["snr_db"] = rng.uniform(20.0, 30.0)
        eff["noise_kind"] = "white" if rng.random() < 0.3 else "lowpass2"
        eff["noise_poles"] = [rng.uniform(0.3, 0.85), rng.uniform(0.3, 0.85)] if eff["noise_kind"] != "white" else []
    return eff


def sensor_noise(rng, std, poles, length):
    """White (no poles) or second-order low-pass 1/((1-p1 q^-1)(1-p2 q^-1)) noise of stationary std `std`."""
    den = plant.poly_from_roots(poles) if poles else [1.0]
    gain = math.sqrt(plant.impulse_energy([1.0], den))
    burn = 300
    w = [rng.gauss(0.0, std / gain) for _ in range(length + burn)]
    e = []
    for t in range(len(w)):
        s = w[t] - sum(den[i] * e[t - i] for i in range(1, len(den)) if t - i >= 0)
        e.append(s)
    return e[burn:]


def actuator(op_kind, borders, v, lam, delay, v_min):
    """v -> input lag -> dead time -> operator: one continuous run from rest at v_min, the operator on
    (v_min, C_d(v_min)), the lag filter at v_min and the delay line full of v_min."""
    op = plant.make_operator(op_kind, borders, v_min, borders.cd(v_min))
    lagged, line, u = v_min, [v_min] * delay, []
    for x in v:
        lagged = x + lam * (lagged - x)  # (1-lam)/(1-lam q^-1), written so it approaches x monotonically
        line.append(lagged)
        u.append(op.step(line.pop(0)))
    return u


def pwl(xs, ys):
    """Piecewise-linear interpolation through (xs, ys), xs increasing, constant outside."""
    def f(x):
        if x <= xs[0]:
            return ys[0]
        for i in range(len(xs) - 1):
            if x <= xs[i + 1]:
                return ys[i] + (ys[i + 1] - ys[i]) * (x - xs[i]) / (xs[i + 1] - xs[i])
        return ys[-1]
    return f


def std(x):
    mu = sum(x) / len(x)
    return math.sqrt(sum((v - mu) ** 2 for v in x) / len(x))


# ---------------------------------------------------------------- the recording


def generate(cause_text, seed, n_arg, m_arg, quiet=False):
    causes = parse_causes(cause_text)
    rng = random.Random(f"independent-lashid-{seed}")
    n = rng.randint(1, 3) if n_arg == "random" else int(n_arg)
    m = rng.randint(3, 6) if m_arg == "random" else int(m_arg)
    if not (1 <= n <= 3 and 3 <= m <= 6):
        raise SystemExit("generate.py: n must lie in 1..3 and m in 3..6")
    d = draw_design(rng, n, m)
    a, b, poles = plant.draw_linear(rng, n)
    op_kind = rng.choice(["switch", "backlash"])
    borders, border_desc = plant.draw_borders(rng, op_kind, d["v_min"], d["v_max"])
    eff = draw_effects(rng, causes)

    L = d["step_length"]
    phases = [("step_d", [d["v_min"]] + [d["v_max"]] * L),
              ("dis", pulse_sequence(n, m, d["V_d"], d["v_max"], d["pulse_length_d"])),
              ("step_a", [d["v_max"]] + [d["v_min"]] * L),
              ("ais", pulse_sequence(n, m, d["V_a"], d["v_min"], d["pulse_length_a"])),
              ("val", validation_input(rng, d, d["val_length"]))]
    v = [x for _, seq in phases for x in seq]
    total = len(v)

    lam, delay = eff.get("lambda", 0.0), eff.get("delay", 0)
    u = actuator(op_kind, borders, v, lam, delay, d["v_min"])
    y_clean = plant.filter_ab(b, a, u)
    y_range, y_std = max(y_clean) - min(y_clean), std(y_clean)
    # white equation error xi: its effect xi/A on y has std eq_frac * (output range)
    eq_frac = rng.uniform(0.003, 0.01) * (1e-6 if quiet else 1.0)  # --quiet: a nearly noise-free check
    xi_std = eq_frac * y_range / math.sqrt(plant.impulse_energy([1.0], [1.0] + a))
    xi = [rng.gauss(0.0, xi_std) for _ in range(total)]
    eq = []  # A(q^-1) eq(t) = xi(t)
    for t in range(total):
        eq.append(xi[t] - sum(a[i - 1] * eq[t - i] for i in range(1, n + 1) if t - i >= 0))
    y = [yc + en for yc, en in zip(y_clean, eq)]
    drift_total = eff.get("drift_ratio", 0.0) * y_std
    drift = [drift_total * t / (total - 1) for t in range(total)]
    if "colored_noise" in causes:
        noise_std = y_std / 10 ** (eff["snr_db"] / 20.0)
        e = sensor_noise(rng, noise_std, eff["noise_poles"], total)
        # analysis only (no draw): how coloured the sensor noise looks in the equation error, A(q^-1) e:
        # 1 - 1/sum(h^2) of A/D; near 0 it is white, i.e. indistinguishable from the ARX equation error
        den = plant.poly_from_roots(eff["noise_poles"]) if eff["noise_poles"] else [1.0]
        eff["colour_through_A"] = 1.0 - 1.0 / plant.impulse_energy([1.0] + a, den)
    else:
        noise_std, e = 0.0, [0.0] * total
    y_meas = [yy + dr + ee for yy, dr, ee in zip(y, drift, e)]

    cfg_op = ({"switch": "backlash", "backlash": "switch"}[op_kind] if "operator_type" in causes else op_kind)
    config = dict(d, operator=cfg_op)

    # true border values the schemes see: F^d(V_j^d) from the held (v_M, u_M), F^a(V_j^a) from (v_m, u_m)
    def seen(levels, held, start_u):
        out = []
        for lv in levels:
            o = plant.make_operator(op_kind, borders, held, start_u)
            out.append(o.step(lv))
        return out
    u_M, u_m = borders.ca(d["v_max"]), borders.cd(d["v_min"])
    val_start = total - d["val_length"]
    params = {}
    if "input_lag" in causes:
        params["lambda"] = lam
    if "dead_time" in causes:
        params["delay"] = delay
    if "sensor_drift" in causes:
        params["drift_total"] = drift_total
    if "operator_type" in causes:
        params["operator"] = op_kind
    truth = {
        "generator": "tests/independent/generate.py", "seed": seed, "cause_text": cause_text,
        "causes": causes or ["none"], "parameters": params, "n": n, "m": m,
        "plant": {"a": a, "b": b, "poles": poles, "operator": op_kind, "config_operator": cfg_op,
                  "borders": border_desc,
                  "border_table": {"v": [d["v_min"] + (d["v_max"] - d["v_min"]) * i / 40 for i in range(41)]},
                  "u_M": u_M, "u_m": u_m,
                  "F_d_true": seen(d["V_d"], d["v_max"], u_M), "F_a_true": seen(d["V_a"], d["v_min"], u_m)},
        "effects": eff, "equation_error": {"frac_of_range": eq_frac, "xi_std": xi_std},
        "sensor_noise_std": noise_std, "output_range": y_range, "output_std": y_std, "total_samples": total,
        "val_noise_free": [yc + dr for yc, dr in zip(y_clean[val_start:], drift[val_start:])],
    }
    # ceiling of an m-point border model: the true plant and effects, but borders linear between the true points
    # at the configured levels (and (v_M, u_M), (v_m, u_m)), as an identified model can represent them at best
    f_d, f_a = truth["plant"]["F_d_true"], truth["plant"]["F_a_true"]
    cd_pwl = pwl(d["V_d"] + [d["v_max"]], f_d + [u_M])
    ca_pwl = pwl([d["v_min"]] + d["V_a"][::-1], [u_m] + f_a[::-1])
    pwl_borders = plant.Borders(ca_pwl, cd_pwl, d["v_min"], d["v_max"])
    y_pwl = plant.filter_ab(b, a, actuator(op_kind, pwl_borders, v, lam, delay, d["v_min"]))
    truth["val_pwl_noise_free"] = [yp + dr for yp, dr in zip(y_pwl[val_start:], drift[val_start:])]
    tab = truth["plant"]["border_table"]
    tab["ascending"] = [borders.ca(x) for x in tab["v"]]
    tab["descending"] = [borders.cd(x) for x in tab["v"]]

    rows, k = [], 0
    for name, seq in phases:
        for t in range(len(seq)):
            rows.append(f"{name},{t},{fmt(v[k])},{fmt(y_meas[k])}")
            k += 1
    return config, truth, rows


def fmt(x):
    s = repr(float(x))
    return "0" if s in ("0.0", "-0.0") else s  # repr gives the shortest round-trip form; no 'nan', no '+'


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__)
    ap.add_argument("--cause", required=True)
    ap.add_argument("--seed", type=int, required=True)
    ap.add_argument("--out", required=True)
    ap.add_argument("--config-out", required=True)
    ap.add_argument("--truth-out", required=True)
    ap.add_argument("--n", default="2")
    ap.add_argument("--m", default="6")
    ap.add_argument("--quiet", action="store_true", help="equation error 1e-6 of its size (identify check)")
    args = ap.parse_args(argv)
    config, truth, rows = generate(args.cause, args.seed, args.n, args.m, args.quiet)
    with open(args.out, "w") as f:
        f.write(f"# tests/independent/generate.py, cause {args.cause}, seed {args.seed}\nphase,t,v,y\n")
        f.write("\n".join(rows) + "\n")
    with open(args.config_out, "w") as f:
        json.dump(config, f, indent=2)
        f.write("\n")
    with open(args.truth_out, "w") as f:
        json.dump(truth, f, indent=1)
        f.write("\n")


if __name__ == "__main__":
    sys.exit(main())
