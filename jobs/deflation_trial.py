#!/usr/bin/env python3
"""Would the slow modes of one step's solve speed up the next? (docs/performance.md, "Recycling, fitted
interpolation, patches and warm starts").

Reads two consecutive implicit systems of a hanging-sheet run on 1 rank (both matrices in one PETSc binary file, both
right-hand sides in another, as -ksp_view_mat / -ksp_view_rhs write them over two steps), preconditions each by the
two-grid method of jobs/slow_modes.py (cartesian bilinear interpolation of --ratio, 2 Chebyshev steps on point-block
Jacobi around an exact coarse solve), and solves both by CG from a zero guess to a relative 1e-5. From the first
solve's Lanczos process it takes the Ritz vectors of the k smallest Ritz values of B A (B the preconditioner), the
modes the two-grid method converges slowest, and solves again with them deflated (the balancing form
(I - Q A) B (I - A Q) + Q, Q = W (W^T A W)^-1 W^T, and the first iterate W (W^T A W)^-1 W^T b):
  same system  the first system again: what deflation of exact slow modes can give;
  next system  the second: what recycling them one step later gives (Krylov subspace recycling, deflated CG).

  mpiexec -n 1 build/clothsim -scene input/hanging_sheet.yaml -grid 513 -restart run/checkpoint_000048.h5 \\
      -steps 50 -implicit_mat_type baij -ksp_view_mat binary:A2.bin -ksp_view_rhs binary:b2.bin -output_dir tmp
  python3 jobs/deflation_trial.py --matrices A2.bin --rhs b2.bin --grid 513
"""
import argparse

import numpy as np

from slow_modes import (bilinear_weights, block_diagonal_inverse, block_interpolation, largest_eigenvalue,
                        point_block_jacobi, preconditioned_cg, read_petsc_matrices, read_petsc_vectors,
                        two_grid_preconditioner)


def two_grid(A, P):
    """The two-grid preconditioner of jobs/slow_modes.py for A."""
    smoother_apply = point_block_jacobi(block_diagonal_inverse(A))
    return two_grid_preconditioner(A, P, smoother_apply, largest_eigenvalue(A, smoother_apply, seed=5))


def smallest_ritz_vectors(alphas, betas, V, k):
    """Ritz values and vectors of B A from CG's Lanczos tridiagonal matrix."""
    m = len(alphas)
    T = np.zeros((m, m))
    for j in range(m):
        T[j, j] = 1 / alphas[j] + (betas[j - 1] / alphas[j - 1] if j > 0 else 0)
        if j + 1 < m:
            T[j, j + 1] = T[j + 1, j] = -np.sqrt(betas[j]) / alphas[j]
    values, Q = np.linalg.eigh(T)
    return values[:k], np.array(V[:m]).T @ Q[:, :k]


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument('--matrices', required=True, help='two consecutive systems, -ksp_view_mat binary:FILE over 2 steps (1 rank)')
    ap.add_argument('--rhs', required=True, help='their right-hand sides, -ksp_view_rhs binary:FILE')
    ap.add_argument('--grid', type=int, required=True, help='particles per side of the square sheet')
    ap.add_argument('--ratio', type=int, default=4, help='coarsening ratio of the two-grid method')
    ap.add_argument('--k', default='5,10,20,40', help='numbers of Ritz vectors to deflate')
    args = ap.parse_args()
    n = args.grid
    systems = list(zip(read_petsc_matrices(args.matrices, 2), read_petsc_vectors(args.rhs, 2)))
    pinned = np.zeros(n * n, bool)
    pinned[0] = pinned[n - 1] = True
    W, _ = bilinear_weights(n, args.ratio, pinned)
    Wc = W.tocoo()
    P = block_interpolation(W, np.broadcast_to(np.eye(3), (Wc.nnz, 3, 3)) * Wc.data[:, None, None])
    precs = [two_grid(A, P) for A, _ in systems]
    first = preconditioned_cg(*systems[0], precs[0])
    second = preconditioned_cg(*systems[1], precs[1])
    print(f'two-grid CG, ratio {args.ratio}: {first[0]} iterations (first system), {second[0]} (next system)')
    ks = [int(k) for k in args.k.split(',')]
    values, Y = smallest_ritz_vectors(*first[1:], max(ks))
    print('smallest Ritz values of B A:', ' '.join(f'{v:.4f}' for v in values[:10]))
    for k in ks:
        same = preconditioned_cg(*systems[0], precs[0], Y[:, :k])[0]
        following = preconditioned_cg(*systems[1], precs[1], Y[:, :k])[0]
        print(f'{k:>3} Ritz vectors deflated: same system {same}, next system {following}', flush=True)


if __name__ == '__main__':
    main()
