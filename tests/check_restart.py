#!/usr/bin/python3
"""Checkpoint/restart of a run (Restart/Interval, --restart DIR): runs the app once
uninterrupted, then once more in another directory, killed with SIGKILL (every process of its session) as soon
as its log shows a checkpoint of step >= --kill-after, and resumes that run in place with
--restart OUT/restart. Checks that
  - the killed run's checkpoint directory is complete (`latest` names a directory with the shared
    and every rank's file) and the resumed run says where it restarted;
  - the resumed run ends with the same displacement norms as the uninterrupted one (every
    number of the app's "Displacement norms: ..." line, relative 1e-10);
  - its run log equals the uninterrupted one line by line (every Newton and converged-step line
    and every energy line with all their values; timings, memory and the checkpoint/restarted/
    timers events left out, step cuts included), its .pvd series list the same records and its
    CSV files are the same; with
    --expect-cut-after N the resumed part shows a step cut (a failure injected with
    Linear solver/Injected failures, whose solve count the checkpoint carries).
Then a checkpoint of this problem given to another problem (--other-prm) must be refused with
exit status 2 and a one-line message naming the checkpoint. Exit status 0 if all hold, 1 otherwise.

  check_restart.py --app build/apps/contact_blocks --mpiexec mpirun --prm apps/contact_rings_2d.prm
                   --out DIR [--ranks 2] [--kill-after 4] [--other-prm apps/contact_patch_2d.prm]
                   [--other-set S/E=V]... [--expect-cut-after N] [--set S/E=V]...
"""
import argparse
import json
import os
import re
import shutil
import subprocess
import sys
import time

from app_runs import app_command


def command(args, out, extra=()):
    return app_command(args.mpiexec, args.ranks, args.app, args.prm, out, args.set, extra)


def norms(stdout):
    """The numbers of the app's "Displacement norms: ..." line (contact: l2, max; fsi: structure
    l2, max, ALE l2, fluid l2)."""
    m = re.search(r"Displacement norms: (.*)", stdout)
    if not m:
        return None
    values = re.findall(r"[-+]?[0-9]*\.?[0-9]+(?:[eE][-+]?[0-9]+)?", re.sub(r"l2", "", m.group(1)))
    return tuple(float(v) for v in values) or None


def log_lines(path):
    """The run log without what legitimately differs: timings, memory, checkpoint bookkeeping."""
    lines = []
    for text in open(path):
        entry = json.loads(text)
        if entry.get("event") in ("timers", "restarted", "checkpoint"):
            continue
        lines.append({k: v for k, v in entry.items()
                      if not k.endswith("seconds") and not k.startswith("peak_memory")})
    return lines


def pvd_records(path):
    return re.findall(r'timestep="([^"]+)"[^>]*file="([^"]+)"', open(path).read())


def kill_session(process):
    """SIGKILL to every process of the run's session (mpirun and the ranks it started, which
    Open MPI may put in process groups of their own), then wait until none is left, so that no
    rank of the killed run writes into its directory while it is resumed."""
    subprocess.run(["pkill", "-KILL", "-s", str(process.pid)])
    process.wait()
    for _ in range(200):
        if subprocess.run(["pgrep", "-s", str(process.pid)], capture_output=True).returncode != 0:
            return
        subprocess.run(["pkill", "-KILL", "-s", str(process.pid)])
        time.sleep(0.05)
    raise RuntimeError(f"processes of session {process.pid} survive SIGKILL")


def killed_run(args, out):
    """Starts the run, kills it once a checkpoint of step >= kill_after is logged."""
    log = os.path.join(out, "run_log.jsonl")
    process = subprocess.Popen(command(args, out), stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL,
                               start_new_session=True)
    deadline = time.time() + args.timeout
    while time.time() < deadline and process.poll() is None:
        if os.path.exists(log):
            for text in open(log):
                if '"checkpoint"' in text and json.loads(text).get("load_step", 0) >= args.kill_after:
                    kill_session(process)
                    return True
        time.sleep(0.05)
    if process.poll() is None:
        kill_session(process)
    print(f"the run to be killed ended (exit {process.poll()}) before a checkpoint of step {args.kill_after}")
    return False


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--app", required=True)
    parser.add_argument("--mpiexec", required=True)
    parser.add_argument("--prm", required=True)
    parser.add_argument("--out", required=True)
    parser.add_argument("--ranks", type=int, default=2)
    parser.add_argument("--kill-after", type=int, default=4, help="kill after the checkpoint of this step")
    parser.add_argument("--other-prm", help="a parameter file of another problem (the refusal check)")
    parser.add_argument("--other-set", action="append", default=[],
                        help="S/E=V for the other problem (e.g. another mesh size of the same file)")
    parser.add_argument("--expect-cut-after", type=int, default=0,
                        help="the resumed log must show a step cut after this step (an injected failure)")
    parser.add_argument("--timeout", type=float, default=600)
    parser.add_argument("--set", action="append", default=[])
    args = parser.parse_args()
    shutil.rmtree(args.out, ignore_errors=True)
    failures = []

    reference_out = os.path.join(args.out, "uninterrupted")
    reference = subprocess.run(command(args, reference_out), capture_output=True, text=True)
    if reference.returncode != 0 or not norms(reference.stdout):
        print(f"the uninterrupted run failed (exit {reference.returncode}): {reference.stderr[-800:]}")
        return 1

    out = os.path.join(args.out, "killed")
    if not killed_run(args, out):
        return 1
    root = os.path.join(out, "restart")
    latest = open(os.path.join(root, "latest")).read().strip()
    checkpoint = os.path.join(root, latest)
    needed = ["checkpoint.bin"] + [f"rank_{r}.bin" for r in range(args.ranks)]
    missing = [f for f in needed if not os.path.isfile(os.path.join(checkpoint, f))]
    if missing:
        failures.append(f"checkpoint {checkpoint} lacks {missing}")
    print(f"killed after a checkpoint; the newest is {checkpoint}")

    resumed = subprocess.run(command(args, out, ["--restart", root]), capture_output=True, text=True)
    if resumed.returncode != 0 or not norms(resumed.stdout):
        print(f"the resumed run failed (exit {resumed.returncode}): {resumed.stderr[-800:]}")
        return 1
    restarted = re.search(r"Restarted from (\S+) after step (\d+)", resumed.stdout)
    if not restarted:
        failures.append("the resumed run does not say where it restarted")
    else:
        print(f"resumed from {restarted.group(1)} after step {restarted.group(2)}")

    a, b = norms(reference.stdout), norms(resumed.stdout)
    if len(a) != len(b):
        failures.append(f"the displacement norm lines differ: {a} and {b}")
    for k, (x, y) in enumerate(zip(a, b)):
        rel = abs(x - y) / max(abs(x), 1e-300)
        print(f"displacement norm {k + 1}: uninterrupted {x:.16g}, resumed {y:.16g}, relative difference {rel:.2e}")
        if rel > 1e-10:
            failures.append(f"displacement norm {k + 1} differs by {rel:.2e} (allowed 1e-10)")

    ref_lines, res_lines = log_lines(os.path.join(reference_out, "run_log.jsonl")), log_lines(os.path.join(out, "run_log.jsonl"))
    differing = [i for i, (x, y) in enumerate(zip(ref_lines, res_lines)) if x != y]
    print(f"run log: {len(ref_lines)} lines uninterrupted, {len(res_lines)} resumed, {len(differing)} differ")
    if len(ref_lines) != len(res_lines) or differing:
        failures.append(f"the run logs differ (first differing line {differing[:1]})")
    # Every ParaView series and CSV record of the run (contact: solution.pvd, contact_nodes.csv;
    # fsi: fluid.pvd, structure.pvd, wall_displacement.csv) as the uninterrupted run wrote it.
    outputs = sorted(f for f in os.listdir(reference_out) if f.endswith((".pvd", ".csv")))
    for f in outputs:
        mine = os.path.join(out, f)
        if not os.path.exists(mine):
            failures.append(f"the resumed run has no {f}")
        elif f.endswith(".pvd") and pvd_records(os.path.join(reference_out, f)) != pvd_records(mine):
            failures.append(f"the series {f} differ")
        elif f.endswith(".csv") and open(os.path.join(reference_out, f)).read() != open(mine).read():
            failures.append(f"{f} differs")
    print(f"outputs compared: {outputs}")
    if args.expect_cut_after:
        cuts = [l for l in res_lines if l.get("event") == "step_cut" and l.get("load_step", 0) > args.expect_cut_after]
        print(f"step cuts after step {args.expect_cut_after} in the resumed log: "
              f"{[(c['load_step'], c['reason']) for c in cuts]}")
        if not cuts:
            failures.append(f"no step cut after step {args.expect_cut_after} in the resumed run's log")

    if args.other_prm:
        other = app_command(args.mpiexec, args.ranks, args.app, args.other_prm, os.path.join(args.out, "other"),
                            args.other_set, ["--restart", root])
        refused = subprocess.run(other, capture_output=True, text=True)
        message = [l for l in refused.stderr.splitlines() if "--restart" in l]
        print(f"another problem with this checkpoint: exit {refused.returncode}, {message[:1]}")
        if refused.returncode != 2 or len(message) != 1 or "a checkpoint of" not in message[0]:
            failures.append("a checkpoint of another problem was not refused with exit 2 and one line")

    for f in failures:
        print("FAILED:", f)
    if not failures:
        print("restart check passed")
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
