#!/usr/bin/python3
"""Runs the fsi app on 1 and on 2 ranks with the same parameters and checks that both runs take
the same Newton steps in every time step (from run_log.jsonl) and end with the same largest wall
displacement (the app's summary line) to a relative 1e-8. Exit status 0 if so, 1 otherwise.

  check_fsi_ranks.py --app build/apps/fsi --mpiexec mpirun --prm apps/fsi_channel_2d.prm --out DIR [--set S/E=V]...
"""
import argparse
import json
import os
import re
import subprocess
import sys


def run(args, ranks):
    out = os.path.join(args.out, f"np{ranks}")
    command = [args.mpiexec, "-np", str(ranks), "--oversubscribe", args.app, args.prm,
               "--set", f"Output/Directory={out}", "--set", "Output/VTK=false"]
    for s in args.set:
        command += ["--set", s]
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
    return float(match.group(1)), steps


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--app", required=True)
    ap.add_argument("--mpiexec", required=True)
    ap.add_argument("--prm", required=True)
    ap.add_argument("--out", required=True)
    ap.add_argument("--set", action="append", default=[])
    args = ap.parse_args()
    one, two = run(args, 1), run(args, 2)
    if one is None or two is None:
        return 1
    failures = []
    if not one[1] or one[1] != two[1]:
        failures.append(f"Newton steps per time step differ: 1 rank {one[1]}, 2 ranks {two[1]}")
    if not (abs(one[0] - two[0]) <= 1e-8 * abs(one[0]) and one[0] > 0):
        failures.append(f"largest wall displacement differs: 1 rank {one[0]!r}, 2 ranks {two[0]!r}")
    for f in failures:
        print(f)
    if not failures:
        print(f"1 and 2 ranks agree: Newton steps {one[1]}, wall displacement {one[0]!r}")
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
