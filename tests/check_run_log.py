#!/usr/bin/python3
"""Checks a run's JSON-lines log (run_log.jsonl) for what a test of the failure handling expects:
events (e.g. step_cut) whose reason matches a pattern, and that the run ended with a converged
Newton step and a timers summary. Exit status 0 if all checks pass, 1 otherwise (one line per
failed check).

  check_run_log.py LOG --event "step_cut:det F" --final-converged
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
    for f in failures:
        print(f"{args.log}: {f}")
    if not failures:
        print(f"{args.log}: run log checks passed")
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
