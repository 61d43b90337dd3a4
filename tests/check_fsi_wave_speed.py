#!/usr/bin/python3
"""Checks postprocess/fsi_wave_speed.py on a wall profile of known speed: a smooth front
d(x, t) = h (1 + tanh((c t - x) / w)) / 2 travelling at c = 500 (stations every 0.25, steps of
1e-4 as the tube writes them) must come out at c to 1 % by both arrival times, the Moens-Korteweg
verdict must pass a tolerance the speed meets and fail one it does not, and a missing file must
give exit status 2, as must an --until that keeps fewer than 3 steps. The fitted long-wave speed: a Gaussian pulse in a thin tube (kR ~ 0, no
dispersion) must give c0 to 0.5 % by the fit and the pure delay alike, and fail a 5 % verdict
against 1.1 c0; the same pulse dispersed by a tube of R = 0.5 (built here by a Fourier integral,
k(omega) by bisection on the Bessel series) must give c0 to 0.5 % by the fit, while a pure delay
fits it worse and slower. Exit status 0 if so, 1 otherwise.

  check_fsi_wave_speed.py --work DIR
"""
import argparse
import math
import os
import re
import subprocess
import sys

import numpy as np

TOOL = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "postprocess", "fsi_wave_speed.py")


def write_profile(directory, c):
    os.makedirs(directory, exist_ok=True)
    stations = [0.25 * k for k in range(21)]
    with open(os.path.join(directory, "wall_displacement.csv"), "w") as f:
        f.write("time," + ",".join(f"{x:g}" for x in stations) + "\n")
        for n in range(1, 101):
            t = 1e-4 * n
            f.write(f"{t:g}," + ",".join(f"{0.005 * (1 + math.tanh((c * t - x) / 0.3)):.10g}" for x in stations) + "\n")


def write_pulse(directory, c0, radius):
    """A Gaussian pulse exp(-((t - t0) / s)^2) at x = 0 carried to the stations x = 0 ... 2 by the
    fluid-filled tube's dispersion (radius R, long-wave speed c0; R -> 0: none), by the Fourier
    integral w(x, t) = 1/pi int_0^inf Re(G(omega) exp(i (omega t - k(omega) x))) d omega with
    G(omega) = s sqrt(pi) exp(-(omega s / 2)^2 - i omega t0); k(omega) by bisection on the Bessel
    series (independent of the tool's table). Steps of 2e-5 up to 0.03."""
    os.makedirs(directory, exist_ok=True)
    s, t0 = 0.001, 0.006
    omega = np.linspace(0.0, 8.0 / s, 801)[1:]
    k = np.array([wave_number(w, c0, radius) for w in omega])
    weight = s * math.sqrt(math.pi) * np.exp(-(omega * s / 2) ** 2) * (omega[1] - omega[0]) / math.pi
    stations = [0.5 * j for j in range(5)]
    times = 2e-5 * np.arange(1, 1501)
    columns = [np.cos(np.outer(times - t0, omega) - k * x).dot(weight) for x in stations]
    with open(os.path.join(directory, "wall_displacement.csv"), "w") as f:
        f.write("time," + ",".join(f"{x:g}" for x in stations) + "\n")
        for n, t in enumerate(times):
            f.write(f"{t:.6g}," + ",".join(f"{column[n]:.12g}" for column in columns) + "\n")


def bessel_ratio(x):
    """2 I1(x) / (x I0(x)) by the power series."""
    i0 = i1 = 0.0
    for m in range(40):
        i0 += (x / 2) ** (2 * m) / math.factorial(m) ** 2
        i1 += (x / 2) ** (2 * m + 1) / (math.factorial(m) * math.factorial(m + 1))
    return 2 * i1 / (x * i0)


def wave_number(omega, c0, radius):
    """k with omega = c0 k sqrt(2 I1(kR) / (kR I0(kR))) (omega grows with k)."""
    low, high = 0.0, 10 * omega / c0
    for _ in range(60):
        k = 0.5 * (low + high)
        low, high = (k, high) if c0 * k * math.sqrt(bessel_ratio(k * radius)) < omega else (low, k)
    return 0.5 * (low + high)


def fit_failures(work, c):
    """The fitted long-wave speed of an undistorted pulse (thin tube) and a dispersed one (R = 0.5)."""
    failures = []
    pattern = r"long-wave speed with dispersion (\S+) \(residual (\S+)\); pure delay (\S+) \(residual (\S+)\)"
    for radius, name in ((1e-4, "undistorted"), (0.5, "dispersed")):
        directory = os.path.join(work, name)
        write_pulse(directory, c, radius)
        # Moens-Korteweg with E h / (2 rho R) = c^2 (h = rho = 1).
        status, out = tool(directory, "--from", "0.5", "--to", "2", "--young", str(2 * radius * c * c), "--thickness",
                           "1", "--radius", str(radius), "--density", "1", "--method", "fit", "--tolerance", "0.01")
        match = re.search(pattern, out)
        if status != 0 or not match:
            failures.append(f"the fit failed on the {name} pulse (c0 = {c}, exit {status}): {out}")
            continue
        fit, fit_residual, delay, delay_residual = (float(v) for v in match.groups())
        if not abs(fit - c) <= 0.005 * c:
            failures.append(f"{name} pulse: fitted long-wave speed {fit}, expected {c} to 0.5 %")
        if radius < 1e-3 and not abs(delay - c) <= 0.005 * c:
            failures.append(f"undistorted pulse: delay speed {delay}, expected {c} to 0.5 %")
        if radius > 1e-3 and not (delay < 0.97 * c and delay_residual > 2 * fit_residual):
            failures.append(f"dispersed pulse: a pure delay ({delay}, residual {delay_residual}) should fit worse "
                            f"and slower than the dispersion (residual {fit_residual})")
    status, out = tool(os.path.join(work, "undistorted"), "--from", "0.5", "--to", "2", "--young",
                       str(2e-4 * 1.21 * c * c), "--thickness", "1", "--radius", "1e-4", "--density", "1",
                       "--method", "fit", "--tolerance", "0.05")
    if status != 1:
        failures.append(f"a fitted speed 10 % off the reference passed a 5 % tolerance (exit {status}): {out}")
    return failures


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
    failures += fit_failures(args.work, c)
    status, out = tool(args.work, "--until", "1e-4")
    if status != 2 or "expected at least 3" not in out or "Traceback" in out:
        failures.append(f"--until before the third step gave exit {status}, expected a one-line error and 2: {out}")
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
