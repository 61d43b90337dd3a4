#!/usr/bin/python3
"""The Turek-Hron FSI1 table from fsi runs (apps/fsi_turek_hron.prm): for each run directory the
last row of DIRECTORY/forces.csv (the steady state the pseudo-time stepping reaches) against the
published values (Turek & Hron 2006, FSI1: u_x(A) = 2.2700e-5 m, u_y(A) = 8.2090e-4 m, drag
14.295 N/m, lift 0.7638 N/m), with relative errors, and how much the last step still changed
each value (the run is steady when that is far below the errors).

  fsi_turek_hron.py output/fsi_turek_hron [more run directories, coarse to fine]
                    [--tolerance 0.02] [--decreasing] [--steady 1e-4]
With --tolerance the exit status says whether every value of the LAST directory is within that
relative distance of the reference; with --decreasing also whether the largest of the four
errors decreases from each directory to the next; --steady bounds the last step's relative
change of every value (default 1e-4).
Exit status: 0 (checks passed, or none asked), 1 a check failed, 2 unreadable input.
"""
import argparse
import os
import sys

REFERENCE = {"monitor_displacement_x": 2.2700e-5, "monitor_displacement_y": 8.2090e-4, "drag": 14.295,
             "lift": 0.7638}
NAMES = {"monitor_displacement_x": "u_x(A)", "monitor_displacement_y": "u_y(A)", "drag": "drag",
         "lift": "lift"}


def read_forces(directory):
    """The last two rows of forces.csv as dictionaries (column -> value)."""
    path = os.path.join(directory, "forces.csv")
    with open(path) as f:
        header = f.readline().strip().split(",")
        rows = [dict(zip(header, map(float, line.strip().split(",")))) for line in f if line.strip()]
    missing = [c for c in REFERENCE if c not in header]
    if missing:
        raise ValueError(f"{path}: no column {', '.join(missing)} (a run with an obstacle and a monitor point?)")
    if len(rows) < 2:
        raise ValueError(f"{path}: fewer than 2 time steps")
    return rows[-2], rows[-1]


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0],
                                     formatter_class=argparse.RawDescriptionHelpFormatter, epilog=__doc__)
    parser.add_argument("directories", nargs="+", help="fsi run directories, coarse to fine")
    parser.add_argument("--tolerance", type=float, help="relative error bound for the last directory")
    parser.add_argument("--decreasing", action="store_true",
                        help="require the largest relative error to decrease from run to run")
    parser.add_argument("--steady", type=float, default=1e-4,
                        help="bound on the last step's relative change of every value (default 1e-4)")
    args = parser.parse_args()

    try:
        results = [(d, *read_forces(d)) for d in args.directories]
    except (OSError, ValueError) as e:
        print(f"fsi_turek_hron.py: {e}", file=sys.stderr)
        return 2

    ok = True
    print("Turek-Hron FSI1, steady state (last time step) against Turek & Hron 2006:")
    print(f"{'run':<32}" + "".join(f"{NAMES[c]:>24}" for c in REFERENCE) + f"{'largest error':>15}{'last change':>13}")
    print(f"{'reference':<32}" + "".join(f"{REFERENCE[c]:>24.5g}" for c in REFERENCE))
    largest_errors = []
    for directory, before, last in results:
        errors = {c: (last[c] - REFERENCE[c]) / REFERENCE[c] for c in REFERENCE}
        change = max(abs(last[c] - before[c]) / abs(REFERENCE[c]) for c in REFERENCE)
        largest = max(abs(e) for e in errors.values())
        largest_errors.append(largest)
        cells = "".join(f"{last[c]:>14.6g} ({100 * errors[c]:+6.2f} %)" for c in REFERENCE)
        print(f"{os.path.basename(os.path.normpath(directory)):<32}{cells}{100 * largest:>13.2f} %{change:>13.1e}")
        if change > args.steady:
            print(f"  not steady: the last step changed a value by {change:.2e} (relative) > {args.steady:g}")
            ok = False
    if args.tolerance is not None:
        if largest_errors[-1] > args.tolerance:
            print(f"FAIL: largest relative error {100 * largest_errors[-1]:.2f} % > {100 * args.tolerance:g} %")
            ok = False
        else:
            print(f"within {100 * args.tolerance:g} % of the reference")
    if args.decreasing:
        if any(b >= a for a, b in zip(largest_errors, largest_errors[1:])):
            print("FAIL: the largest relative error does not decrease from run to run: " +
                  ", ".join(f"{100 * e:.2f} %" for e in largest_errors))
            ok = False
        else:
            print("the largest relative error decreases from run to run")
    return 0 if ok else 1


if __name__ == "__main__":
    sys.exit(main())
