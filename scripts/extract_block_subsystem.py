#!/usr/bin/python3
"""Cut a small BlockSystem out of an exported 2 x 2 contact system (primal block + multipliers),
keeping only some bodies: for tests that need the real structure of a multi-body contact system
(nearly floating bodies, active and inactive contact nodes) at a fraction of its size.

Keeps the primal DOFs whose body label (the interface line's label file) is in --bodies, the
multiplier nodes whose slave node is kept, and every matrix entry between kept rows and columns.
A constraint row whose master side lies on a dropped body thus keeps only its kept columns (the
dropped body acts as a fixed obstacle); the mass term keeps the operator regular. Writes the
same files (manifest, matrix, rhs, nullspace, coordinates, dual-to-primal, body labels) with
--digits significant digits.

  scripts/extract_block_subsystem.py --system DIR --bodies 1 2 7 8 --out OUTDIR [--digits 10]
"""
import argparse
import os
import sys

import numpy as np
import scipy.io
import scipy.sparse as sp

from block_system_files import read_manifest, read_system


def interface_files(d):
    with open(os.path.join(d, "manifest.txt")) as f:
        for line in f:
            w = line.split()
            if w and w[0] == "interface":
                return os.path.join(d, w[1]), os.path.join(d, w[3])
    sys.exit(f"{d}/manifest.txt: expected an 'interface DUAL_TO_PRIMAL - BODY_LABELS' line")


def write_mm(path, a, digits, comment):
    # through a file object: scipy.io.mmwrite would append ".mtx" to a path
    with open(path, "wb") as f:
        scipy.io.mmwrite(f, a, comment=comment, precision=digits)


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--system", required=True, help="BlockSystem directory with two blocks and body labels")
    ap.add_argument("--bodies", type=int, nargs="+", required=True, help="body labels to keep")
    ap.add_argument("--out", required=True, help="output directory (created)")
    ap.add_argument("--digits", type=int, default=10, help="significant digits written (default 10)")
    a = ap.parse_args()

    A, b, blocks = read_system(a.system, n_blocks=2)
    primal, dual = blocks
    d2p_file, labels_file = interface_files(a.system)
    d2p = np.asarray(scipy.io.mmread(d2p_file)).astype(int)
    labels = np.asarray(scipy.io.mmread(labels_file)).ravel().astype(int)
    dpn, ddpn, n = primal["dofs_per_node"], dual["dofs_per_node"], primal["size"]
    missing = sorted(set(a.bodies) - set(labels.tolist()))
    if missing:
        sys.exit(f"extract_block_subsystem.py: --bodies: labels {missing} are not in {labels_file}")

    keep_dof = np.isin(labels, a.bodies)
    keep_node = keep_dof[::dpn]
    new_node = np.cumsum(keep_node) - 1
    keep_dual = keep_node[d2p[:, 1]]
    rows = np.r_[np.where(keep_dof)[0], n + np.where(np.repeat(keep_dual, ddpn))[0]]
    sub = sp.csr_matrix(A[rows][:, rows])
    sub.eliminate_zeros()

    os.makedirs(a.out, exist_ok=True)
    origin = f"cut from {os.path.normpath(a.system)} by extract_block_subsystem.py, bodies {a.bodies}"
    write_mm(os.path.join(a.out, "matrix.mm"), sub, a.digits, origin)
    write_mm(os.path.join(a.out, "rhs.mm"), b[rows].reshape(-1, 1), a.digits, origin)
    write_mm(os.path.join(a.out, "nullspace_0.mm"), np.asarray(scipy.io.mmread(primal["nullspace"]))[keep_dof],
                a.digits, origin)
    write_mm(os.path.join(a.out, "coordinates_0.mm"),
                np.asarray(scipy.io.mmread(primal["coordinates"]))[keep_node], a.digits, origin)
    kept = d2p[keep_dual]
    write_mm(os.path.join(a.out, "dual_to_primal.mm"),
                np.c_[np.arange(len(kept)), new_node[kept[:, 1]]].astype(np.int64), a.digits,
                "column 1: multiplier node (0-based in block 1), column 2: its primal node")
    write_mm(os.path.join(a.out, "body_labels.mm"), labels[keep_dof].reshape(-1, 1).astype(float), a.digits, origin)
    with open(os.path.join(a.out, "manifest.txt"), "w") as f:
        f.write(f"# BlockSystem {origin}\nformat block-system-1\nmatrix matrix.mm\nrhs rhs.mm\n"
                f"block {primal['name']} {int(keep_dof.sum())} {dpn} nullspace_0.mm coordinates_0.mm\n"
                f"block {dual['name']} {int(keep_dual.sum()) * ddpn} {ddpn} - -\n"
                "interface dual_to_primal.mm - body_labels.mm\n")
    print(f"{a.out}: {int(keep_dof.sum())} primal + {int(keep_dual.sum()) * ddpn} multiplier DOFs, {sub.nnz} nonzeros")


if __name__ == "__main__":
    main()
