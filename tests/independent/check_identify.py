#!/usr/bin/env python3
# Checks the independent generator against `lashid identify`: a nearly noise-free recording without hidden effect
# (generate.py --quiet --cause none) must be accepted and identified: a, b and the border points agree with the
# truth after the paper's scaling (3.11c): b_est = K b, F_est = F / K with K = u_M - u_m.
# Written without reading the project's own generator. Pure Python 3, standard library only.
#
#   python3 check_identify.py --lashid BIN --seeds 10 --workdir DIR [--n random] [--m random]
import argparse
import json
import os
import subprocess
import sys

import score

HERE = os.path.dirname(os.path.abspath(__file__))


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--lashid", required=True)
    ap.add_argument("--seeds", type=int, default=10)
    ap.add_argument("--first-seed", type=int, default=1)
    ap.add_argument("--workdir", required=True)
    ap.add_argument("--n", default="random")
    ap.add_argument("--m", default="random")
    args = ap.parse_args()
    score.require_executable(args.lashid, "check_identify.py")
    os.makedirs(args.workdir, exist_ok=True)
    worst_all = 0.0
    for seed in range(args.first_seed, args.first_seed + args.seeds):
        base = os.path.join(args.workdir, f"quiet_{seed}")
        subprocess.run([sys.executable, os.path.join(HERE, "generate.py"), "--cause", "none", "--seed", str(seed),
                        "--out", base + ".csv", "--config-out", base + ".cfg.json", "--truth-out",
                        base + ".truth.json", "--n", args.n, "--m", args.m, "--quiet"], check=True)
        r = subprocess.run([args.lashid, "identify", "--config", base + ".cfg.json", "--data", base + ".csv",
                            "--json", base + ".id.json"], capture_output=True, text=True)
        if r.returncode != 0:
            print(f"seed {seed}: identify failed ({r.returncode}): {r.stderr.strip()}")
            continue
        truth = json.load(open(base + ".truth.json"))
        ident = json.load(open(base + ".id.json"))
        p = truth["plant"]
        k = p["u_M"] - p["u_m"]
        scale = max(abs(x) for x in p["F_d_true"] + p["F_a_true"]) / abs(k)
        errs = {}
        for scheme, f_true in (("dis", p["F_d_true"]), ("ais", p["F_a_true"])):
            est = ident[scheme]
            errs[scheme + ".a"] = max(abs(x - y) for x, y in zip(est["a"], p["a"]))
            errs[scheme + ".b"] = max(abs(x - k * y) for x, y in zip(est["b"], p["b"])) / max(abs(k * y) for y in p["b"])
            errs[scheme + ".F"] = max(abs(x - y / k) for x, y in zip(est["F"], f_true)) / scale
        worst = max(errs.values())
        worst_all = max(worst_all, worst)
        print(f"seed {seed}: n={truth['n']} m={truth['m']} {p['operator']:8s} {p['borders']['mode'][:10]:10s} "
              f"worst relative error {worst:.2e}  " + " ".join(f"{k_}={v:.1e}" for k_, v in errs.items()))
    print(f"worst over all seeds: {worst_all:.2e}")


if __name__ == "__main__":
    main()
