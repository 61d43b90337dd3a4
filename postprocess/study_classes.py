"""The problem classes of a weak-scaling study: for each, the app and parameter file it runs,
the mesh parameter that sets its size, and how many DOFs a size gives (the apps' own count,
checked against `global_size` in the run logs by the tests).

A weak-scaling study keeps the DOFs per rank constant: for p ranks the class picks the size
whose DOFs are nearest to p times the target (`size_for`).
"""
import math


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
    benchmark's refinement r). DOFs: 3 per solid node, 6 per beam node."""
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
                "Fibres/Elements per fibre": str(2 * n)}

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


CLASSES = {c.name: c for c in (Contact3D, BeamSolid, FsiTube)}

# The seeds' largest weak-scaling configurations (BENCHMARKS.md): total DOFs and ranks. The
# contact study names no rank count (at the seeds' ~50 k DOFs per rank it is 158 ranks); the
# beam/solid table says "50k DOFs per proc", but its 26.4 M DOFs on 1000 ranks are 26 k per rank.
SEED_CONFIGURATIONS = [
    {"class": "contact3d", "dofs": 7.9e6, "ranks": None, "note": "contact, two blocks, up to 7.9 M DOFs"},
    {"class": "beam_solid", "dofs": 24361803 + 2037192, "ranks": 1000, "note": "beam/solid, 24.4 M solid + 2.0 M beam DOFs on 1000 ranks"},
    {"class": "fsi", "dofs": 15.8e6, "ranks": 316, "note": "FSI tube, 15.8 M DOFs on 316 ranks"},
]


def size_for(cls, total, limit=100000):
    """The smallest size n whose DOFs are nearest to `total` (DOFs grow with n)."""
    best, n = None, cls.smallest
    while n < limit:
        d = cls.dofs(n)["total"]
        if best is None or abs(d - total) < abs(cls.dofs(best)["total"] - total):
            best = n
        if d > total:
            break
        n += 1
    return best


def plan(cls, dofs_per_rank, ranks):
    """One entry per rank count: the size, its DOFs and the DOFs per rank it gives."""
    entries = []
    for p in ranks:
        n = size_for(cls, dofs_per_rank * p)
        d = cls.dofs(n)
        entries.append({"ranks": p, "size": n, "mesh": cls.mesh_text(n), "dofs": d["total"], "dofs_split": d,
                        "dofs_per_rank": d["total"] / p})
    return entries
