#!/usr/bin/python3
"""Energy check of a frictionless impact (issue 3, implicit dynamics): runs
apps/contact_impact_2d.prm (a half cylinder hitting a clamped block at 1 m/s, plane strain) with
the generalized-alpha method for several spectral radii rho_inf and time steps over the same
0.04 s, and reads the total energy (kinetic + strain) per time step from run_log.jsonl.

Frictionless contact does no work, so the total energy should stay at E0 = m v^2 / 2 up to the
time discretization: exactly during the free flight (a rigid translation), and after the impact
within the numerical dissipation of rho_inf < 1, which vanishes as dt -> 0 (second order) and
grows as rho_inf decreases. With rho_inf = 1 (trapezoidal rule) nothing damps the chatter of
contact nodes and the energy can grow (run --rho 1 to see it; the README records the numbers).

  scripts/impact_energy_2d.py --build build --runs 0.9:40 0.9:160 0.5:40 [--check 0.005]
"""
import argparse
import json
import os
import subprocess
import sys

from json_output import write_json_atomically

END_TIME = 0.04


def run(build, ranks, rho, steps, out_root):
    directory = os.path.join(out_root, f"rho{rho}_n{steps}")
    cmd = [os.path.join(build, "apps", "contact_blocks"), "apps/contact_impact_2d.prm",
           "--set", f"Loading/Load steps={steps}", "--set", f"Time integration/Time step={END_TIME / steps}",
           "--set", f"Time integration/Spectral radius={rho}", "--set", f"Output/Directory={directory}",
           "--set", "Output/VTK=false"]
    if ranks > 1:
        cmd = ["mpirun", "-np", str(ranks), "--oversubscribe"] + cmd
    env = dict(os.environ, OMPI_ALLOW_RUN_AS_ROOT="1", OMPI_ALLOW_RUN_AS_ROOT_CONFIRM="1")
    proc = subprocess.run(cmd, capture_output=True, text=True, env=env)
    if proc.returncode != 0:
        errors = [l for l in proc.stderr.splitlines() if l.startswith("contact_blocks")]
        return {"rho": rho, "steps": steps, "dt": END_TIME / steps,
                "failed": errors[0] if errors else f"exit status {proc.returncode}"}
    lines = [json.loads(l) for l in open(os.path.join(directory, "run_log.jsonl"))]
    energy = [l for l in lines if "time_step" in l]
    newton = [l for l in lines if "newton" in l]
    active = {}
    for l in newton:
        active[l["load_step"]] = l["active"]
    e0 = energy[0]["total_energy"]
    dev = [(e["total_energy"] - e0) / e0 for e in energy]
    first_contact = min((s for s, a in active.items() if a > 0), default=None)
    flight = [abs(d) for e, d in zip(energy, dev) if first_contact is None or e["time_step"] < first_contact]
    return {"rho": rho, "steps": steps, "dt": END_TIME / steps, "E0": e0,
            "free_flight_deviation": max(flight), "max_increase": max(dev), "max_decrease": -min(dev),
            "final_deviation": dev[-1], "first_contact_time": first_contact * END_TIME / steps if first_contact else None,
            "newton_steps": len(newton) - len(energy) + 1, "max_active": max(active.values()),
            "final_kinetic": energy[-1]["kinetic_energy"], "final_strain": energy[-1]["strain_energy"]}


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--build", default="build")
    ap.add_argument("--ranks", type=int, default=2)
    ap.add_argument("--runs", nargs="+", default=["0.9:40", "0.9:160", "0.5:40"],
                    help="RHO:STEPS pairs (time step = 0.04 s / STEPS)")
    ap.add_argument("--out", default="output/impact_2d")
    ap.add_argument("--json", default=None, help="write the results here")
    ap.add_argument("--check", type=float, default=None,
                    help="fail unless |E - E0| / E0 stays below this for every rho < 1 run, the free flight "
                         "conserves energy to 1e-10, the energy change shrinks with dt and a smaller rho "
                         "dissipates more")
    args = ap.parse_args()
    results = []
    print(f"{'rho':>5} {'steps':>6} {'dt [s]':>9} {'E0 [J/m]':>9} {'flight':>9} {'max +dE/E0':>11} "
          f"{'max -dE/E0':>11} {'final dE/E0':>12} {'Newton':>7} {'active':>7}")
    for spec in args.runs:
        rho, steps = spec.split(":")
        r = run(args.build, args.ranks, float(rho), int(steps), args.out)
        results.append(r)
        if "failed" in r:
            print(f"{r['rho']:5.2f} {r['steps']:6d} {r['dt']:9.2e}  failed: {r['failed']}", flush=True)
            continue
        print(f"{r['rho']:5.2f} {r['steps']:6d} {r['dt']:9.2e} {r['E0']:9.3f} {r['free_flight_deviation']:9.1e} "
              f"{r['max_increase']:11.2e} {r['max_decrease']:11.2e} {r['final_deviation']:12.3e} "
              f"{r['newton_steps']:7d} {r['max_active']:7d}", flush=True)
    if args.json:
        write_json_atomically(args.json, results)
    if args.check is None:
        return
    failures = [f"rho {r['rho']}, {r['steps']} steps: {r['failed']}" for r in results if "failed" in r]
    results = [r for r in results if "failed" not in r]
    for r in results:
        if r["first_contact_time"] is None:
            failures.append(f"rho {r['rho']}, {r['steps']} steps: no contact")
        if r["free_flight_deviation"] > 1e-10:
            failures.append(f"rho {r['rho']}, {r['steps']} steps: energy changed in free flight "
                            f"({r['free_flight_deviation']:.1e})")
        if r["rho"] < 1 and max(r["max_increase"], r["max_decrease"]) > args.check:
            failures.append(f"rho {r['rho']}, {r['steps']} steps: |dE|/E0 up to "
                            f"{max(r['max_increase'], r['max_decrease']):.2e} > {args.check}")
    by_rho = {}
    for r in results:
        by_rho.setdefault(r["rho"], []).append(r)
    for rho, runs in by_rho.items():
        runs.sort(key=lambda r: r["dt"])
        if rho < 1 and len(runs) > 1 and abs(runs[0]["final_deviation"]) >= abs(runs[-1]["final_deviation"]):
            failures.append(f"rho {rho}: final |dE|/E0 does not shrink with dt "
                            f"({runs[-1]['final_deviation']:.2e} at dt {runs[-1]['dt']:.1e}, "
                            f"{runs[0]['final_deviation']:.2e} at dt {runs[0]['dt']:.1e})")
    same_dt = {}
    for r in results:
        same_dt.setdefault(r["steps"], []).append(r)
    for steps, runs in same_dt.items():
        runs.sort(key=lambda r: r["rho"])
        for lo, hi in zip(runs, runs[1:]):
            if not lo["final_deviation"] < hi["final_deviation"]:
                failures.append(f"{steps} steps: rho {lo['rho']} does not dissipate more than rho {hi['rho']}")
    if failures:
        print("FAILED: " + "; ".join(failures))
        sys.exit(1)
    print("impact energy check passed")


if __name__ == "__main__":
    main()
