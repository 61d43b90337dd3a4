#!/usr/bin/python3
"""Checks postprocess/fsi_wave_speed.py on a wall profile of known speed: a smooth front
d(x, t) = h (1 + tanh((c t - x) / w)) / 2 travelling at c = 500 (stations every 0.25, steps of
1e-4 as the tube writes them) must come out at c to 1 % by both arrival times, the Moens-Korteweg
verdict must pass a tolerance the speed meets and fail one it does not, and a missing file must
give exit status 2. Exit status 0 if so, 1 otherwise.

  check_fsi_wave_speed.py --work DIR
"""
import argparse
import math
import os
import re
import subprocess
import sys

TOOL = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "postprocess", "fsi_wave_speed.py")


def write_profile(directory, c):
    os.makedirs(directory, exist_ok=True)
    stations = [0.25 * k for k in range(21)]
    with open(os.path.join(directory, "wall_displacement.csv"), "w") as f:
        f.write("time," + ",".join(f"{x:g}" for x in stations) + "\n")
        for n in range(1, 101):
            t = 1e-4 * n
            f.write(f"{t:g}," + ",".join(f"{0.005 * (1 + math.tanh((c * t - x) / 0.3)):.10g}" for x in stations) + "\n")


def tool(*args):
    result = subprocess.run([sys.executable, TOOL, *args], capture_output=True, text=True)
    return result.returncode, result.stdout + result.stderr


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--work", required=True)
    args = ap.parse_args()
    c = 500.0
    write_profile(args.work, c)
    failures = []
    # Moens-Korteweg with E h / (2 rho R) = c^2: E = 2 c^2 (h = R = rho = 1).
    mk = ["--young", str(2 * c * c), "--thickness", "1", "--radius", "1", "--density", "1"]
    status, out = tool(args.work, "--from", "1", "--to", "3", *mk, "--tolerance", "0.01")
    match = re.search(r"pulse speed \(steepest rise\): (\S+); \(half height \S+\): (\S+)", out)
    if status != 0 or not match:
        failures.append(f"the tool failed on a front of speed {c} (exit {status}): {out}")
    else:
        for name, value in zip(("steepest rise", "half height"), match.groups()):
            if not abs(float(value) - c) <= 0.01 * c:
                failures.append(f"{name} speed {value}, expected {c} to 1 %")
    status, out = tool(args.work, "--from", "1", "--to", "3", "--young", str(2 * 1.1 * 1.1 * c * c), "--thickness", "1",
                       "--radius", "1", "--density", "1", "--tolerance", "0.05")
    if status != 1:
        failures.append(f"a speed 10 % off Moens-Korteweg passed a 5 % tolerance (exit {status}): {out}")
    status, out = tool(os.path.join(args.work, "missing"))
    if status != 2:
        failures.append(f"a missing profile gave exit {status}, expected 2: {out}")
    for f in failures:
        print(f"check_fsi_wave_speed: {f}")
    if not failures:
        print("check_fsi_wave_speed: all checks passed")
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
