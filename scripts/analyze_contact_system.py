#!/usr/bin/python3
"""Measurements on an exported multi-body contact system (2 x 2: displacements + standard
Lagrange multipliers, body labels), for issue 13 (AMG iterations growing with the active set):

  - bodies, nodes per body, active multiplier nodes (a constraint row with a non-zero) and the
    body pairs they couple; slave nodes that also appear on the master side of another contact
  - how well each body's rigid modes are held: Rayleigh quotient r^T A r / r^T diag(A) r of the
    rigid modes of every body (nullspace columns restricted to the body; ~0 for a floating body,
    the mass term M/(beta dt^2)) against a typical element mode (1.0)
  - the nullspace's rotation column against the coordinates (-y, x about some centre)
  - the scales that meet in a multiplier aggregate: constraint entries, diag(B diag(A)^-1 B^T) of
    the active rows against the identity rows (1) of the inactive ones
With --scale-inactive EPS DIR it also writes the system with the inactive identity rows scaled
by EPS (same solution): mixing an EPS-row into a coarse constraint no longer swamps it.

  scripts/analyze_contact_system.py --system DIR [--scale-inactive 1e-6 OUTDIR]
"""
import argparse
import os
import shutil
import sys

import numpy as np
import scipy.io
import scipy.sparse as sp

from block_system_files import read_system


def mm(path):
    return np.asarray(scipy.io.mmread(path))


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--system", required=True, help="BlockSystem directory (two blocks, interface line)")
    ap.add_argument("--scale-inactive", nargs=2, metavar=("EPS", "OUTDIR"),
                    help="write the system with the inactive identity rows scaled by EPS to OUTDIR")
    a = ap.parse_args()
    A, b, blocks = read_system(a.system, n_blocks=2)
    primal, dual = blocks
    n, dpn, ddpn = primal["size"], primal["dofs_per_node"], dual["dofs_per_node"]
    iface = [l.split() for l in open(os.path.join(a.system, "manifest.txt")) if l.startswith("interface")]
    if not iface or primal["nullspace"] is None or primal["coordinates"] is None:
        sys.exit(f"{a.system}/manifest.txt: expected an interface line, a nullspace and coordinates")
    d2p = mm(os.path.join(a.system, iface[0][1])).astype(int)[:, 1]
    labels = mm(os.path.join(a.system, iface[0][3])).ravel().astype(int)
    ns, X = mm(primal["nullspace"]), mm(primal["coordinates"])
    K, B2 = A[:n, :n].tocsr(), A[n:, :n].tocsr()
    C = A[n:, n:].tocsr()
    node_body = labels[::dpn]

    row_active = np.asarray(abs(B2).sum(axis=1)).ravel() > 0
    active = row_active.reshape(-1, ddpn).any(axis=1)
    print(f"system {a.system}: {n} displacement + {dual['size']} multiplier DOFs")
    bodies, sizes = np.unique(node_body, return_counts=True)
    print(f"bodies {len(bodies)}; nodes per body: " + ", ".join(f"{s}x{c}" for s, c in
                                                              zip(*np.unique(sizes, return_counts=True))))
    print(f"multiplier nodes {len(d2p)}, active {active.sum()} on {len(np.unique(node_body[d2p[active]]))} slave bodies")
    inactive_rows = ~row_active
    Cd = C.diagonal()
    identity = inactive_rows & (np.diff(C.indptr) == 1) & (Cd == 1.0)
    print(f"inactive multiplier rows {inactive_rows.sum()}, of them identity rows {identity.sum()}")

    # slave nodes on the master side of another active contact
    master_nodes = set()
    for k in np.where(active)[0]:
        cols = np.unique(np.concatenate([B2.indices[B2.indptr[r]:B2.indptr[r + 1]] for r in range(k * ddpn, (k + 1) * ddpn)]) // dpn)
        master_nodes.update(int(c) for c in cols if node_body[c] != node_body[d2p[k]])
    both = len(master_nodes & set(d2p.tolist()))
    print(f"primal nodes on the master side of active contacts {len(master_nodes)}, of them also slave nodes {both}")

    # rigid modes per body
    D = K.diagonal()
    centre = X.mean(axis=0)
    rot = np.zeros(n)
    rot[0::dpn], rot[1::dpn] = -(X[:, 1] - centre[1]), X[:, 0] - centre[0]
    coef = np.linalg.lstsq(np.c_[ns[:, :2], rot], ns[:, 2], rcond=None)[0]
    err = np.linalg.norm(np.c_[ns[:, :2], rot] @ coef - ns[:, 2]) / np.linalg.norm(ns[:, 2])
    print(f"nullspace columns {ns.shape[1]}; rotation column = translations + {coef[2]:.3g} (-y, x): relative misfit {err:.2e}")
    q = []
    for body in bodies:
        m = labels == body
        R = ns[m]
        KR = K[m][:, m] @ R
        q.append([float(R[:, j] @ KR[:, j] / (R[:, j] ** 2 @ D[m])) for j in range(R.shape[1])])
    q = np.array(q)
    print("rigid-mode Rayleigh quotient r^T A r / r^T diag(A) r of each body (min/median/max over bodies):")
    for j in range(q.shape[1]):
        print(f"  column {j}: {q[:, j].min():.2e} / {np.median(q[:, j]):.2e} / {q[:, j].max():.2e}")

    # scales that meet in a multiplier aggregate
    S = (B2 @ sp.diags(1.0 / D) @ A[:n, n:]).tocsr()
    s = np.abs(S.diagonal()[row_active])
    print(f"constraint entries |B| of active rows: median {np.median(np.abs(B2[row_active].data)):.3g}, max {np.abs(B2.data).max():.3g}; "
          f"|diag(A)|: {np.abs(D).min():.3g}..{np.abs(D).max():.3g}")
    print(f"diag(B diag(A)^-1 B^T) of active rows: {s.min():.2e} / {np.median(s):.2e} / {s.max():.2e} "
          f"(min/median/max) against 1 on the identity rows")

    if a.scale_inactive:
        eps, out = float(a.scale_inactive[0]), a.scale_inactive[1]
        scale = np.ones(A.shape[0])
        scale[n + np.where(identity)[0]] = eps
        shutil.copytree(a.system, out, dirs_exist_ok=True)
        with open(os.path.join(out, "matrix.mm"), "wb") as f:
            scipy.io.mmwrite(f, sp.diags(scale) @ A, comment=f"{a.system} with identity rows x {eps}")
        with open(os.path.join(out, "rhs.mm"), "wb") as f:
            scipy.io.mmwrite(f, (scale * b).reshape(-1, 1))
        print(f"wrote {out} (identity rows scaled by {eps})")


if __name__ == "__main__":
    main()
