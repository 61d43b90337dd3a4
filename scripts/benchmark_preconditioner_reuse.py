#!/usr/bin/python3
"""What keeping the preconditioner across the Newton steps of a load/time step saves (issue 13
item 5): runs one example with `Linear solver/Reuse preconditioner` = false, true (the whole
preconditioner) and transfers (the hierarchy set up again on the kept aggregates and
prolongators), one after the other on the same machine, and prints from each run's log: Newton
steps, GMRES iterations per Newton step, the solves with a kept preconditioner / kept transfers,
the set-up and GMRES seconds in all, the mean set-up seconds of a fresh hierarchy and of one on
kept transfers, and the run's wall seconds; the ratios against `false` close the table. The
runs share the machine's state one after the other: repeat with another --modes order to see
the noise. Writes the figures as JSON with --json.

  scripts/benchmark_preconditioner_reuse.py --app build/apps/contact_blocks --prm apps/contact_rings_2d.prm \\
      [--ranks 2] [--set "Loading/Load steps=40"]... [--modes transfers false true] [--json FILE] [--out DIR]
"""
import argparse
import json
import os
import subprocess
import sys
import tempfile
import time

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from json_output import write_json_atomically  # noqa: E402

MODES = ["false", "true", "transfers"]


def summarize(log_path):
    """The figures of one run's JSON-lines log (Newton lines carry the linear solve's figures)."""
    newton = [json.loads(line) for line in open(log_path) if '"newton"' in line]
    newton = [e for e in newton if "linear_iterations" in e]
    fresh = [e["setup_seconds"] for e in newton if not e.get("preconditioner_reused") and not e.get("transfers_reused")]
    refreshed = [e["setup_seconds"] for e in newton if e.get("transfers_reused")]
    return {
        "newton_steps": len(newton),
        "gmres_per_newton_step": sum(e["linear_iterations"] for e in newton) / max(len(newton), 1),
        "kept_preconditioner": sum(1 for e in newton if e.get("preconditioner_reused")),
        "kept_transfers": len(refreshed),
        "repeated_with_fresh": sum(1 for e in newton if "reused_preconditioner_iterations" in e),
        "setup_seconds": sum(e.get("setup_seconds", 0) for e in newton),
        "solve_seconds": sum(e.get("solve_seconds", 0) for e in newton),
        "fresh_setup_mean": sum(fresh) / len(fresh) if fresh else None,
        "refreshed_setup_mean": sum(refreshed) / len(refreshed) if refreshed else None,
    }


def run(args, mode, out):
    command = [args.mpiexec, "-np", str(args.ranks), "--oversubscribe", args.app, args.prm,
               "--set", f"Output/Directory={out}", "--set", "Output/VTK=false",
               "--set", f"Linear solver/Reuse preconditioner={mode}"]
    for s in args.set:
        command += ["--set", s]
    start = time.time()
    result = subprocess.run(command, capture_output=True, text=True)
    wall = time.time() - start
    if result.returncode != 0:
        sys.exit(f"benchmark_preconditioner_reuse: the run with reuse={mode} failed "
                 f"(exit {result.returncode}): {result.stderr.strip()[-400:]}")
    figures = summarize(os.path.join(out, "run_log.jsonl"))
    figures["wall_seconds"] = wall
    return figures


def fmt(value, digits=2):
    return "-" if value is None else f"{value:.{digits}f}"


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--app", required=True, help="the app (e.g. build/apps/contact_blocks)")
    parser.add_argument("--prm", required=True, help="its parameter file")
    parser.add_argument("--mpiexec", default="mpirun")
    parser.add_argument("--ranks", type=int, default=2)
    parser.add_argument("--set", action="append", default=[], help="Section/Entry=value for every run")
    parser.add_argument("--modes", nargs="+", choices=MODES, default=MODES,
                        help="the settings to run, in this order (false must be one: the ratios' base)")
    parser.add_argument("--json", help="write the figures here")
    parser.add_argument("--out", help="the runs' output directories go here (default: a temporary one)")
    args = parser.parse_args()
    for path in (args.app, args.prm):
        if not os.path.exists(path):
            sys.exit(f"benchmark_preconditioner_reuse: {path}: no such file")
    if "false" not in args.modes:
        sys.exit("benchmark_preconditioner_reuse: --modes must include false (the ratios' base)")
    with tempfile.TemporaryDirectory() as tmp:
        base = args.out or tmp
        results = {mode: run(args, mode, os.path.join(base, f"reuse_{mode}")) for mode in args.modes}
    print(f"{args.prm} on {args.ranks} ranks {' '.join(args.set)}")
    print(f"{'reuse':>10} {'Newton':>7} {'GMRES/N':>8} {'kept':>5} {'transf.':>7} {'again':>5} {'set-up s':>9} "
          f"{'solve s':>8} {'fresh s':>8} {'refr. s':>8} {'wall s':>7}")
    for mode, r in results.items():
        print(f"{mode:>10} {r['newton_steps']:7d} {r['gmres_per_newton_step']:8.2f} {r['kept_preconditioner']:5d} "
              f"{r['kept_transfers']:7d} {r['repeated_with_fresh']:5d} {r['setup_seconds']:9.2f} "
              f"{r['solve_seconds']:8.2f} {fmt(r['fresh_setup_mean'], 3):>8} {fmt(r['refreshed_setup_mean'], 3):>8} "
              f"{r['wall_seconds']:7.1f}")
    base = results["false"]
    for mode in [m for m in args.modes if m != "false"]:
        r = results[mode]
        print(f"{mode} / false: set-up {r['setup_seconds'] / base['setup_seconds']:.2f}, solve "
              f"{r['solve_seconds'] / base['solve_seconds']:.2f}, set-up + solve "
              f"{(r['setup_seconds'] + r['solve_seconds']) / (base['setup_seconds'] + base['solve_seconds']):.2f}, "
              f"wall {r['wall_seconds'] / base['wall_seconds']:.2f}")
    if args.json:
        write_json_atomically(args.json, {"prm": args.prm, "ranks": args.ranks, "set": args.set, "runs": results})


if __name__ == "__main__":
    main()
