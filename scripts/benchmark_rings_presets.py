#!/usr/bin/python3
"""GMRES iterations of the block presets on exported contact systems (issue 13, issue 14 item 4/5).

Solves every given BlockSystem directory (e.g. the collapsing-rings Newton systems exported by
contact_blocks with `Export systems = true`) with every preset through solve_block_system and
prints a table: iterations per preset and system, plus the number of active contact nodes
(multiplier rows with a constraint entry / DOFs per node). `--set` overrides are passed to every
preset they apply to (scoped with [preset] as in the app's Overrides). Writes the table as JSON
with --json.

  scripts/benchmark_rings_presets.py --build build --systems DIR1 DIR2 ... \
      [--presets P1 P2 ...] [--set "[emin(cheapsimple)] template parameters/MIN_AGG_SIZE=6"] \
      [--tol 1e-8] [--json FILE]
"""
import argparse
import json
import os
import subprocess
import sys
import tempfile

from json_output import write_json_atomically

PRESETS = ["emin(cheapsimple)", "pa-amg(cheapsimple)", "sa-amg(cheapsimple)", "fully-coupled-sa-amg(simple)",
           "cheapsimple(sa-amg)", "cheapsimple(pa-amg)"]
RINGS_PRM = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "apps", "contact_rings_2d.prm")


def rings_overrides():
    """The `Linear solver/Overrides` of the rings example (apps/contact_rings_2d.prm), one per entry.

    Read from the .prm rather than copied here, so the benchmark solves with what the example runs
    (ParameterHandler's syntax: a line ending in a backslash continues on the next one)."""
    text = open(RINGS_PRM).read().replace("\\\n", " ")
    for line in text.split("\n"):
        words = line.split("#")[0].split("=", 1)
        if len(words) == 2 and words[0].split() == ["set", "Overrides"]:
            return [o.strip() for o in words[1].split(";") if o.strip()]
    sys.exit(f"benchmark_rings_presets.py: {RINGS_PRM} has no 'set Overrides' (expected the rings example's)")


def active_nodes(directory):
    """Active multiplier nodes: dual rows with an entry in a primal column, over DOFs per node."""
    manifest = open(os.path.join(directory, "manifest.txt")).read().split("\n")
    blocks = [line.split() for line in manifest if line.startswith("block ")]
    if len(blocks) != 2:
        return None
    n_primal, dual_dpn = int(blocks[0][2]), int(blocks[1][3])
    rows = set()
    with open(os.path.join(directory, "matrix.mm")) as f:
        header = True
        for line in f:
            if line.startswith("%"):
                continue
            if header:
                header = False
                continue
            i, j, v = line.split()
            if int(i) > n_primal and int(j) <= n_primal and float(v) != 0.0:
                rows.add((int(i) - n_primal - 1) // dual_dpn)
    return len(rows)


def solve(build, directory, preset, overrides, tol):
    with tempfile.TemporaryDirectory() as tmp:
        report = os.path.join(tmp, "r.json")
        cmd = [os.path.join(build, "apps", "solve_block_system"), "--system", directory, "--preset", preset,
               "--tol", str(tol), "--max-iterations", "1000", "--json", report]
        for o in overrides:
            if not o.startswith("[") or o.startswith(f"[{preset}]"):
                cmd += ["--set", o]
        proc = subprocess.run(cmd, capture_output=True, text=True)
        if proc.returncode == 2 or not os.path.exists(report):
            sys.exit(f"benchmark_rings_presets.py: {' '.join(cmd)} failed: {proc.stderr.strip()}")
        r = json.load(open(report))
    return {"iterations": r.get("iterations"), "converged": proc.returncode == 0}


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--build", default="build", help="build directory holding apps/solve_block_system")
    ap.add_argument("--systems", nargs="+", required=True, help="BlockSystem directories")
    ap.add_argument("--presets", nargs="+", default=PRESETS)
    ap.add_argument("--set", action="append", default=None, dest="overrides",
                    help="override passed to solve_block_system (repeatable; default: the rings example's)")
    ap.add_argument("--tol", type=float, default=1e-8)
    ap.add_argument("--json", help="write the table to this file")
    a = ap.parse_args()
    overrides = rings_overrides() if a.overrides is None else a.overrides
    for d in a.systems:
        if not os.path.exists(os.path.join(d, "manifest.txt")):
            sys.exit(f"benchmark_rings_presets.py: --systems: {d} has no manifest.txt (expected a BlockSystem directory)")
    table = []
    print(f"{'system':<22} {'active':>6} " + " ".join(f"{p:>28}" for p in a.presets))
    for d in a.systems:
        row = {"system": os.path.basename(os.path.normpath(d)), "active_nodes": active_nodes(d), "iterations": {}}
        for p in a.presets:
            row["iterations"][p] = solve(a.build, d, p, overrides, a.tol)
        cells = [f"{r['iterations']}{'' if r['converged'] else '!'}" for r in row["iterations"].values()]
        print(f"{row['system']:<22} {row['active_nodes']!s:>6} " + " ".join(f"{c:>28}" for c in cells), flush=True)
        table.append(row)
    if a.json:
        write_json_atomically(a.json, {"tolerance": a.tol, "overrides": overrides, "rows": table})


if __name__ == "__main__":
    main()
