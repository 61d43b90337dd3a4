#!/usr/bin/python3
"""Checks a run's JSON-lines log (run_log.jsonl) for what a test of the failure handling expects:
events (e.g. step_cut) whose reason matches a pattern, that the run ended with a converged
Newton step and a timers summary, that every linear solve converged (GMRES at its tolerance with
the true residual, not only the implicit one) and that some Newton step had at least N active
contact nodes. Exit status 0 if all checks pass, 1 otherwise (one line per failed check).

  check_run_log.py LOG --event "step_cut:det F" --final-converged
  check_run_log.py LOG --every-solve-converged --min-active 40
"""
import argparse
import json
import re
import sys


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("log")
    ap.add_argument("--event", action="append", default=[],
                    help="NAME[:REGEX]: an event line of this name whose reason matches REGEX must exist")
    ap.add_argument("--final-converged", action="store_true",
                    help="the last Newton line is converged and a timers event follows it")
    ap.add_argument("--every-solve-converged", action="store_true",
                    help="every linear solve of the log converged (linear_converged), no step was cut")
    ap.add_argument("--min-active", type=int, default=0,
                    help="some Newton line has at least this many active contact nodes")
    args = ap.parse_args()
    try:
        lines = [json.loads(l) for l in open(args.log) if l.strip()]
    except (OSError, ValueError) as e:
        print(f"{args.log}: cannot read the run log ({e})")
        return 1
    failures = []
    for spec in args.event:
        name, _, pattern = spec.partition(":")
        events = [l for l in lines if l.get("event") == name]
        if not any(re.search(pattern, l.get("reason", "")) for l in events):
            failures.append(f"no '{name}' event with a reason matching '{pattern}' "
                            f"(found: {[l.get('reason') for l in events]})")
    if args.final_converged:
        newton = [l for l in lines if "newton" in l]
        if not newton or not newton[-1].get("converged"):
            failures.append("the last Newton line is not converged")
        if not lines or lines[-1].get("event") != "timers":
            failures.append("the log does not end with the timers summary")
    solves = [l for l in lines if "linear_iterations" in l]
    if args.every_solve_converged:
        if not solves:
            failures.append("no linear solve in the log")
        for l in solves:
            if not l.get("linear_converged"):
                failures.append(f"the linear solve of step {l.get('load_step')}, Newton {l.get('newton')} did not "
                                f"converge (true relative residual {l.get('linear_relative_residual')})")
        cuts = [l for l in lines if l.get("event") == "step_cut"]
        if cuts:
            failures.append(f"{len(cuts)} step cut(s): {[l.get('reason') for l in cuts]}")
    if args.min_active:
        most = max((l.get("active", 0) for l in lines if "newton" in l), default=0)
        if most < args.min_active:
            failures.append(f"at most {most} active contact nodes, expected at least {args.min_active}")
    for f in failures:
        print(f"{args.log}: {f}")
    if not failures:
        print(f"{args.log}: run log checks passed")
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
