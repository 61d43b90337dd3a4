#!/usr/bin/python3
"""Runs the fsi app on several rank counts (default 1 and 2; oversubscribed where the machine has
fewer cores) with the same parameters and checks that every run takes the same Newton steps in
every time step (from run_log.jsonl) and ends with the same largest wall displacement (the app's
summary line) and the same displacement norms (structure l2 and max, ALE l2, fluid l2; printed
in full precision) as the first, to a relative 1e-8. With --distributed it also checks that the
meshes are fully distributed: on more than one rank, the most cells a rank stores (the app's
"N cells (at most M stored on a rank)") is below the number of cells, for the fluid and the
structure. Exit status 0 if so, 1 otherwise.

  check_fsi_ranks.py --app build/apps/fsi --mpiexec mpirun --prm apps/fsi_channel_2d.prm --out DIR
                     [--ranks 1 2 3] [--distributed] [--set S/E=V]...
"""
import argparse
import json
import os
import re
import subprocess
import sys

from app_runs import app_command


def run(args, ranks):
    out = os.path.join(args.out, f"np{ranks}")
    command = app_command(args.mpiexec, ranks, args.app, args.prm, out, ["Output/VTK=false"] + args.set)
    result = subprocess.run(command, capture_output=True, text=True)
    match = re.search(r"largest wall displacement ([0-9.eE+-]+); converged", result.stdout)
    if result.returncode != 0 or not match:
        print(f"the run on {ranks} ranks failed (exit {result.returncode}): {result.stdout[-500:]}{result.stderr[-500:]}")
        return None
    steps = {}
    for line in open(os.path.join(out, "run_log.jsonl")):
        entry = json.loads(line)
        if "newton" in entry and entry.get("converged"):
            steps[entry["load_step"]] = entry["newton"]
    cells = {field: (int(n), int(m)) for field, n, m in
             re.findall(r"(fluid|structure) ([0-9]+) cells \(at most ([0-9]+) stored on a rank\)", result.stdout)}
    norms = re.search(r"Displacement norms: structure l2 (\S+), max (\S+), ALE l2 (\S+), fluid l2 (\S+)", result.stdout)
    norms = [float(v) for v in norms.groups()] if norms else None
    return {"wall": float(match.group(1)), "steps": steps, "cells": cells, "norms": norms}


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--app", required=True)
    ap.add_argument("--mpiexec", required=True)
    ap.add_argument("--prm", required=True)
    ap.add_argument("--out", required=True)
    ap.add_argument("--ranks", type=int, nargs="+", default=[1, 2])
    ap.add_argument("--distributed", action="store_true",
                    help="also require fewer stored cells per rank than cells on more than one rank")
    ap.add_argument("--set", action="append", default=[])
    args = ap.parse_args()
    if len(args.ranks) < 2 and not args.distributed:
        print("--ranks: expected at least two rank counts to compare")
        return 1
    runs = {r: run(args, r) for r in args.ranks}
    if any(result is None for result in runs.values()):
        return 1
    first = args.ranks[0]
    reference = runs[first]
    failures = []
    if not reference["steps"] or not reference["wall"] > 0:
        failures.append(f"the run on {first} ranks took no converged step or did not move the wall")
    for r in args.ranks[1:]:
        if runs[r]["steps"] != reference["steps"]:
            failures.append(f"Newton steps per time step differ: {first} ranks {reference['steps']}, "
                            f"{r} ranks {runs[r]['steps']}")
        if not abs(runs[r]["wall"] - reference["wall"]) <= 1e-8 * abs(reference["wall"]):
            failures.append(f"largest wall displacement differs: {first} ranks {reference['wall']!r}, "
                            f"{r} ranks {runs[r]['wall']!r}")
        a, b = reference["norms"], runs[r]["norms"]
        if a is None or b is None or any(not abs(x - y) <= 1e-8 * abs(x) for x, y in zip(a, b)):
            failures.append(f"displacement norms (structure l2, max, ALE l2, fluid l2) differ or are missing: "
                            f"{first} ranks {a}, {r} ranks {b}")
    if args.distributed:
        for r in args.ranks:
            cells = runs[r]["cells"]
            if set(cells) != {"fluid", "structure"}:
                failures.append(f"the run on {r} ranks did not print 'N cells (at most M stored on a rank)' "
                                f"for the fluid and the structure")
            elif r > 1:
                for field, (n, m) in cells.items():
                    if not 0 < m < n:
                        failures.append(f"{field} on {r} ranks: a rank stores {m} of the {n} cells")
    for f in failures:
        print(f)
    for r in args.ranks:
        print(f"{r} ranks: Newton steps {runs[r]['steps']}, wall displacement {runs[r]['wall']!r}, "
              f"norms {runs[r]['norms']}, cells (total, most on a rank) {runs[r]['cells']}")
    if not failures:
        if len(args.ranks) > 1:
            print(f"ranks {', '.join(map(str, args.ranks))} agree")
        if args.distributed:
            print("every rank stores fewer cells than the mesh has")
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
