#!/usr/bin/python3
"""Plots of one run's log (RUN/run_log.jsonl): GMRES iterations per Newton step over the load or
time steps beside the number of active contact nodes (contact runs), and the Newton convergence
of every step (residual norm per field, log scale). Writes OUT/<run>_gmres.png and
OUT/<run>_newton.png and prints their names.

  postprocess/plot_run.py build/tests/contact_out/app --out plots

Exit status 0, or 2 for bad input (a missing or malformed log: one line naming the file).
"""
import argparse
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import plots  # noqa: E402
from runlog import InputError, RunLog  # noqa: E402


def plot_run(run, out, prefix=None):
    """Both plots of `run` into `out` (files named PREFIX_gmres.png, PREFIX_newton.png; PREFIX:
    the run directory's name); returns their descriptions (plots.describe)."""
    if not run.solves:
        raise InputError(f"{run.log_file}: no Newton step with a linear solve to plot")
    prefix = prefix or run.name
    return [plots.gmres_and_active_set(run, os.path.join(out, f"{prefix}_gmres.png")),
            plots.newton_convergence(run, os.path.join(out, f"{prefix}_newton.png"))]


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("runs", nargs="+", help="run directories (each holding run_log.jsonl)")
    ap.add_argument("--out", default=".", help="directory for the PNGs (default: .)")
    args = ap.parse_args()
    try:
        for d in args.runs:
            for info in plot_run(RunLog(d), args.out):
                print(os.path.join(args.out, info["file"]))
    except InputError as e:
        print(f"plot_run: {e}", file=sys.stderr)
        return 2
    return 0


if __name__ == "__main__":
    sys.exit(main())
