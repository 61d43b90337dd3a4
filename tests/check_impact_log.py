#!/usr/bin/python3
"""Checks the run log of a frictionless impact without loads or supports (the two tori): the
bodies come into contact (some converged step has at least --min-active active slave nodes) and
separate again (the last --separated steps have none), frictionless contact creates no energy
(the total energy of every step stays below the initial one times 1 + --growth), and the energy
lost to the time integrator's numerical damping stays bounded (the final total energy is at
least the initial one times 1 - --loss). The largest penetration of the converged steps (the
weighted gap) must stay below --penetration. Prints the figures; exit status 0 if all hold, 1 if
not.

  check_impact_log.py LOG [--min-active 1] [--separated 3] [--growth 0.01] [--loss 0.2]
                          [--penetration 5e-6]
"""
import argparse
import json
import sys


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("log")
    ap.add_argument("--min-active", type=int, default=1)
    ap.add_argument("--separated", type=int, default=3)
    ap.add_argument("--growth", type=float, default=0.01)
    ap.add_argument("--loss", type=float, default=0.2)
    ap.add_argument("--penetration", type=float, default=5e-6)
    args = ap.parse_args()
    try:
        lines = [json.loads(l) for l in open(args.log) if l.strip()]
    except (OSError, ValueError) as e:
        print(f"{args.log}: cannot read the run log ({e})")
        return 1
    steps = [l for l in lines if "converged_step" in l]
    energy = [l for l in lines if "time_step" in l]
    failures = []
    if not steps or not energy:
        print("the log has no converged steps or no energy lines")
        return 1
    active = [s["active"] for s in steps]
    in_contact = [s["converged_step"] for s in steps if s["active"] >= args.min_active]
    print(f"{len(steps)} steps; contact (>= {args.min_active} active nodes) in steps "
          f"{in_contact[:1] + in_contact[-1:]} ({len(in_contact)} steps), most active {max(active)}")
    if not in_contact:
        failures.append("the bodies never came into contact")
    if any(a > 0 for a in active[-args.separated:]):
        failures.append(f"still in contact in the last {args.separated} steps: {active[-args.separated:]}")
    e0 = energy[0]["total_energy"]
    peak = max(e["total_energy"] for e in energy)
    final = energy[-1]["total_energy"]
    print(f"total energy: initial {e0:.6g}, largest {peak:.6g} ({peak / e0 - 1:+.2%}), final {final:.6g} "
          f"({final / e0 - 1:+.2%})")
    if peak > e0 * (1 + args.growth):
        failures.append(f"the total energy grew by {peak / e0 - 1:.2%} (allowed {args.growth:.0%})")
    if final < e0 * (1 - args.loss):
        failures.append(f"the total energy fell by {1 - final / e0:.2%} (allowed {args.loss:.0%})")
    penetration = max(s["max_penetration"] for s in steps)
    print(f"largest penetration of the converged steps: {penetration:.3g} (allowed {args.penetration:.3g})")
    if penetration > args.penetration:
        failures.append("penetration above the allowed value")
    for f in failures:
        print("FAILED:", f)
    if not failures:
        print("impact check passed")
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
