#!/usr/bin/python3
"""Solver comparison over presets from several run directories (e.g. the runs of
scripts/benchmark_contact_solvers.py, or runs of one .prm with different `Linear solver/Preset`):
a Markdown table and a CSV of every run (DOFs, Newton steps, average/largest GMRES per Newton
step, setup/solve/assembly seconds, operator complexity, peak memory per rank), and a bar chart of
iterations and seconds over the presets for each problem size.

  postprocess/compare_solvers.py RUN_A RUN_B ... --out DIR
  postprocess/compare_solvers.py --find output/benchmark_contact_runs --out DIR

Writes DIR/solver_comparison.md, DIR/solver_comparison.csv and DIR/solver_comparison_<DOFs>.png.
Exit status 0, 2 for bad input (one line naming the file).
"""
import argparse
import csv
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import plots  # noqa: E402
import report  # noqa: E402
from runlog import InputError, RunLog, find_runs  # noqa: E402

CSV_KEYS = ["run", "problem_class", "preset", "dofs", "load_steps", "newton_steps", "gmres_average", "gmres_max",
            "gmres_all_converged", "converged", "step_cuts", "setup_seconds", "solve_seconds", "assembly_seconds",
            "operator_complexity", "peak_memory_mb_max", "directory"]


def summaries(directories):
    rows = [RunLog(d).summary() for d in directories]
    for r in rows:
        # Label a bar by its preset when that tells the runs of one size apart, else by the run.
        same = [q for q in rows if q["dofs"] == r["dofs"] and q["preset"] == r["preset"]]
        r["label"] = r["preset"] if r["preset"] and len(same) == 1 else r["run"]
    return rows


def write_csv(rows, path):
    with open(path, "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=CSV_KEYS, extrasaction="ignore")
        w.writeheader()
        w.writerows(rows)


def compare(directories, out):
    """Table, CSV and one bar chart per problem size; returns (markdown, [plot descriptions])."""
    if not directories:
        raise InputError("no run directories given (expected directories holding run_log.jsonl)")
    rows = summaries(directories)
    os.makedirs(out, exist_ok=True)
    write_csv(rows, os.path.join(out, "solver_comparison.csv"))
    infos, lines = [], ["## Solver comparison", ""]
    for dofs in sorted({r["dofs"] or 0 for r in rows}):
        group = [r for r in rows if (r["dofs"] or 0) == dofs]
        info = plots.solver_comparison(group, os.path.join(out, f"solver_comparison_{dofs}.png"))
        infos.append(info)
        lines += [f"### {dofs} DOFs", "", report.table(group, report.RUN_COLUMNS), "",
                  report.image(info, f"solver comparison, {dofs} DOFs"), ""]
    text = "\n".join(lines)
    with open(os.path.join(out, "solver_comparison.md"), "w") as f:
        f.write(text)
    return text, infos


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("runs", nargs="*", help="run directories (each holding run_log.jsonl)")
    ap.add_argument("--find", help="also every run directory below this one")
    ap.add_argument("--out", default=".", help="output directory (default: .)")
    args = ap.parse_args()
    directories = list(args.runs) + (find_runs(args.find) if args.find else [])
    try:
        text, _ = compare(directories, args.out)
    except InputError as e:
        print(f"compare_solvers: {e}", file=sys.stderr)
        return 2
    print(text)
    return 0


if __name__ == "__main__":
    sys.exit(main())
