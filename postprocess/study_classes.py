"""The problem classes of a weak-scaling study: for each, the app and parameter file it runs,
the mesh parameter that sets its size, and how many DOFs a size gives (the apps' own count,
checked against `global_size` in the run logs by the tests).

A weak-scaling study keeps the DOFs per rank constant: for p ranks the class picks the size
whose DOFs are nearest to p times the target (`size_for`).
"""
import functools
import math
import os
import subprocess
import tempfile

SOURCE = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))


class MeshingError(RuntimeError):
    """gmsh is missing or could not mesh a size whose DOFs a class counts on the mesh."""


def nearest(x):
    """Round half up, as the .geo files do (Floor(x + 0.5)); Python's round() rounds to even."""
    return int(math.floor(x + 0.5))


class Contact3D:
    """The 3D two-block benchmark (apps/contact_blocks_3d.prm) on meshes/two_blocks_3d_weak.geo:
    size n = elements per metre of the lower block (n = 10 N is the benchmark's Gmsh refinement N).
    DOFs: 3 per node of both hexahedral blocks, plus 3 multipliers per slave-surface node."""
    name = "contact3d"
    app = "contact_blocks"
    prm = "apps/contact_blocks_3d.prm"
    mesh = "meshes/two_blocks_3d_weak.geo"
    smallest = 3
    description = "3D two-block mortar contact benchmark (seed 001)"

    @staticmethod
    def elements(n):
        return (max(1, nearest(n)), max(1, nearest(0.5 * n)), max(1, nearest(0.7 * n)), max(1, nearest(0.4 * n)))

    @classmethod
    def dofs(cls, n):
        nl, hl, nu, hu = cls.elements(n)
        lower = 3 * (nl + 1) ** 2 * (hl + 1)
        upper = 3 * (nu + 1) ** 2 * (hu + 1)
        multipliers = 3 * (nu + 1) ** 2
        return {"total": lower + upper + multipliers, "displacement": lower + upper, "multipliers": multipliers}

    @classmethod
    def settings(cls, n, data_dir):
        return {"Mesh/Mesh file": f"{data_dir}/{cls.mesh}", "Mesh/Gmsh refinement": str(n)}

    @classmethod
    def mesh_text(cls, n):
        nl, hl, nu, hu = cls.elements(n)
        return f"refine {n}: {nl}x{nl}x{hl} + {nu}x{nu}x{hu} hexahedra"


class BeamSolid:
    """The beam/solid family (apps/beam_solid_block.prm): a 2 x 1 x 1 block of 2n x n x n
    trilinear cells with round(n/2)^2 inclined fibres of 2n cubic Hermite elements (n = 4 r is the
    benchmark's refinement r). DOFs: 3 per solid node, 6 per beam node. With Newton's line search:
    the prm's whole load in one step makes the first full Newton update overshoot (the residual
    grows 23x), and that iterate's system gets harder with the size (7 / 11 / 64 GMRES iterations
    at n = 12 / 16 / 25, Newton 8 / 8 / 12 steps); backtracking keeps it out (n = 25: 6 Newton steps,
    8.3 GMRES per step instead of 12.7), so the study measures the preconditioner, not that iterate."""
    name = "beam_solid"
    app = "beam_solid"
    prm = "apps/beam_solid_block.prm"
    mesh = None
    smallest = 2
    description = "beam/solid penalty meshtying, fibres in a block (seed 001)"

    @staticmethod
    def fibres(n):
        return max(1, nearest(n / 2))

    @classmethod
    def dofs(cls, n):
        solid = 3 * (2 * n + 1) * (n + 1) ** 2
        beam = 6 * cls.fibres(n) ** 2 * (2 * n + 1)
        return {"total": solid + beam, "solid": solid, "beam": beam}

    @classmethod
    def settings(cls, n, data_dir):
        f = cls.fibres(n)
        return {"Mesh/Cells": f"{2 * n}, {n}, {n}", "Fibres/Fibres in y": str(f), "Fibres/Fibres in z": str(f),
                "Fibres/Elements per fibre": str(2 * n), "Newton/Line search": "true"}

    @classmethod
    def mesh_text(cls, n):
        f = cls.fibres(n)
        return f"n {n}: {2 * n}x{n}x{n} cells, {f}x{f} fibres of {2 * n} elements"


class FsiTube:
    """The pressure-wave tube (apps/fsi_tube_3d.prm, meshes/fsi_tube_3d.geo) made longer at a
    fixed cross-section (Gmsh refinement 2: 16 cells around, 2 through the wall): size n = cells
    along the tube, length n / 8 cm (n = 40 is the benchmark's 5 cm), so the DOFs grow exactly
    with n. DOFs per cross-section of nodes (the Newton system's blocks): structure 3 per wall
    node, fluid 4 per fluid node (the condensed interface velocities stay as placeholder rows),
    ALE 3 per fluid node off the interface. Three time steps of 1e-4 s with the fully coupled
    preset (the prm's SuperLU does not scale)."""
    name = "fsi"
    app = "fsi"
    prm = "apps/fsi_tube_3d.prm"
    mesh = "meshes/fsi_tube_3d.geo"
    smallest = 2
    refine = 2
    description = "condensed FSI, pressure-wave tube lengthened (seed 001)"

    @classmethod
    def section_dofs(cls):
        r = cls.refine
        wall_nodes = 8 * r * (r + 1)
        fluid_nodes = (2 * r + 1) ** 2 + 8 * r * (r + 1)
        return {"structure": 3 * wall_nodes, "fluid": 4 * fluid_nodes, "ale": 3 * (fluid_nodes - 8 * r)}

    @classmethod
    def dofs(cls, n):
        d = {k: (n + 1) * v for k, v in cls.section_dofs().items()}
        d["total"] = sum(d.values())
        return d

    @classmethod
    def length(cls, n):
        return n / (4 * cls.refine)

    @classmethod
    def settings(cls, n, data_dir):
        return {"Mesh/Mesh file": f"{data_dir}/{cls.mesh}", "Mesh/Gmsh refinement": str(cls.refine),
                "Mesh/Gmsh variables": f"length={cls.length(n)!r}", "Time/End time": "3e-4",
                "Linear solver/Preset": "fully-coupled-sa-amg(bgs)"}

    @classmethod
    def mesh_text(cls, n):
        return f"refine {cls.refine}, length {cls.length(n):g} cm: {n} cells along"


class Rings2D:
    """The collapsing rings (apps/contact_rings_2d.prm, meshes/rings_2d.geo) made wider at a fixed
    height: size n = columns of rings (Gmsh variable nx) under 4 rows (ny = 4), refinement 1 (the
    seeds' ~110 nodes per ring), so every rank's share of the pack is a strip of the same columns
    with the same interfaces to its neighbours. The first 10 of the prm's 80 time steps (the plate
    pushed down 12 mm at the prm's 1.2 mm per step: it meets the top row in step 2 and by step 10
    every gap of a column has closed), every body against every other (automatic pairs).
    DOFs: 2 per node plus 2 multipliers per slave node; the slave bodies are all but the one of
    highest material id (the container), their slave nodes those on a contact surface (boundary
    ids 1, 2). The container and the plate are meshed unstructured, so the node counts are gmsh's
    (the mesh is made here with the app's gmsh options and counted)."""
    name = "rings"
    app = "contact_blocks"
    prm = "apps/contact_rings_2d.prm"
    mesh = "meshes/rings_2d.geo"
    smallest = 1
    rows = 4
    time_steps = 10
    push_per_step = 96.0 / 80  # the prm's Loading/Displacement over its Load steps
    description = "collapsing rings, multi-body mortar contact (seed 000), widened"

    @staticmethod
    @functools.lru_cache(maxsize=None)
    def dofs(n):
        nodes, slave = Rings2D.mesh_counts(n)
        return {"total": 2 * nodes + 2 * slave, "displacement": 2 * nodes, "multipliers": 2 * slave}

    @classmethod
    def guess(cls, total):
        """The size whose DOFs are nearest to `total` if they grew by the same amount per column
        as from one column to two (the container's and plate's meshes make them nearly so)."""
        one, two = cls.dofs(1)["total"], cls.dofs(2)["total"]
        return 1 + int(round((total - one) / (two - one)))

    @classmethod
    def mesh_counts(cls, n):
        """(nodes, slave nodes) of the mesh gmsh makes for n columns."""
        with tempfile.TemporaryDirectory() as work:
            msh = os.path.join(work, "mesh.msh")
            cmd = ["gmsh", "-2", "-setnumber", "refine", "1", "-setnumber", "nx", str(n), "-setnumber", "ny",
                   str(cls.rows), "-format", "msh22", os.path.join(SOURCE, cls.mesh), "-o", msh]
            try:
                done = subprocess.run(cmd, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
            except FileNotFoundError:
                raise MeshingError("gmsh: not found (the rings class counts its DOFs on gmsh's mesh)")
            if done.returncode != 0 or not os.path.exists(msh):
                said = done.stdout.strip().splitlines()
                why = ([l for l in said if l.startswith("Error")] or said or ["no output"])[0].strip()
                raise MeshingError(f"gmsh could not mesh {cls.mesh} with nx = {n} ({why})")
            return cls.count_nodes(msh)

    @staticmethod
    def count_nodes(msh):
        """Nodes of a Gmsh 2.2 mesh and the nodes on a contact line (physical 1 or 2) of a cell
        of a slave body (physical surface below the highest)."""
        with open(msh) as f:
            lines = f.read().split("\n")
        n_nodes = int(lines[lines.index("$Nodes") + 1])
        start = lines.index("$Elements") + 2
        contact, body_nodes = set(), {}
        for line in lines[start:lines.index("$EndElements")]:
            v = line.split()
            kind, n_tags = int(v[1]), int(v[2])
            physical, nodes = int(v[3]), v[3 + n_tags:]
            if kind == 1 and physical in (1, 2):
                contact.update(nodes)
            elif kind in (2, 3):
                body_nodes.setdefault(physical, set()).update(nodes)
        master = max(body_nodes)
        slave = set().union(*(s for b, s in body_nodes.items() if b != master)) & contact
        return n_nodes, len(slave)

    @classmethod
    def settings(cls, n, data_dir):
        return {"Mesh/Mesh file": f"{data_dir}/{cls.mesh}", "Mesh/Gmsh refinement": "1",
                "Mesh/Gmsh variables": f"nx={n}, ny={cls.rows}", "Loading/Load steps": str(cls.time_steps),
                "Loading/Displacement": f"0, {-cls.push_per_step * cls.time_steps:g}"}

    @classmethod
    def mesh_text(cls, n):
        return f"{n} x {cls.rows} rings, refine 1"


CLASSES = {c.name: c for c in (Contact3D, BeamSolid, FsiTube, Rings2D)}

# The seeds' largest weak-scaling configurations (BENCHMARKS.md): total DOFs and ranks. The
# contact study names no rank count (at the seeds' ~50 k DOFs per rank it is 158 ranks); the
# beam/solid table says "50k DOFs per proc", but its 26.4 M DOFs on 1000 ranks are 26 k per rank.
SEED_CONFIGURATIONS = [
    {"class": "contact3d", "dofs": 7.9e6, "ranks": None, "note": "contact, two blocks, up to 7.9 M DOFs"},
    {"class": "beam_solid", "dofs": 24361803 + 2037192, "ranks": 1000, "note": "beam/solid, 24.4 M solid + 2.0 M beam DOFs on 1000 ranks"},
    {"class": "fsi", "dofs": 15.8e6, "ranks": 316, "note": "FSI tube, 15.8 M DOFs on 316 ranks"},
]


def size_for(cls, total, limit=100000):
    """The smallest size n whose DOFs are nearest to `total`. DOFs grow strictly with n, so the
    sizes around `total` are bracketed by steps that double, from the class's guess where it has
    one (the rings' DOF counts are meshes: a few, near the answer), then bisected; the answer is
    the last size at or below `total` or the first above."""
    def dofs(n):
        return cls.dofs(n)["total"]
    guess = cls.guess(total) if hasattr(cls, "guess") else cls.smallest
    low = high = min(max(guess, cls.smallest), limit)
    step = 1
    if dofs(low) <= total:  # walk up to the first size above total
        while dofs(high) <= total and high < limit:
            low, high, step = high, min(high + step, limit), 2 * step
    else:  # walk down to the last size at or below total
        while low > cls.smallest and dofs(low) > total:
            high, low, step = low, max(low - step, cls.smallest), 2 * step
    while high - low > 1:  # dofs(low) <= total < dofs(high), or low is the smallest size
        mid = (low + high) // 2
        low, high = (mid, high) if dofs(mid) <= total else (low, mid)
    if dofs(low) > total or low == high:
        return low
    return low if abs(dofs(low) - total) <= abs(dofs(high) - total) else high


def plan(cls, dofs_per_rank, ranks):
    """One entry per rank count: the size, its DOFs and the DOFs per rank it gives."""
    entries = []
    for p in ranks:
        n = size_for(cls, dofs_per_rank * p)
        d = cls.dofs(n)
        entries.append({"ranks": p, "size": n, "mesh": cls.mesh_text(n), "dofs": d["total"], "dofs_split": d,
                        "dofs_per_rank": d["total"] / p})
    return entries
