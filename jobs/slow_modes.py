#!/usr/bin/env python3
"""What the multigrid's coarse levels miss on a folded sheet (docs/performance.md, "The slow error of a folded sheet").

Reads one implicit system of a hanging-sheet run on 1 rank (its matrix dumped by PETSc, in natural order) and the
checkpoint it was linearised at, makes "algebraically smooth" error by damped point-block Jacobi sweeps on A e = 0
(what a point-block smoother leaves), and measures how much of that error's energy each candidate coarse space of
the pattern grid cannot represent: the A-norm projection error |e - P (P^T A P)^-1 P^T A e|_A^2 / |e|_A^2 (0: the
coarse level removes it entirely, 1: not at all).

  mpiexec -n 1 build/clothsim -scene input/hanging_sheet.yaml -grid 513 -restart run/checkpoint_000048.h5 \\
      -steps 49 -implicit_mat_type baij -ksp_view_mat binary:A.bin -output_dir tmp -output_overwrite
  python3 jobs/slow_modes.py --matrix A.bin --checkpoint run/checkpoint_000048.h5 --grid 513

Coarse spaces (every `--ratio`-th row and column of the grid, bilinear weights, pinned particles left out as
src/gridhierarchy.c does):
  cartesian   the three components interpolated alike (clothsim's pattern-grid multigrid);
  local-frame each fine particle's displacement in its own frame (two tangents and the normal) interpolated from the
              coarse particles' frame components;
  enriched    cartesian plus a fourth coarse unknown per coarse particle: a displacement along the fine normals;
  smoothed-k  cartesian smoothed k times by damped point-block Jacobi, (I - omega D^-1 A)^k P (smoothed aggregation's
              prolongator smoothing);
  ls-fit      (--fit K) the cartesian pattern, each fine particle's 3x3 weight blocks fitted by least squares to K
              further smooth vectors made like the measured ones (bootstrap/adaptive multigrid's interpolation),
              translations reproduced exactly, weights drawn towards bilinear by a ridge term (--ridge).

With --rhs (the same solve's right-hand side, -ksp_view_rhs binary:FILE) each coarse space is also tried as a
two-grid preconditioner of CG: 2 Chebyshev steps on point-block Jacobi (on [0.1, 1.1] x the largest eigenvalue, as
clothsim's smoother) before and after an exact coarse solve, from a zero guess to a relative 1e-5 in the natural
norm; the iterations are printed. A two-grid count is a floor for the same coarse space in a V-cycle.
"""
import argparse
import itertools

import h5py
import numpy as np
import scipy.sparse as sp
import scipy.sparse.linalg as sla

PETSC_MAT_ID, PETSC_VEC_ID = 1211216, 1211214


def read_petsc_matrices(path, count=1):
    """The first count PETSc binary matrices (big-endian, 32-bit indices) of a file, as CSR (-ksp_view_mat appends one
    a solve)."""
    out = []
    with open(path, 'rb') as f:
        for _ in range(count):
            classid, m, n, nnz = np.fromfile(f, dtype='>i4', count=4)
            if classid != PETSC_MAT_ID:
                raise SystemExit(f'{path}: fewer than {count} PETSc binary matrices (class id {classid})')
            lengths = np.fromfile(f, dtype='>i4', count=m)
            cols = np.fromfile(f, dtype='>i4', count=nnz).astype(np.int64)
            vals = np.fromfile(f, dtype='>f8', count=nnz).astype(np.float64)
            out.append(sp.csr_matrix((vals, cols, np.concatenate([[0], np.cumsum(lengths)])), shape=(m, n)))
    return out


def read_petsc_matrix(path):
    return read_petsc_matrices(path)[0]


def grid_frames(x, n):
    """Per particle: tangent along i, tangent along j (orthogonalised) and normal, from central differences."""
    X = x.reshape(n, n, 3)
    du, dv = np.gradient(X, axis=1), np.gradient(X, axis=0)
    normal = np.cross(du, dv)
    normal /= np.linalg.norm(normal, axis=2, keepdims=True)
    t1 = du / np.linalg.norm(du, axis=2, keepdims=True)
    t2 = np.cross(normal, t1)
    return np.stack([t1, t2, normal], axis=3).reshape(n * n, 3, 3)  # columns: t1, t2, n


def block_diagonal_inverse(A):
    """The inverses of A's 3x3 diagonal blocks, (N, 3, 3)."""
    B = sp.bsr_matrix(A, blocksize=(3, 3))
    B.sort_indices()
    rows = np.repeat(np.arange(B.shape[0] // 3), np.diff(B.indptr))
    diag = B.data[B.indices == rows]
    return np.linalg.inv(diag)


def bilinear_weights(n, ratio, pinned):
    """Scalar bilinear weights W (fine x coarse) and each coarse particle's fine index."""
    nc = (n - 1) // ratio + 1 + (1 if (n - 1) % ratio else 0)

    def along(i):
        if i % ratio == 0 or i == n - 1:
            return [(nc - 1 if i == n - 1 else i // ratio, 1.0)]
        a = i // ratio
        f0, f1 = a * ratio, min((a + 1) * ratio, n - 1)
        t = (i - f0) / (f1 - f0)
        return [(a, 1 - t), (a + 1, t)]

    coarse_fine = np.array([min(cj * ratio, n - 1) * n + min(ci * ratio, n - 1) for cj in range(nc) for ci in range(nc)])
    rows, cols, vals = [], [], []
    for j in range(n):
        wj = along(j)
        for i in range(n):
            f, wi = j * n + i, along(i)
            for ci, a in wi:
                for cj, b in wj:
                    c = cj * nc + ci
                    if pinned[f] and len(wi) * len(wj) > 1:
                        continue  # a pinned particle only from a coarse particle on itself
                    if not pinned[f] and pinned[coarse_fine[c]]:
                        continue  # a free one leaves the pinned coarse particles out
                    rows.append(f), cols.append(c), vals.append(a * b)
    return sp.csr_matrix((vals, (rows, cols)), shape=(n * n, nc * nc)), coarse_fine


def block_interpolation(W, blocks):
    """P with the 3x3 block blocks[k] in place of W's k-th stored weight (COO order)."""
    Wc = W.tocoo()
    r = np.arange(3)
    rows = (3 * Wc.row[:, None, None] + r[None, :, None] + 0 * r[None, None, :]).ravel()
    cols = (3 * Wc.col[:, None, None] + 0 * r[None, :, None] + r[None, None, :]).ravel()
    P = sp.csr_matrix((blocks.ravel(), (rows, cols)), shape=(3 * W.shape[0], 3 * W.shape[1]))
    P.eliminate_zeros()
    return P


def coarse_spaces(A, W, coarse_fine, frames, Dinv, omega, smooth_max):
    Wc = W.tocoo()
    eye = np.broadcast_to(np.eye(3), (Wc.nnz, 3, 3))
    cart = block_interpolation(W, eye * Wc.data[:, None, None])
    yield 'cartesian', cart
    local = np.einsum('kab,kcb->kac', frames[Wc.row], frames[coarse_fine[Wc.col]]) * Wc.data[:, None, None]
    yield 'local-frame', block_interpolation(W, local)
    normals = frames[:, :, 2]
    along_normal = sp.csr_matrix(((normals[Wc.row] * Wc.data[:, None]).ravel(),
                                  ((3 * Wc.row[:, None] + np.arange(3)).ravel(), np.repeat(Wc.col, 3))),
                                 shape=(A.shape[0], W.shape[1]))
    yield 'enriched', sp.hstack([cart, along_normal], format='csr')
    N = A.shape[0] // 3
    Dinv_mat = sp.bsr_matrix((Dinv, np.arange(N), np.arange(N + 1)), shape=A.shape).tocsr()
    P = cart
    for k in range(1, smooth_max + 1):
        P = (P - omega * (Dinv_mat @ (A @ P))).tocsr()
        P.eliminate_zeros()
        yield f'smoothed-{k}', P


def least_squares_interpolation(W, coarse_fine, V, ridge):
    """P on W's pattern with 3x3 blocks: fine particle f's blocks B_c minimise sum_k |v_k(f) - sum_c B_c v_k(c)|^2 over
    the smooth vectors V (columns, each scaled to unit energy by the caller) plus ridge^2 |B - bilinear|^2 (scaled),
    with the three translations reproduced exactly (a heavily weighted row each). A coarse particle's own row is
    injection."""
    n_fine = W.shape[0]
    Vp = V.reshape(n_fine, 3, -1)
    Wr = W.tocsr()
    rows, cols, vals = [], [], []
    for f in range(n_fine):
        parents = Wr.indices[Wr.indptr[f]:Wr.indptr[f + 1]]
        weights = Wr.data[Wr.indptr[f]:Wr.indptr[f + 1]]
        m = len(parents)
        if m == 0:
            continue
        if m == 1 and coarse_fine[parents[0]] == f:
            blocks = np.eye(3)[None]
        else:
            X = Vp[coarse_fine[parents]].reshape(3 * m, -1).T  # vectors x (parent, component)
            scale = np.sqrt(np.mean(X ** 2))
            translation = np.tile(np.eye(3), (1, m))
            bilinear = np.hstack([w * np.eye(3) for w in weights])
            lhs = np.vstack([X, 1e2 * scale * translation, ridge * scale * np.eye(3 * m)])
            rhs = np.vstack([Vp[f].T, 1e2 * scale * np.eye(3), ridge * scale * bilinear.T])
            blocks = np.linalg.lstsq(lhs, rhs, rcond=None)[0].T.reshape(3, m, 3).transpose(1, 0, 2)
        for c, block in zip(parents, blocks):
            for a in range(3):
                rows.extend([3 * f + a] * 3)
                cols.extend(3 * c + np.arange(3))
                vals.extend(block[a])
    return sp.csr_matrix((vals, (rows, cols)), shape=(3 * n_fine, 3 * W.shape[1]))


def point_block_jacobi(Dinv):
    """V -> D^-1 V for the columns of V (3 rows a particle)."""
    def apply(V):
        return np.einsum('fab,fbk->fak', Dinv, V.reshape(Dinv.shape[0], 3, -1)).reshape(V.shape)
    return apply


def largest_eigenvalue(A, smoother_apply, seed=1, iterations=30):
    """The largest eigenvalue of D^-1 A by power iteration."""
    v = np.random.default_rng(seed).standard_normal((A.shape[0], 1))
    for _ in range(iterations):
        u = smoother_apply(A @ v)
        lam = np.linalg.norm(u) / np.linalg.norm(v)
        v = u / np.linalg.norm(u)
    return lam


def two_grid_preconditioner(A, P, smoother_apply, lam):
    """r -> B r: 2 Chebyshev steps on point-block Jacobi (on [0.1, 1.1] x lam, as clothsim's smoother: PETSc's
    KSPCHEBYSHEV) before and after an exact solve with P^T A P."""
    lu = sla.splu((P.T @ (A @ P)).tocsc())
    emax, emin = 1.1 * lam, 0.1 * lam
    theta, delta = (emax + emin) / 2, (emax - emin) / 2
    sigma = theta / delta

    def D(r):
        return smoother_apply(r[:, None])[:, 0]

    def chebyshev(rhs, x):
        d = D(rhs - A @ x) / theta
        x = x + d
        rho_new = 1 / (2 * sigma - 1 / sigma)
        return x + rho_new / sigma * d + 2 * rho_new / delta * D(rhs - A @ x)

    def apply(r):
        x = chebyshev(r, np.zeros_like(r))
        return chebyshev(r, x + P @ lu.solve(P.T @ (r - A @ x)))
    return apply


def preconditioned_cg(A, b, B, W=None, rtol=1e-5, maxit=1000):
    """CG preconditioned by B from a zero guess, stopped at rtol relative to B's norm of b; with W (columns), deflated in
    the balancing form (I - Q A) B (I - A Q) + Q, Q = W (W^T A W)^-1 W^T, from the first iterate Q b (after it W^T r = 0,
    so the + Q r term is left out). Returns the iterations and the Lanczos data: the coefficients alpha and
    beta and the vectors z / sqrt(r.z)."""
    reference = np.sqrt(b @ B(b))
    x = np.zeros_like(b)
    if W is not None:
        AW = A @ W
        Einv = np.linalg.inv(W.T @ AW)
        x = W @ (Einv @ (W.T @ b))
        inner = B

        def B(r):
            y = inner(r - AW @ (Einv @ (W.T @ r)))
            return y - W @ (Einv @ (AW.T @ y))
    r = b - A @ x
    z = B(r)
    p, rz = z.copy(), r @ z
    alphas, betas, V = [], [], []
    for it in range(1, maxit + 1):
        V.append(z / np.sqrt(rz))
        Ap = A @ p
        alpha = rz / (p @ Ap)
        alphas.append(alpha)
        x += alpha * p
        r -= alpha * Ap
        z = B(r)
        rz_new = r @ z
        if np.sqrt(abs(rz_new)) < rtol * reference:
            return it, alphas, betas, V
        betas.append(rz_new / rz)
        p = z + betas[-1] * p
        rz = rz_new
    return maxit, alphas, betas, V


def read_petsc_vectors(path, count=1):
    """The first count PETSc binary vectors of a file (-ksp_view_rhs appends one a solve)."""
    out = []
    with open(path, 'rb') as f:
        for _ in range(count):
            classid, n = np.fromfile(f, dtype='>i4', count=2)
            if classid != PETSC_VEC_ID:
                raise SystemExit(f'{path}: fewer than {count} PETSc binary vectors (class id {classid})')
            out.append(np.fromfile(f, dtype='>f8', count=n).astype(np.float64))
    return out


def projection_error(A, P, E):
    """|e - P (P^T A P)^-1 P^T A e|_A^2 / |e|_A^2 per column of E (coarse systems by Jacobi-preconditioned CG)."""
    AP = A @ P
    Ac = (P.T @ AP).tocsr()
    AE = A @ E
    rhs = np.asarray(P.T @ AE)
    diag = Ac.diagonal()
    M = sla.LinearOperator(Ac.shape, matvec=lambda y: y / diag)
    C = np.zeros_like(rhs)
    for k in range(rhs.shape[1]):
        C[:, k], info = sla.cg(Ac, rhs[:, k], tol=1e-10, maxiter=50000, M=M)
        if info:
            print(f'  warning: coarse CG stopped with info {info}')
    R = E - P @ C
    return np.einsum('ij,ij->j', R, A @ R) / np.einsum('ij,ij->j', E, AE)


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument('--matrix', required=True, help='PETSc binary matrix of the implicit system (1 rank, -ksp_view_mat binary:FILE)')
    ap.add_argument('--checkpoint', required=True, help='the checkpoint the system was linearised at (state/position)')
    ap.add_argument('--grid', type=int, required=True, help='particles per side of the square sheet')
    ap.add_argument('--pins', default='0,-1', help='pinned grid indices i on the edge j = 0 (hanging sheet: 0,-1)')
    ap.add_argument('--ratio', type=int, default=4, help='coarsening ratio (clothsim: -implicit_pc_grid_ratio, 4)')
    ap.add_argument('--vectors', type=int, default=8, help='random starts of smooth error')
    ap.add_argument('--sweeps', type=int, default=300, help='damped point-block Jacobi sweeps')
    ap.add_argument('--smooth', type=int, default=2, help='prolongator smoothings to try')
    ap.add_argument('--seed', type=int, default=1)
    ap.add_argument('--fit', type=int, default=0, help='also the least-squares fitted interpolation from this many more smooth vectors (0: not)')
    ap.add_argument('--ridge', type=float, default=0.1, help='ls-fit: weight of the pull towards the bilinear weights')
    ap.add_argument('--skip', default='', help='coarse spaces to leave out, comma-separated (e.g. enriched: singular where the sheet is flat)')
    ap.add_argument('--rhs', help='the solve\'s right-hand side (-ksp_view_rhs binary:FILE): also two-grid CG iterations per coarse space')
    args = ap.parse_args()

    n = args.grid
    A = read_petsc_matrix(args.matrix)
    if A.shape[0] != 3 * n * n:
        raise SystemExit(f'{args.matrix}: {A.shape[0]} rows, expected 3 x {n}^2 = {3 * n * n} (--grid {n}, 1 rank)')
    with h5py.File(args.checkpoint, 'r') as f:
        x = f['state/position'][:]
    pinned = np.zeros(n * n, bool)
    for i in map(int, args.pins.split(',')):
        pinned[i % n] = True
    frames = grid_frames(x, n)
    Dinv = block_diagonal_inverse(A)

    smoother_apply = point_block_jacobi(Dinv)
    lam = largest_eigenvalue(A, smoother_apply, args.seed)
    rng = np.random.default_rng(args.seed)
    rng.standard_normal((A.shape[0], 1))  # the power iteration's start: the same random errors as before
    E = rng.standard_normal((A.shape[0], args.vectors + args.fit))
    E[np.repeat(pinned, 3)] = 0
    for _ in range(args.sweeps):
        E -= smoother_apply(A @ E) / (1.05 * lam)
    E, F = E[:, :args.vectors], E[:, args.vectors:]  # measured / fitted to: the fit is judged on vectors it has not seen
    D_norm = np.einsum('ij,ij->j', E, np.einsum('fab,fbk->fak', np.linalg.inv(Dinv), E.reshape(n * n, 3, -1)).reshape(E.shape))
    rayleigh = np.einsum('ij,ij->j', E, A @ E) / D_norm / lam
    En = E.reshape(n * n, 3, -1)
    normal_part = np.einsum('fc,fck->fk', frames[:, :, 2], En)
    normal_share = (normal_part ** 2).sum(0) / (En ** 2).sum((0, 1))
    w = normal_part[:, 0].reshape(n, n)

    def autocorrelation(axis, lag):
        a, b = np.take(w, range(0, n - lag), axis=axis), np.take(w, range(lag, n), axis=axis)
        return (a * b).sum() / np.sqrt((a * a).sum() * (b * b).sum())

    print(f'system: {n} x {n} particles, {A.nnz} stored entries; largest eigenvalue of D^-1 A {lam:.3f}')
    print(f'smooth error after {args.sweeps} sweeps: Rayleigh quotient / lambda_max {np.median(rayleigh):.2e}; '
          f'share along the normals {normal_share.min():.3f}-{normal_share.max():.3f}')
    lags = (1, 2, 4, 8, 16)
    print('normal part, autocorrelation at lags', lags, 'along i:', [round(autocorrelation(1, l), 2) for l in lags],
          'along j:', [round(autocorrelation(0, l), 2) for l in lags])
    W, coarse_fine = bilinear_weights(n, args.ratio, pinned)
    b = read_petsc_vectors(args.rhs)[0] if args.rhs else None
    spaces = coarse_spaces(A, W, coarse_fine, frames, Dinv, 1.0 / lam, args.smooth)
    if args.fit:
        F = F / np.sqrt(np.einsum('ij,ij->j', F, A @ F))
        spaces = itertools.chain(spaces, [('ls-fit', least_squares_interpolation(W, coarse_fine, F, args.ridge))])
    print(f'{"coarse space":<12} {"columns":>8} {"nnz/row":>8}  energy left unrepresented (median, max)'
          + ('  two-grid CG its' if b is not None else ''))
    skip = set(args.skip.split(',')) - {''}
    for name, P in spaces:
        if name in skip:
            continue
        err = projection_error(A, P, E)
        its = f'  {preconditioned_cg(A, b, two_grid_preconditioner(A, P, smoother_apply, lam))[0]}' if b is not None and name != 'enriched' else ''
        print(f'{name:<12} {P.shape[1]:>8} {P.nnz / P.shape[0]:>8.1f}  {np.median(err):.3f}  {err.max():.3f}{its}', flush=True)


if __name__ == '__main__':
    main()
