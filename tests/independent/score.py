#!/usr/bin/env python3
# Scoring harness: generates recordings with tests/independent/generate.py (written WITHOUT reading the project's
# own generator), runs `lashid diagnose` on each and scores it as the issue defines a hit: the JSON's "causes"
# equal the hidden set exactly (["none"] when none is hidden, compared as sets) and the parameters are right where
# present (lambda within 0.05, delay exact, drift_total within 20 % of the true D, operator exact). Also records
# fit_extended against the fit of the true plant's noise-free val output ("fit rule": fit_extended >= true - 3).
# Pure Python 3, standard library only.
#
#   python3 score.py --lashid BIN --seeds 25 --first-seed 1 --workdir DIR [--causes a,b] [--pairs]
#                    [--n 2|random] [--m 6|random] [--jobs 1|2] [--json OUT] [--keep-all]
import argparse
import concurrent.futures
import json
import math
import os
import subprocess
import sys
import threading
import time

HERE = os.path.dirname(os.path.abspath(__file__))
SINGLES = ["none", "input_lag", "dead_time", "sensor_drift", "colored_noise", "operator_type"]
PAIRS = ["input_lag+sensor_drift", "dead_time+colored_noise", "dead_time+operator_type",
         "sensor_drift+colored_noise"]


def require_executable(path, program):
    """Exit with a one-line error (no traceback) unless `path` is an executable file."""
    if not (os.path.isfile(path) and os.access(path, os.X_OK)):
        sys.exit(f"{program}: --lashid {path}: not an executable file")


def read_val_y(path):
    ys = []
    with open(path) as f:
        for line in f:
            if line.startswith("val,"):
                ys.append(float(line.rstrip("\n").split(",")[3]))
    return ys


def fit_percent(y, y_sim):
    mu = sum(y) / len(y)
    num = math.sqrt(sum((a - b) ** 2 for a, b in zip(y, y_sim)))
    den = math.sqrt(sum((a - mu) ** 2 for a in y))
    return 100.0 * (1.0 - num / den)


def param_checks(true_params, found_params):
    """{name: True/False} for every true parameter the diagnosis reports; a missing one is left out."""
    out = {}
    for name, tv in true_params.items():
        if name not in found_params:
            continue
        fv = found_params[name]
        if name == "lambda":
            out[name] = abs(fv - tv) <= 0.05
        elif name == "delay":
            out[name] = fv == tv
        elif name == "drift_total":
            out[name] = abs(fv - tv) <= 0.2 * abs(tv)
        elif name == "operator":
            out[name] = fv == tv
    return out


def run_one(args, cause, seed):
    base = os.path.join(args.workdir, f"{cause}_s{seed}")
    rec, cfg, tru, out = base + ".csv", base + ".cfg.json", base + ".truth.json", base + ".diag.json"
    gen = subprocess.run([sys.executable, os.path.join(HERE, "generate.py"), "--cause", cause, "--seed",
                          str(seed), "--out", rec, "--config-out", cfg, "--truth-out", tru,
                          "--n", args.n, "--m", args.m], capture_output=True, text=True)
    if gen.returncode != 0:
        raise RuntimeError(f"generate.py failed for {cause} seed {seed}: {gen.stderr}")
    truth = json.load(open(tru))
    t0 = time.monotonic()
    diag = subprocess.run([args.lashid, "diagnose", "--config", cfg, "--data", rec, "--json", out],
                          capture_output=True, text=True)
    seconds = time.monotonic() - t0
    r = {"cause": cause, "seed": seed, "n": truth["n"], "m": truth["m"],
         "operator": truth["plant"]["operator"], "config_operator": truth["plant"]["config_operator"],
         "border_mode": truth["plant"]["borders"]["mode"].split(":")[0],
         "hidden": sorted(truth["causes"]), "true_parameters": truth["parameters"],
         "effects": truth["effects"], "seconds": seconds, "exit_code": diag.returncode}
    y_val = read_val_y(rec)
    r["fit_true"] = fit_percent(y_val, truth["val_noise_free"])
    r["fit_pwl"] = fit_percent(y_val, truth["val_pwl_noise_free"])
    if diag.returncode != 0 or not os.path.exists(out):
        r.update(error=(diag.stderr or diag.stdout).strip()[-400:], found=[], strongest=None,
                 found_parameters={}, causes_right=False, params_ok={}, hit=False,
                 fit_extended=None, fit_nominal=None, fit_rule=False, fit_rule_pwl=False)
        return r
    d = json.load(open(out))
    found = sorted(d.get("causes", []))
    checks = param_checks(truth["parameters"], d.get("parameters", {}))
    r.update(found=found, strongest=d.get("cause"), found_parameters=d.get("parameters", {}),
             causes_right=set(found) == set(truth["causes"]), params_ok=checks,
             fit_extended=d.get("fit_extended"), fit_nominal=d.get("fit_nominal"))
    r["params_right"] = all(checks.values())
    r["hit"] = r["causes_right"] and r["params_right"]
    r["fit_rule"] = r["fit_extended"] is not None and r["fit_extended"] >= r["fit_true"] - 3.0
    r["fit_rule_pwl"] = r["fit_extended"] is not None and r["fit_extended"] >= r["fit_pwl"] - 3.0
    if r["hit"] and not args.keep_all:
        for p in (rec, out):
            os.remove(p)
    return r


def table(rows_by_cause, causes):
    labels = sorted({r["strongest"] or "error" for rs in rows_by_cause.values() for r in rs})
    head = (f"{'hidden':28s} {'hits':>8s} {'causes':>8s} {'params':>8s} {'fitrule':>8s} {'fit_pwl':>8s}"
            f"   strongest found 'cause'")
    lines = [head, "-" * len(head)]
    for c in causes:
        rs = rows_by_cause.get(c, [])
        if not rs:
            continue
        k = len(rs)
        hits = sum(r["hit"] for r in rs)
        cr = sum(r["causes_right"] for r in rs)
        with_params = [r for r in rs if r["causes_right"] and r["params_ok"]]
        pr = sum(all(r["params_ok"].values()) for r in with_params)
        fr = sum(r["fit_rule"] for r in rs)
        fp = sum(r["fit_rule_pwl"] for r in rs)
        conf = {}
        for r in rs:
            key = r["strongest"] or "error"
            conf[key] = conf.get(key, 0) + 1
        conf_s = ", ".join(f"{lab} {conf[lab]}" for lab in labels if lab in conf)
        pr_s = f"{pr}/{len(with_params)}" if with_params else "-"
        lines.append(f"{c:28s} {hits:>3d}/{k:<4d} {cr:>3d}/{k:<4d} {pr_s:>8s} {fr:>3d}/{k:<4d} {fp:>3d}/{k:<4d}   {conf_s}")
    return "\n".join(lines)


def fmt_params(p):
    return "{" + ", ".join(f"{k}: {v:.3g}" if isinstance(v, float) else f"{k}: {v}" for k, v in sorted(p.items())
                           if k != "estimator") + "}"


def miss_line(r):
    fe = "n/a" if r["fit_extended"] is None else f"{r['fit_extended']:.1f}"
    extra = f" ERROR: {r['error']}" if r.get("error") else ""
    return (f"{r['cause']:26s} seed {r['seed']:3d} n={r['n']} m={r['m']} {r['operator']:8s} "
            f"({r['border_mode']}) found {'+'.join(r['found']) or '-'} params {fmt_params(r['found_parameters'])}"
            f" vs true {fmt_params(r['true_parameters'])} fit_ext {fe} fit_true {r['fit_true']:.1f}"
            f" fit_pwl {r['fit_pwl']:.1f}"
            f" {r['seconds']:.2f}s{extra}")


def main():
    ap = argparse.ArgumentParser(description="Score lashid diagnose on independently generated recordings")
    ap.add_argument("--lashid", required=True)
    ap.add_argument("--causes", default="", help="comma-separated; default the six singles, or the pairs")
    ap.add_argument("--pairs", action="store_true")
    ap.add_argument("--seeds", type=int, required=True)
    ap.add_argument("--first-seed", type=int, default=1)
    ap.add_argument("--workdir", required=True)
    ap.add_argument("--n", default="2")
    ap.add_argument("--m", default="6")
    ap.add_argument("--jobs", type=int, default=1, choices=[1, 2])
    ap.add_argument("--json", default=None)
    ap.add_argument("--keep-all", action="store_true", help="keep the recordings of hits too")
    args = ap.parse_args()
    require_executable(args.lashid, "score.py")
    causes = args.causes.split(",") if args.causes else (PAIRS if args.pairs else SINGLES)
    for c in causes:
        if c not in SINGLES + PAIRS:
            raise SystemExit(f"score.py: unknown cause '{c}'")
    os.makedirs(args.workdir, exist_ok=True)
    jobs = [(c, s) for c in causes for s in range(args.first_seed, args.first_seed + args.seeds)]
    results, lock, t_start = [], threading.Lock(), time.monotonic()

    def task(job):
        r = run_one(args, *job)
        with lock:
            results.append(r)
            mark = "hit " if r["hit"] else "MISS"
            print(f"[{len(results):4d}/{len(jobs)}] {mark} {r['cause']:26s} seed {r['seed']:3d} found "
                  f"{'+'.join(r['found']) or r.get('error', '-')[:60]} ({r['seconds']:.2f}s)", file=sys.stderr,
                  flush=True)
        return r

    with concurrent.futures.ThreadPoolExecutor(max_workers=args.jobs) as ex:
        list(ex.map(task, jobs))
    results.sort(key=lambda r: (causes.index(r["cause"]), r["seed"]))
    by_cause = {c: [r for r in results if r["cause"] == c] for c in causes}
    tab = table(by_cause, causes)
    misses = [r for r in results if not r["hit"]]
    print(tab)
    print(f"\n{len(misses)} misses of {len(results)}:")
    for r in misses:
        print("  " + miss_line(r))
    print("\nfit_ext / fit_true / fit_pwl means per row (fit rule: fit_ext >= fit_true - 3; fit_pwl: the same"
          " against the true plant with borders linear between the true points at the levels):")
    for c, rs in by_cause.items():
        ok = [r for r in rs if r["fit_extended"] is not None]
        if ok:
            mean = lambda key: sum(r[key] for r in ok) / len(ok)
            print(f"  {c:28s} {mean('fit_extended'):6.1f} / {mean('fit_true'):6.1f} / {mean('fit_pwl'):6.1f}")
    cn = [r for r in results if "colour_through_A" in r["effects"]]
    if cn:
        print("\nrows with colored_noise, by how coloured the sensor noise e looks through A (1 - 1/sum h^2 of"
              " A(q^-1) e; near 0 = white = indistinguishable from the ARX equation error):")
        for lo, hi in ((0.0, 0.1), (0.1, 1.01)):
            sel = [r for r in cn if lo <= r["effects"]["colour_through_A"] < hi]
            print(f"  colour in [{lo:.1f}, {min(hi, 1.0):.1f}): {sum(r['hit'] for r in sel)}/{len(sel)} hits, "
                  f"{sum('colored_noise' in r['found'] for r in sel)}/{len(sel)} name colored_noise")
    secs = [r["seconds"] for r in results]
    print(f"\ndiagnosis time: mean {sum(secs) / len(secs):.2f}s, max {max(secs):.2f}s; wall "
          f"{time.monotonic() - t_start:.0f}s")
    if args.json:
        summary = {c: {"runs": len(rs), "hits": sum(r["hit"] for r in rs),
                       "causes_right": sum(r["causes_right"] for r in rs),
                       "fit_rule": sum(r["fit_rule"] for r in rs),
                       "fit_rule_pwl": sum(r["fit_rule_pwl"] for r in rs)} for c, rs in by_cause.items()}
        with open(args.json, "w") as f:
            json.dump({"command": sys.argv, "summary": summary, "table": tab,
                       "misses": [miss_line(r) for r in misses], "runs": results}, f, indent=1)
            f.write("\n")


if __name__ == "__main__":
    main()
