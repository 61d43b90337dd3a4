#!/usr/bin/python3
"""Benchmark: every contact preset on the tied-blocks family (4x DOFs per level).

Runs apps/solve_block_system for each preset and level, reads its JSON reports and prints one
table: GMRES iterations, setup and solve seconds, operator complexity, and the growth of the
iteration count from the smallest to the largest size (the seeds' claim: saddle-point AMG
barely grows). Compare rows of one run only: the machines are shared and noisy.

  scripts/benchmark_tied_blocks_family.py [--build build] [--levels 2 3 4] [--ranks 1]
                                          [--out output/tied_blocks_family.json]

The 2D overrides of the test suite apply (min aggregate 6 for the seeds' 3D value 18, max coarse
size 100 so every size gets the same 3-level hierarchy).
"""
import argparse
import json
import os
import subprocess
import sys
import tempfile

from json_output import write_json_atomically

PRESETS = ["pa-amg(cheapsimple)", "sa-amg(cheapsimple)", "emin(cheapsimple)",
           "sa-amg(braess-sarazin)", "sa-amg(uzawa)", "fully-coupled-sa-amg(simple)",
           "cheapsimple(pa-amg)", "cheapsimple(sa-amg)", "cheapsimplec(sgs)", "direct(superlu)"]
FULLY_COUPLED = set(PRESETS[:6])


def overrides(preset):
    if preset in FULLY_COUPLED:
        return ["--set", "template parameters/MIN_AGG_SIZE=6",
                "--set", "template parameters/COARSE_MAX_SIZE=100"]
    if preset in ("cheapsimple(pa-amg)", "cheapsimple(sa-amg)"):
        return ["--set", "primal solver/aggregation: min agg size=6",
                "--set", "primal solver/coarse: max size=100"]
    return []


def run(build, preset, level, ranks):
    with tempfile.TemporaryDirectory() as tmp:
        report = os.path.join(tmp, "report.json")
        cmd = [os.path.join(build, "apps", "solve_block_system"), "--builtin",
               f"tied-blocks-2d:{level}", "--preset", preset, "--max-iterations", "1000",
               "--json", report] + overrides(preset)
        if ranks > 1:
            cmd = ["mpirun", "--oversubscribe", "-np", str(ranks)] + cmd
        env = dict(os.environ, OMPI_ALLOW_RUN_AS_ROOT="1", OMPI_ALLOW_RUN_AS_ROOT_CONFIRM="1")
        done = subprocess.run(cmd, env=env, capture_output=True, text=True)
        if not os.path.exists(report):
            sys.exit(f"benchmark: {preset} at level {level} failed: {done.stderr.strip()}")
        with open(report) as f:
            return json.load(f)


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--build", default="build")
    parser.add_argument("--levels", type=int, nargs="+", default=[2, 3, 4])
    parser.add_argument("--ranks", type=int, default=1)
    parser.add_argument("--out", default="")
    args = parser.parse_args()

    rows, results = [], {}
    for preset in PRESETS:
        reports = [run(args.build, preset, level, args.ranks) for level in args.levels]
        results[preset] = reports
        its = [r["iterations"] for r in reports]
        growth = its[-1] / max(its[0], 1)
        rows.append((preset, reports, growth))

    sizes = [r["global_size"] for r in rows[0][1]]
    print(f"tied-blocks-2d family on {args.ranks} rank(s): sizes " + ", ".join(map(str, sizes)))
    head = f"{'preset':30s}" + "".join(f" | {'its':>4s} {'setup':>6s} {'solve':>6s} {'opc':>5s}" for _ in sizes)
    print(head + " | growth")
    for preset, reports, growth in rows:
        cells = "".join(f" | {r['iterations']:4d} {r['setup_seconds']:6.2f} {r['solve_seconds']:6.2f} "
                        f"{r['operator_complexity']:5.2f}" + ("" if r["converged"] else "!") for r in reports)
        flag = "" if preset not in FULLY_COUPLED else ("  (<= 1.5)" if growth <= 1.5 else "  (> 1.5)")
        print(f"{preset:30s}{cells} | {growth:5.2f}{flag}")
    print("! = not converged within 1000 iterations (reported, not an error of the benchmark)")
    if args.out:
        write_json_atomically(args.out, results)
    return 0


if __name__ == "__main__":
    sys.exit(main())
