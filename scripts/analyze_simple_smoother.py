#!/usr/bin/python3
"""Why a SIMPLE-type level smoother converges or not on an exported saddle-point system.

Reads a BlockSystem directory (manifest.txt + Matrix Market, written by `contact_blocks` with
`Output/Export systems = true` or by `solve_block_system --export-system`) with scipy alone and
measures, for the 2 x 2 system

    K = [ A   B1^T ]      A: displacements, C: multiplier block
        [ B2  C    ]

  scaling   the size of the multiplier rows (B2, C) against the displacement rows (A, B1^T),
            and how B2 relates to B1 (B2 = diag(s) B1 row by row? the sign of s);
  lumping   diag(A)^-1 against the lumped inverses: signed row sum (zero for the rows of a
            stiffness matrix without a Dirichlet condition), absolute row sum;
  Schur     S = C - B2 Â B1^T for each Â: its diagonal (zero pivots of ILU(0)/SGS), the
            eigenvalues of its symmetric part (definiteness), ILU(0)'s smallest pivot;
  exact     the eigenvalues of S^-1 S_exact, S_exact = C - B2 A^-1 B1^T: one SIMPLE sweep with
            exact inner solves propagates the multiplier error by I - omega S^-1 S_exact, so
            rho < 1 needs 0 < omega lambda < 2 for every eigenvalue lambda;
  smoother  the spectral radius of the iteration matrix I - M^-1 K of one sweep of the level
            smoother as the presets build it (predictor p x SGS(w_p), corrector ILU(0) on S,
            damping omega, final update with Â_u), for every combination given (ARPACK on the
            operator; nothing dense but S).

    scripts/analyze_simple_smoother.py DIR [--json FILE] [--predictor-sweeps 1 3]

Only for small systems (a few thousand rows): S is formed densely, and A^-1 B1^T by a sparse LU.
"""
import argparse
import json

import numpy as np
import scipy.io
import scipy.linalg
import scipy.sparse as sp
import scipy.sparse.linalg as spla

import block_system_files  # scripts/, beside this file


def read_system(d):
    """K (CSR) and the size of the first (primal) block, from a manifest directory."""
    K, _, blocks = block_system_files.read_system(d, n_blocks=2, need_rhs=False)
    return K, blocks[0]["size"]


def inverse_approximation(A, kind):
    """The diagonal Â of `kind` as a vector, and the number of rows where it does not exist."""
    d = A.diagonal()
    rows = np.asarray(A.sum(axis=1)).ravel()
    abs_rows = np.asarray(abs(A).sum(axis=1)).ravel()
    if kind == "diagonal":
        value, bad = d, d == 0
    elif kind == "row-sum":
        value, bad = rows, np.abs(rows) <= 1e-12 * abs_rows
    elif kind == "absolute-row-sum":
        value, bad = np.sign(d) * abs_rows, d == 0
    else:
        raise ValueError(kind)
    inv = np.zeros_like(value)
    inv[~bad] = 1.0 / value[~bad]
    return inv, int(bad.sum())


def ilu0(S):
    """ILU(0) of a (small, dense-stored) matrix on its own pattern; returns L, U (dense)."""
    pattern = S != 0
    LU = S.copy()
    n = S.shape[0]
    for i in range(1, n):
        for k in range(i):
            if pattern[i, k] and LU[k, k] != 0:
                LU[i, k] /= LU[k, k]
                cols = np.nonzero(pattern[i, k + 1:])[0] + k + 1
                LU[i, cols] -= LU[i, k] * LU[k, cols]
    L = np.tril(LU, -1) + np.eye(n)
    U = np.triu(LU)
    return L, U


def sgs_operator(A, sweeps, damping):
    """x = SGS(b) from zero: `sweeps` symmetric Gauss-Seidel sweeps with damping (SSOR), as
    Ifpack2's relaxation does it."""
    D = sp.diags(A.diagonal() / damping)
    lower = sp.csr_matrix(sp.tril(A, -1) + D)
    upper = sp.csr_matrix(sp.triu(A, 1) + D)

    def apply(b):
        x = np.zeros_like(b)
        for _ in range(sweeps):
            x = x + spla.spsolve_triangular(lower, b - A @ x, lower=True)
            x = x + spla.spsolve_triangular(upper, b - A @ x, lower=False)
        return x

    return apply


def spectral_radius(n, step):
    """Largest |eigenvalue| of the linear map x -> step(x) (ARPACK)."""
    op = spla.LinearOperator((n, n), matvec=step, dtype=float)
    try:
        values = spla.eigs(op, k=3, which="LM", return_eigenvectors=False, maxiter=3000, tol=1e-4)
        return float(np.max(np.abs(values)))
    except spla.ArpackNoConvergence as e:
        return float(np.max(np.abs(e.eigenvalues))) if len(e.eigenvalues) else float("nan")


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("system")
    parser.add_argument("--json")
    parser.add_argument("--predictor-sweeps", type=int, nargs="+", default=[1, 3])
    parser.add_argument("--damping", type=float, default=0.8, help="SIMPLE damping omega (and SGS damping)")
    parser.add_argument("--no-smoother", action="store_true", help="skip the smoother's spectral radius")
    args = parser.parse_args()

    K, n1 = read_system(args.system)
    A, B1t, B2, C = K[:n1, :n1], K[:n1, n1:], K[n1:, :n1], K[n1:, n1:]
    n2 = K.shape[0] - n1
    report = {"system": args.system, "primal rows": n1, "dual rows": n2}

    # --- scaling of the rows, relation of B2 to B1 --------------------------------------------
    def row_max(M):
        return np.asarray(abs(M).max(axis=1).todense()).ravel() if M.nnz else np.zeros(M.shape[0])

    a_rows, b1_rows, b2_rows, c_rows = row_max(A), row_max(B1t), row_max(B2), row_max(C)
    coupled = b2_rows > 0
    report["scaling"] = {
        "median max|A| per row": float(np.median(a_rows)),
        "median max|B1^T| per coupled displacement row": float(np.median(b1_rows[b1_rows > 0])),
        "median max|B2| per constraint row": float(np.median(b2_rows[coupled])) if coupled.any() else 0.0,
        "median max|C| per row with C": float(np.median(c_rows[c_rows > 0])) if (c_rows > 0).any() else 0.0,
        "constraint rows with B2 != 0": int(coupled.sum()),
        "rows with C only": int(((c_rows > 0) & ~coupled).sum()),
        "rows with both": int(((c_rows > 0) & coupled).sum()),
    }
    # Sign convention: B2 diag(A)^-1 B1^T has a positive diagonal where B2's row is a positive
    # multiple of B1's (the same sign convention in both off-diagonal blocks).
    normal = c_rows == 0
    P = (B2 @ sp.diags(1.0 / A.diagonal()) @ B1t).diagonal()
    report["B2 vs B1"] = {
        "median max|B2| on rows without C (normal)": float(np.median(b2_rows[normal])) if normal.any() else 0.0,
        "median max|B2| on rows with C (tangential/inactive)":
            float(np.median(b2_rows[~normal & coupled])) if (~normal & coupled).any() else 0.0,
        "diag(B2 diag(A)^-1 B1^T) signs (+/-/0) on rows without C": [int((P[normal] > 0).sum()),
                                                                      int((P[normal] < 0).sum()),
                                                                      int((P[normal] == 0).sum())],
        "diag(B2 diag(A)^-1 B1^T) signs (+/-/0) on rows with C": [int((P[~normal] > 0).sum()),
                                                                   int((P[~normal] < 0).sum()),
                                                                   int((P[~normal] == 0).sum())],
    }

    # --- S_exact = C - B2 A^-1 B1^T --------------------------------------------------------
    lu = spla.splu(sp.csc_matrix(A))
    S_exact = C.toarray() - B2 @ lu.solve(B1t.toarray())

    report["inverse approximations"] = {}
    S_of = {}
    for kind in ("diagonal", "row-sum", "absolute-row-sum"):
        inv, bad = inverse_approximation(A, kind)
        entry = {"rows without a value (zero pivot)": bad}
        if bad == 0:
            S = (C - B2 @ sp.diags(inv) @ B1t).toarray()
            S_of[kind] = (inv, S)
            sym = 0.5 * (S + S.T)
            ev = scipy.linalg.eigvalsh(sym)
            diag = np.diag(S)
            L, U = ilu0(S)
            pivots = np.abs(np.diag(U))
            mu = scipy.linalg.eigvals(S_exact, S)  # S^-1 S_exact
            # the rows without a C entry (active normal constraints: linearized weighted gap)
            # against those with one (tangential and inactive rows: tau . lambda, identity)
            mu_n = scipy.linalg.eigvals(S_exact[np.ix_(normal, normal)], S[np.ix_(normal, normal)]) \
                if normal.any() else np.array([np.nan])
            entry.update({
                "min |Â_ii| * a_ii": float(np.min(np.abs(inv * A.diagonal()))),
                "S: zero diagonals": int((diag == 0).sum()),
                "S: |diagonal| min / max on rows without C (normal)":
                    [float(np.abs(diag[normal]).min()), float(np.abs(diag[normal]).max())] if normal.any() else [],
                "S: |diagonal| min / max on rows with C":
                    [float(np.abs(diag[~normal]).min()), float(np.abs(diag[~normal]).max())] if (~normal).any() else [],
                "S: diagonal signs (+/-) on rows without C": [int((diag[normal] > 0).sum()),
                                                              int((diag[normal] < 0).sum())],
                "S^-1 S_exact on the rows without C: real part min / max": [float(mu_n.real.min()),
                                                                             float(mu_n.real.max())],
                "S: diagonal signs (+/-)": [int((diag > 0).sum()), int((diag < 0).sum())],
                "S: symmetric part eigenvalues min / max": [float(ev.min()), float(ev.max())],
                "S: symmetric part eigenvalues (+/-)": [int((ev > 1e-12 * abs(ev).max()).sum()),
                                                        int((ev < -1e-12 * abs(ev).max()).sum())],
                "S: ILU(0) smallest |pivot| / largest": float(pivots.min() / pivots.max()),
                "S^-1 S_exact: eigenvalue real part min / max": [float(mu.real.min()), float(mu.real.max())],
                "S^-1 S_exact: max |imag|": float(np.abs(mu.imag).max()),
                "exact-solve SIMPLE rho(I - omega S^-1 S_exact)":
                    float(np.max(np.abs(1 - args.damping * mu))),
            })
        report["inverse approximations"][kind] = entry

    # --- the level smoother's iteration matrix ---------------------------------------------
    omega = args.damping
    report["smoother"] = []
    for schur in ([] if args.no_smoother else S_of):
        _, S = S_of[schur]
        L, U = ilu0(S)
        corrector = lambda r: scipy.linalg.solve_triangular(U, scipy.linalg.solve_triangular(L, r, lower=True,
                                                                                             unit_diagonal=True))
        for update in ("diagonal", "absolute-row-sum"):
            inv_u, _ = inverse_approximation(A, update)
            for sweeps in args.predictor_sweeps:
                predictor = sgs_operator(A, sweeps, omega)

                def step(e):
                    # error propagation of one sweep: e <- e - M^-1 K e
                    r = K @ e
                    dx1 = predictor(r[:n1])
                    dx2 = corrector(r[n1:] - B2 @ dx1)
                    dx1 = dx1 - inv_u * (B1t @ (omega * dx2))
                    return e - np.concatenate([dx1, omega * dx2])

                rho = spectral_radius(K.shape[0], step)
                report["smoother"].append({"schur inverse": schur, "update inverse": update,
                                           "predictor sweeps": sweeps, "rho(I - M^-1 K)": rho})
                print(f"smoother: S with {schur:17s} update {update:17s} {sweeps} x SGS: rho = {rho:.4g}",
                      flush=True)

    print(json.dumps(report, indent=1))
    if args.json:
        with open(args.json, "w") as f:
            json.dump(report, f, indent=1)


if __name__ == "__main__":
    main()
