#!/usr/bin/env python3
"""The install and concurrent runs, tried as a user would (issue 12, "multigrid/ and the build").

  check_install.py install --build B --work W ...
      `cmake --install B --prefix W/prefix`, then, from another working directory, the installed
      apps: contact_blocks on the installed 2D example (small: refine 2, one load step, 2 ranks)
      and solve_block_system with a preset. A copy of an app without the share/ folder beside it
      must refuse with one line naming where it looked for the presets.
  check_install.py concurrent --build B --work W ...
      Two runs of the 2D example started at once in the same folder, writing into the same
      output directory: both must converge, and no temporary (gmsh's, *.tmp, *.partial) may be
      left there.

Exit status 0 only when every check passed (the last line then says so); each failed check
prints what was expected and what came instead."""
import argparse
import os
import re
import shutil
import subprocess
import sys

PROJECT = "saddle_point_multiphysics"
SUCCESS = re.compile(r"^Summary: 1 load steps, [0-9]+ Newton steps, .*; converged$", re.MULTILINE)
SMALL = ["--set", "Mesh/Gmsh refinement=2", "--set", "Loading/Load steps=1"]


def fail(message):
    print("FAILED: " + message)
    sys.exit(1)


def environment():
    """The user's environment without the presets override: the apps must find them alone."""
    env = dict(os.environ)
    env.pop("SADDLE_POINT_PRESETS", None)
    return env


def run(command, cwd, env=None, expect=0):
    print("+ (cd " + cwd + " && " + " ".join(command) + ")", flush=True)
    result = subprocess.run(command, cwd=cwd, env=env or environment(), capture_output=True, text=True)
    if result.returncode != expect:
        fail("exit status %d, expected %d\nstdout:\n%s\nstderr:\n%s" %
             (result.returncode, expect, result.stdout[-4000:], result.stderr[-4000:]))
    return result


def contact_run(mpiexec, exe, prm, mesh, output):
    return [mpiexec, "-np", "2", "--oversubscribe", exe, prm, "--set", "Mesh/Mesh file=" + mesh,
            *SMALL, "--set", "Output/Directory=" + output]


def fresh(directory):
    shutil.rmtree(directory, ignore_errors=True)
    os.makedirs(directory)
    return directory


def check_install(args):
    work = fresh(os.path.abspath(args.work))
    prefix = os.path.join(work, "prefix")
    run([args.cmake, "--install", args.build, "--prefix", prefix], cwd=work)
    share = os.path.join(prefix, "share", PROJECT)
    expected = [os.path.join(prefix, "bin", app) for app in ("solve_block_system", "contact_blocks", "beam_solid")]
    expected += [os.path.join(share, f) for f in ("presets/sa-amg.xml", "presets/saddle_point_amg.xml.in",
                                                  "apps/contact_blocks_2d.prm", "meshes/two_blocks_2d.geo")]
    for path in expected:
        if not os.path.isfile(path):
            fail(path + ": not installed")

    # From another working directory, with nothing of the build or source tree named.
    elsewhere = fresh(os.path.join(work, "elsewhere"))
    result = run(contact_run(args.mpiexec, os.path.join(prefix, "bin", "contact_blocks"),
                             os.path.join(share, "apps", "contact_blocks_2d.prm"),
                             os.path.join(share, "meshes", "two_blocks_2d.geo"), os.path.join(elsewhere, "out")),
                 cwd=elsewhere)
    if not SUCCESS.search(result.stdout):
        fail("installed contact_blocks: no line matching '%s' in\n%s" % (SUCCESS.pattern, result.stdout[-4000:]))
    if not os.path.isfile(os.path.join(elsewhere, "out", "solution.pvd")):
        fail("installed contact_blocks wrote no " + os.path.join(elsewhere, "out", "solution.pvd"))
    result = run([os.path.join(prefix, "bin", "solve_block_system"), "--builtin", "tied-blocks-2d:0", "--preset",
                  "emin(cheapsimple)"], cwd=elsewhere)
    if not re.search(r"GMRES +converged", result.stdout):
        fail("installed solve_block_system did not converge:\n" + result.stdout[-4000:])
    for app in ("contact_blocks", "beam_solid"):
        run([os.path.join(prefix, "bin", app), "--help"], cwd=elsewhere)

    # An app with no share/ folder beside it: one line naming where it looked, exit status 2.
    lonely = fresh(os.path.join(work, "lonely", "bin"))
    copy = os.path.join(lonely, "solve_block_system")
    shutil.copy2(os.path.join(prefix, "bin", "solve_block_system"), copy)
    result = run([copy, "--list-presets"], cwd=elsewhere, expect=2)
    looked = os.path.join(work, "lonely", "share", PROJECT, "presets")
    lines = result.stderr.strip().splitlines()
    if len(lines) != 1 or "solver presets not found: looked in " + looked not in lines[0]:
        fail("expected one line naming %s on stderr, got:\n%s" % (looked, result.stderr))
    # ... and SADDLE_POINT_PRESETS still points it to presets elsewhere.
    env = environment()
    env["SADDLE_POINT_PRESETS"] = os.path.join(share, "presets")
    result = run([copy, "--list-presets"], cwd=elsewhere, env=env)
    if "sa-amg(cheapsimple)" not in result.stdout:
        fail("--list-presets with SADDLE_POINT_PRESETS lists no sa-amg(cheapsimple):\n" + result.stdout)
    print("install check passed")


def check_concurrent(args):
    work = fresh(os.path.abspath(args.work))
    output = os.path.join(work, "out")
    command = contact_run(args.mpiexec, os.path.join(args.build, "apps", "contact_blocks"),
                          os.path.join(args.source, "apps", "contact_blocks_2d.prm"),
                          os.path.join(args.source, "meshes", "two_blocks_2d.geo"), output)
    print("+ twice at once, in " + work + ": " + " ".join(command), flush=True)
    runs = [subprocess.Popen(command, cwd=work, env=environment(), stdout=subprocess.PIPE, stderr=subprocess.PIPE,
                             text=True) for _ in range(2)]
    for i, p in enumerate(runs):
        stdout, stderr = p.communicate()
        if p.returncode != 0 or not SUCCESS.search(stdout):
            fail("run %d of 2: exit status %d, expected 0 and a line matching '%s'\nstdout:\n%s\nstderr:\n%s" %
                 (i + 1, p.returncode, SUCCESS.pattern, stdout[-4000:], stderr[-4000:]))
    left = [name for name in sorted(os.listdir(output))
            if name.startswith("gmsh-") or name.endswith((".tmp", ".partial", ".msh", ".log"))]
    if left:
        fail("temporaries left in %s: %s" % (output, ", ".join(left)))
    print("concurrent runs check passed")


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("mode", choices=["install", "concurrent"])
    ap.add_argument("--build", required=True, help="the build tree")
    ap.add_argument("--source", help="the source tree (concurrent: the example and its mesh)")
    ap.add_argument("--work", required=True, help="a scratch folder (emptied first)")
    ap.add_argument("--cmake", default="cmake")
    ap.add_argument("--mpiexec", default="mpirun")
    args = ap.parse_args()
    args.build = os.path.abspath(args.build)
    if args.mode == "install":
        check_install(args)
    else:
        if not args.source:
            ap.error("concurrent needs --source")
        args.source = os.path.abspath(args.source)
        check_concurrent(args)


if __name__ == "__main__":
    main()
