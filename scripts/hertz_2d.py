#!/usr/bin/python3
"""Hertz check in 2D (issue 3, item 2): runs apps/contact_hertz_2d.prm at several mesh
refinements and compares the contact pressure with Hertz's solution for a cylinder on a
half-space (plane strain, equal materials):
    E* = E / (2 (1 - nu^2)),  a = sqrt(4 P R / (pi E*)),  p0 = 2 P / (pi a),
P the load per unit length of the whole cylinder (twice the half model's). p0 is compared with
the largest nodal pressure, a with the half-width of the fit p^2 = p0^2 (1 - x^2 / a^2) over the
active nodes (the active-set edge alone resolves a only to one element).

  scripts/hertz_2d.py --build build --levels 1 2 3 4 [--check 0.05]
"""
import argparse
import csv
import math
import os
import subprocess
import sys

E, NU, R, WIDTH = 10e6, 0.3, 1.0, 1.0


def hertz(pressure):
    P = 2 * pressure * WIDTH
    e_star = E / (2 * (1 - NU ** 2))
    a = math.sqrt(4 * P * R / (math.pi * e_star))
    return P, a, 2 * P / (math.pi * a)


def measure(build, level, out_root, pressure):
    directory = os.path.join(out_root, f"level{level}")
    cmd = [os.path.join(build, "apps", "contact_blocks"), "apps/contact_hertz_2d.prm",
           "--set", f"Mesh/Gmsh refinement={level}", "--set", f"Output/Directory={directory}",
           "--set", f"Loading/Pressure={pressure}"]
    proc = subprocess.run(cmd, capture_output=True, text=True)
    if proc.returncode != 0:
        raise SystemExit(f"level {level}: contact_blocks failed:\n{proc.stdout[-2000:]}{proc.stderr[-2000:]}")
    rows = list(csv.DictReader(open(os.path.join(directory, "contact_nodes.csv"))))
    active = [(float(r["x"]), float(r["contact_pressure"])) for r in rows if r["active"] == "1"]
    peak = max(p for _, p in active)
    # least squares of p^2 = c0 + c1 x^2 over nodes carrying at least 30 % of the peak
    pts = [(x * x, p * p) for x, p in active if p > 0.3 * peak]
    n = len(pts)
    sx = sum(u for u, _ in pts); sy = sum(v for _, v in pts)
    sxx = sum(u * u for u, _ in pts); sxy = sum(u * v for u, v in pts)
    c1 = (n * sxy - sx * sy) / (n * sxx - sx * sx)
    c0 = (sy - c1 * sx) / n
    a_fit = math.sqrt(-c0 / c1)
    force = 2 * sum(float(r["weight"]) * float(r["contact_pressure"]) for r in rows if r["active"] == "1")
    h = min(abs(active[i][0] - active[j][0]) for i in range(len(active)) for j in range(len(active)) if i != j)
    return {"level": level, "active": len(active), "h": h, "peak": peak, "a": a_fit, "force": force}


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--build", default="build")
    ap.add_argument("--levels", type=int, nargs="+", default=[1, 2, 3, 4])
    ap.add_argument("--out", default="output/hertz_2d")
    ap.add_argument("--pressure", type=float, default=5394.75,
                    help="dead pressure on the cylinder top (21579 Pa: a/R = 0.1; 5394.75 Pa: a/R = 0.05)")
    ap.add_argument("--check", type=float, default=None,
                    help="fail unless the finest level is within this relative error and errors decrease")
    args = ap.parse_args()
    P, a, p0 = hertz(args.pressure)
    print(f"Hertz: P = {P:.1f} N/m, a = {a:.5f} m, p0 = {p0:.1f} Pa")
    print(f"{'level':>5} {'h_min':>8} {'active':>6} {'peak p':>10} {'err p0':>8} {'a (fit)':>9} {'err a':>8} {'force':>9}")
    results = []
    for level in args.levels:
        r = measure(args.build, level, args.out, args.pressure)
        r["error_p0"] = abs(r["peak"] - p0) / p0
        r["error_a"] = abs(r["a"] - a) / a
        results.append(r)
        print(f"{level:>5} {r['h']:>8.4f} {r['active']:>6} {r['peak']:>10.1f} {r['error_p0']:>8.2%} {r['a']:>9.5f} "
              f"{r['error_a']:>8.2%} {r['force']:>9.1f}", flush=True)
    if args.check is not None:
        last = results[-1]
        ok = last["error_p0"] < args.check and last["error_a"] < args.check
        ok = ok and results[-1]["error_p0"] <= results[0]["error_p0"] and results[-1]["error_a"] <= results[0]["error_a"]
        print("check:", "passed" if ok else "FAILED")
        return 0 if ok else 1
    return 0


if __name__ == "__main__":
    sys.exit(main())
