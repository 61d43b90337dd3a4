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


CLASSES = {c.name: c for c in (Contact3D, BeamSolid)}

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
