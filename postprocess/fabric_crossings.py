"""The fabric's self-intersection test, shared by the postprocess tools and the tests: no fabric edge may cross
a fabric triangle.

The fabric surface is every grid cell (quad a b c d of /topology/quads) split into the triangles (a b c)
and (a c d); its edges are the cell sides and that diagonal, as in src/selfcontact.c. An edge and a
triangle that share a particle are not tested (they meet at it by construction). The segment-triangle
test is Moeller-Trumbore's (1997) on the closed segment and triangle; an edge lying in the triangle's
plane (to 1e-14 relative) is not counted as a crossing.

Used by postprocess/garment_quality.py (fabric_crossings in quality.json) and by the self-collision tests'
checker tests/checkers/check_self_intersection.py."""
import numpy as np


def primitives(quads):
    tris = np.concatenate([quads[:, [0, 1, 2]], quads[:, [0, 2, 3]]])
    edges = np.concatenate([quads[:, [0, 1]], quads[:, [1, 2]], quads[:, [2, 3]], quads[:, [3, 0]], quads[:, [0, 2]]])
    edges = np.unique(np.sort(edges, axis=1), axis=0)
    return tris, edges


def candidate_pairs(x, tris, edges, joined=None):
    """Edge-triangle pairs whose bounding boxes overlap and that share no particle; `joined` (optional,
    sorted int64 codes a * N + b of particle pairs, both orders) lists pairs that count as one particle."""
    tlo, thi = x[tris].min(axis=1), x[tris].max(axis=1)
    elo, ehi = x[edges].min(axis=1), x[edges].max(axis=1)
    pairs = []
    chunk = max(1, 2_000_000 // max(1, len(tris)))
    for start in range(0, len(edges), chunk):
        stop = min(start + chunk, len(edges))
        overlap = np.all((elo[start:stop, None, :] <= thi[None, :, :]) & (ehi[start:stop, None, :] >= tlo[None, :, :]), axis=2)
        e, t = np.nonzero(overlap)
        e += start
        shared = np.zeros(len(e), dtype=bool)
        for a in range(2):
            for b in range(3):
                shared |= edges[e, a] == tris[t, b]
                if joined is not None and len(joined):
                    shared |= np.isin(edges[e, a] * len(x) + tris[t, b], joined, assume_unique=False)
        pairs.append((e[~shared], t[~shared]))
    return np.concatenate([p[0] for p in pairs]), np.concatenate([p[1] for p in pairs])


def crossings(x, tris, edges, examples=5, joined=None):
    """The number of edge-triangle crossings and up to `examples` of them as (edge, triangle) particle lists."""
    e, t = candidate_pairs(x, tris, edges, joined)
    p0, p1 = x[edges[e, 0]], x[edges[e, 1]]
    v0, v1, v2 = x[tris[t, 0]], x[tris[t, 1]], x[tris[t, 2]]
    d, e1, e2 = p1 - p0, v1 - v0, v2 - v0
    h = np.cross(d, e2)
    a = np.einsum("ij,ij->i", e1, h)
    scale = np.linalg.norm(d, axis=1) * np.linalg.norm(e1, axis=1) * np.linalg.norm(e2, axis=1)
    ok = np.abs(a) > 1e-14 * np.maximum(scale, 1e-300)
    f = np.where(ok, 1.0 / np.where(ok, a, 1.0), 0.0)
    s = p0 - v0
    u = f * np.einsum("ij,ij->i", s, h)
    q = np.cross(s, e1)
    v = f * np.einsum("ij,ij->i", d, q)
    tt = f * np.einsum("ij,ij->i", e2, q)
    hit = ok & (u >= 0) & (v >= 0) & (u + v <= 1) & (tt >= 0) & (tt <= 1)
    return int(hit.sum()), list(zip(edges[e[hit]].tolist(), tris[t[hit]].tolist()))[:examples]
