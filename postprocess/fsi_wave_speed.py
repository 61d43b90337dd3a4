#!/usr/bin/python3
"""Pulse speed of an fsi run (the pressure-wave tube, BENCHMARKS.md section 3) from the wall
profile the app writes, DIRECTORY/wall_displacement.csv (a row per time step: time, then the mean
outward wall displacement at each axial station x of the interface nodes, the header naming x).

At every station in the fit range the front's arrival time is taken where the wall moves out
fastest (the largest rise of the displacement per step, refined by a parabola through the three
rates around it: the middle of the front, which diffusion in time spreads symmetrically), and
also where the displacement first reaches half of the pulse's height (the largest displacement
at the fit range's first station before the end of the run); a least-squares line x(t) through
the arrival times gives the speed (stations the front has not passed by the end of the run are
left out and shown as "not reached"). With --young, --thickness, --radius and --density the
Moens-Korteweg speed c = sqrt(E h / (2 rho_F R)) is printed beside it (and, for reference, the
speed of a thick wall from Lame's solution, which is lower for h/R = 0.2), and with --tolerance
the exit status says whether the speed of --method is within that relative distance of
--reference (Moens-Korteweg unless said).

The front of a short pulse is not a long wave: over a wavelength comparable with the radius the
fluid's radial inertia slows the wave (Korteweg's dispersion of a fluid-filled elastic tube,
c(k)^2 = c0^2 2 I1(kR) / (kR I0(kR)), c0 the long-wave speed), so the steepest rise of a sharp
front travels below c0, the more the better a mesh resolves the front. The fit separates the two:
the displacement at the fit range's first station x1, carried to its last station x2 through the
dispersion relation (each Fourier component times exp(-i k(omega) (x2 - x1))) and scaled by one
factor (viscous damping), is fitted to the displacement at x2 in least squares over c0; the
record up to --until (before the outlet's reflection arrives) is used. Printed beside it: the
same fit with a pure delay (no dispersion), its residual, and c0 against Moens-Korteweg and the
thick wall. --method fit makes the verdict use the fitted c0.
From DIRECTORY/run_log.jsonl it also prints the Newton steps per time step and the fluid's mass
balance (the largest relative imbalance while the inlet pressure acts: --pulse).

  fsi_wave_speed.py output/fsi_tube_3d [--from 1 --to 3] [--young 3e6 --thickness 0.1
                    --radius 0.5 --density 1] [--tolerance 0.05] [--method slope|half|fit]
                    [--reference moens-korteweg|thick-wall] [--until T] [--pulse 3e-3]
Exit status: 0 (within the tolerance, or none given), 1 outside it, 2 unreadable input.
"""
import argparse
import json
import math
import os
import sys

import numpy as np
from scipy import optimize, special


def read_profile(path):
    with open(path) as f:
        header = f.readline().strip().split(",")
        stations = [float(x) for x in header[1:]]
        times, rows = [], []
        for line in f:
            values = [float(v) for v in line.strip().split(",")]
            if len(values) != len(stations) + 1:
                raise ValueError(f"{path}: a row with {len(values)} values, expected {len(stations) + 1}")
            times.append(values[0])
            rows.append(values[1:])
    if len(times) < 3:
        raise ValueError(f"{path}: fewer than 3 time steps")
    return stations, times, rows


def steepest_rise(times, series):
    """Time of the largest rise per step (parabola through the neighbouring rates); None if the
    largest rise is the first or the last step's (the front has not passed within the run)."""
    rates = [(series[i + 1] - series[i]) / (times[i + 1] - times[i]) for i in range(len(series) - 1)]
    mid = [0.5 * (times[i] + times[i + 1]) for i in range(len(series) - 1)]
    k = max(range(len(rates)), key=lambda i: rates[i])
    if not 0 < k < len(rates) - 1:
        return None
    a, b, c = rates[k - 1], rates[k], rates[k + 1]
    denominator = a - 2 * b + c
    shift = 0.5 * (a - c) / denominator if denominator != 0 else 0.0
    return mid[k] + shift * (mid[k + 1] - mid[k])


def first_crossing(times, series, level):
    """First time the series reaches `level` (linear between steps), None if never."""
    previous_t, previous = 0.0, 0.0
    for t, v in zip(times, series):
        if v >= level:
            return previous_t + (level - previous) / (v - previous) * (t - previous_t) if v != previous else t
        previous_t, previous = t, v
    return None


def fit_speed(points):
    """Slope dx/dt of the least-squares line through (t, x)."""
    n = len(points)
    mt = sum(t for t, _ in points) / n
    mx = sum(x for _, x in points) / n
    stt = sum((t - mt) ** 2 for t, _ in points)
    return sum((t - mt) * (x - mx) for t, x in points) / stt if stt > 0 else float("nan")


def dispersion_table(radius):
    """k and omega / c0 of the axisymmetric wave in an inviscid fluid filling a tube of radius R
    whose wall (no inertia) has the long-wave speed c0. The linearized fluid has a harmonic
    pressure p = P I0(k r) cos(k x - omega t); its radial momentum rho dv_r/dt = -dp/dr at the
    wall and the wall's distensibility D = 1 / (rho c0^2) (outward displacement D R p / 2) give
    omega^2 = c0^2 k^2 2 I1(kR) / (kR I0(kR)); omega grows with k, so the table inverts by
    interpolation. Exponentially scaled Bessel functions: their ratio stays finite for large kR."""
    kr = np.linspace(1e-8, 400.0, 400001)
    return kr / radius, kr / radius * np.sqrt(2 * special.i1e(kr) / (kr * special.i0e(kr)))


def propagate(series, step, distance, speed, table):
    """The record `series` (steps of `step`, zero before it and padded with zeros after it) carried
    `distance` downstream: with the dispersion `table` (k, omega / c0) and c0 = speed, or as a pure
    delay distance / speed when table is None."""
    n = len(series)
    size = 8 * n
    omega = 2 * np.pi * np.fft.rfftfreq(size, step)
    k = omega / speed if table is None else np.interp(omega, speed * table[1], table[0])
    return np.fft.irfft(np.fft.rfft(series, size) * np.exp(-1j * k * distance), size)[:n]


def fitted_speed(first, last, step, distance, table, bounds):
    """The speed (c0 with the dispersion table, or the delay speed without) whose propagated first
    record, times the best factor, is nearest to the last record; returns (speed, relative residual)."""
    first, last = np.asarray(first), np.asarray(last)

    def misfit(speed):
        guess = propagate(first, step, distance, speed, table)
        scale = guess.dot(last) / guess.dot(guess)
        return np.linalg.norm(scale * guess - last) / np.linalg.norm(last)

    best = optimize.minimize_scalar(misfit, bounds=bounds, method="bounded", options={"xatol": 1e-4 * bounds[1]})
    return best.x, best.fun


def run_log_summary(path, pulse):
    newton, imbalance = {}, 0.0
    for line in open(path):
        entry = json.loads(line)
        if "newton" in entry and entry.get("converged"):
            newton[entry["load_step"]] = entry["newton"]
        if entry.get("event") == "fluid_balance" and entry["time"] <= pulse * (1 + 1e-12):
            imbalance = max(imbalance, entry["mass_imbalance_relative"])
    return newton, imbalance


def long_wave_speeds(args):
    """c0 of Moens-Korteweg, sqrt(E h / (2 rho_F R)), and of a thick wall. The thick wall's
    distensibility (Lame, open ends, inner radius a, outer b): dA/A = 2 p / E ((a^2 + b^2) /
    (b^2 - a^2) + nu), which gives Moens-Korteweg for h << R and is lower for h / R = 0.2."""
    a, b = args.radius, args.radius + args.thickness
    return {"moens-korteweg": math.sqrt(args.young * args.thickness / (2 * args.density * args.radius)),
            "thick-wall": math.sqrt(args.young / (2 * args.density * ((a * a + b * b) / (b * b - a * a) + args.poisson)))}


def verdict(args, speeds, times, first, last, distance):
    """Prints the speeds against the long-wave references; 1 if --method's speed is outside
    --tolerance of --reference, else 0."""
    c0 = long_wave_speeds(args)
    step = times[1] - times[0]
    bounds = (0.3 * c0["moens-korteweg"], 3.0 * c0["moens-korteweg"])
    fit, fit_residual = fitted_speed(first, last, step, distance, dispersion_table(args.radius), bounds)
    delay, delay_residual = fitted_speed(first, last, step, distance, None, bounds)
    print(f"fitted over {distance:g} (record to t = {times[-1]:.6g}): long-wave speed with dispersion {fit:.6g} "
          f"(residual {fit_residual:.3f}); pure delay {delay:.6g} (residual {delay_residual:.3f})")
    speeds = dict(speeds, fit=fit)
    labels = {"moens-korteweg": "Moens-Korteweg c = sqrt(E h / (2 rho_F R))",
              "thick-wall": f"thick-wall (Lame, nu = {args.poisson}) c"}
    for name, c in c0.items():
        print(f"{labels[name]} = {c:.6g}; off by {100 * (fit - c) / c:+.2f} % (fit), "
              f"{100 * (speeds['slope'] - c) / c:+.2f} % (front, steepest rise), "
              f"{100 * (speeds['half'] - c) / c:+.2f} % (front, half height)")
    error = abs(speeds[args.method] - c0[args.reference]) / c0[args.reference]
    print(f"verdict: {args.method} speed against {args.reference} off by {100 * error:.2f} %")
    if args.tolerance is not None and not error <= args.tolerance:
        print(f"outside the tolerance {100 * args.tolerance:.2f} %")
        return 1
    return 0


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("directory", help="the run's Output/Directory")
    ap.add_argument("--from", dest="x_from", type=float, default=1.0, help="first station of the fit (x, cm)")
    ap.add_argument("--to", dest="x_to", type=float, default=3.0, help="last station of the fit (x, cm)")
    ap.add_argument("--method", choices=["slope", "half", "fit"], default="slope",
                    help="the speed the verdict uses: the front's by one of the arrival times, or the "
                    "long-wave speed fitted with the dispersion relation (all are printed)")
    ap.add_argument("--reference", choices=["moens-korteweg", "thick-wall"], default="moens-korteweg",
                    help="long-wave speed c0 of the verdict")
    ap.add_argument("--young", type=float, help="E of the wall")
    ap.add_argument("--thickness", type=float, help="wall thickness h")
    ap.add_argument("--radius", type=float, help="inner radius R")
    ap.add_argument("--density", type=float, help="fluid density rho_F")
    ap.add_argument("--poisson", type=float, default=0.3, help="nu of the wall (thick-wall speed)")
    ap.add_argument("--tolerance", type=float, help="largest relative distance to the reference")
    ap.add_argument("--until", type=float, help="use the record up to this time only (s): before the outlet's "
                    "reflection reaches the fit range")
    ap.add_argument("--pulse", type=float, default=3e-3, help="end of the inlet pressure (s), for the mass balance")
    args = ap.parse_args()
    try:
        stations, times, rows = read_profile(os.path.join(args.directory, "wall_displacement.csv"))
    except (OSError, ValueError) as error:
        print(f"fsi_wave_speed.py: {error}", file=sys.stderr)
        return 2
    if args.until is not None:
        kept = [n for n, t in enumerate(times) if t <= args.until * (1 + 1e-12)]
        times, rows = [times[n] for n in kept], [rows[n] for n in kept]
        if len(times) < 3:
            print(f"fsi_wave_speed.py: --until {args.until} keeps {len(times)} time steps of the record, "
                  "expected at least 3", file=sys.stderr)
            return 2
    used = [k for k, x in enumerate(stations) if args.x_from - 1e-9 <= x <= args.x_to + 1e-9]
    if len(used) < 2:
        print(f"fsi_wave_speed.py: fewer than 2 stations in [{args.x_from}, {args.x_to}] "
              f"(stations {stations[0]} ... {stations[-1]})", file=sys.stderr)
        return 2
    height = max(row[used[0]] for row in rows)
    slope_points, half_points = [], []
    print(f"{'x':>8} {'t_slope':>12} {'t_half':>12}")
    for k in used:
        series = [row[k] for row in rows]
        t_slope = steepest_rise(times, series)
        t_half = first_crossing(times, series, 0.5 * height)
        if t_slope is not None:
            slope_points.append((t_slope, stations[k]))
        if t_half is not None:
            half_points.append((t_half, stations[k]))
        shown = [f"{t:12.6e}" if t is not None else f"{'not reached':>12}" for t in (t_slope, t_half)]
        print(f"{stations[k]:8.4f} {shown[0]} {shown[1]}")
    speeds = {"slope": fit_speed(slope_points) if len(slope_points) >= 2 else float("nan"),
              "half": fit_speed(half_points) if len(half_points) >= 2 else float("nan")}
    print(f"pulse speed (steepest rise): {speeds['slope']:.6g}; (half height {height:.4g}): {speeds['half']:.6g}")
    status = 0
    if None not in (args.young, args.thickness, args.radius, args.density):
        status = verdict(args, speeds, times, [row[used[0]] for row in rows], [row[used[-1]] for row in rows],
                         stations[used[-1]] - stations[used[0]])
    log = os.path.join(args.directory, "run_log.jsonl")
    if os.path.exists(log):
        newton, imbalance = run_log_summary(log, args.pulse)
        if newton:
            counts = sorted(newton.values())
            print(f"Newton steps per time step: min {counts[0]}, max {counts[-1]}, "
                  f"mean {sum(counts) / len(counts):.2f} over {len(counts)} steps")
        print(f"largest relative mass imbalance while the inlet pressure acts: {imbalance:.3g}")
    return status


if __name__ == "__main__":
    sys.exit(main())
