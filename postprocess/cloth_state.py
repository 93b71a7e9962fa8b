"""Shared helpers of the postprocess tools: read a clothsim checkpoint, an XDMF series and a scene.

Positions come from /state/position, shape (N, 3), in global (natural) particle order: pieces in scene
order, each row by row (docs/checkpoint.md, docs/model.md section 1). Grid sizes come from the scene (or its
-grid override).
A series NAME.h5 holds one group /frames/NNNNNN per frame (docs/checkpoint.md "XDMF series").
"""
import csv
import os
import sys

import h5py
import numpy as np
import yaml


def _tool():
    return os.path.basename(sys.argv[0]) or "postprocess"


def series_h5(path):
    """NAME.h5 of a series given as NAME.xdmf or NAME.h5."""
    root, ext = os.path.splitext(path)
    h5 = root + ".h5" if ext.lower() in (".xdmf", ".xmf") else path
    if not os.path.exists(h5):
        raise SystemExit(f"{_tool()}: {h5} not found (give the .xdmf or .h5 of a clothsim output series)")
    return h5


def read_series(h5path, datasets=("position", "velocity"), attributes=()):
    """Frames sorted by step, each a dict of step, time, the named datasets (float arrays) and the named
    attributes of its group; and the quads (M, 4). A frame without one of them is an error."""
    frames = []
    with h5py.File(h5path, "r") as f:
        if "frames" not in f or "topology" not in f or "quads" not in f["topology"]:
            raise SystemExit(f"{_tool()}: {h5path} has no /frames or /topology/quads: not a clothsim series")
        for name in f["frames"]:
            g = f["frames"][name]
            frame = {"step": int(g.attrs["step"]) if "step" in g.attrs else int(name),
                     "time": float(g.attrs["time"]) if "time" in g.attrs else float("nan")}
            missing = [d for d in datasets if d not in g] + [a for a in attributes if a not in g.attrs]
            if missing:
                raise SystemExit(f"{_tool()}: {h5path}:/frames/{name} has no {', '.join(missing)} "
                                 "(written by an older clothsim?)")
            frame.update({d: np.asarray(g[d][...], float) for d in datasets})
            frame.update({a: g.attrs[a].item() for a in attributes})
            frames.append(frame)
        quads = np.asarray(f["topology/quads"][...], dtype=np.int64)
    frames.sort(key=lambda fr: fr["step"])
    if not frames:
        raise SystemExit(f"{_tool()}: {h5path} has no frames")
    return frames, quads


def write_csv(path, rows):
    """rows (a list of dicts with the same keys) as a CSV table; floats in full precision (repr)."""
    with open(path, "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=list(rows[0].keys()))
        w.writeheader()
        for r in rows:
            w.writerow({k: repr(v) if isinstance(v, float) else v for k, v in r.items()})


def finish_axis(ax, ylabel, xlabel=None, title=None):
    """Labels, legend and grid of one panel of a time-series figure."""
    if xlabel:
        ax.set_xlabel(xlabel)
    ax.set_ylabel(ylabel)
    ax.legend(fontsize=8)
    ax.grid(alpha=0.3)
    if title:
        ax.set_title(title, fontsize=10)


def save_figure(fig, out):
    fig.tight_layout()
    fig.savefig(out, dpi=100)
    import matplotlib.pyplot as plt
    plt.close(fig)


def read_positions(path):
    """Final positions (N, 3) from a checkpoint, or from the last frame of an XDMF .h5 series."""
    with h5py.File(path, "r") as f:
        if "state" in f and "position" in f["state"]:
            return np.asarray(f["state/position"][...], dtype=float)
        if "frames" in f and len(f["frames"]):
            last = sorted(f["frames"].keys())[-1]
            return np.asarray(f["frames"][last]["position"][...], dtype=float)
    raise SystemExit(f"{path}: no /state/position dataset (expected a clothsim checkpoint)")


def read_speed(path):
    """Largest particle speed in a checkpoint (m/s), or None when it has no velocities."""
    with h5py.File(path, "r") as f:
        if "state" in f and "velocity" in f["state"]:
            return float(np.max(np.linalg.norm(f["state/velocity"][...], axis=1)))
    return None


def projection_basis(scene):
    """Two orthonormal vectors spanning the plane normal to gravity (the 'floor')."""
    g = np.asarray(scene.get("gravity", [0, -9.81, 0]), dtype=float)
    g /= np.linalg.norm(g)
    helper = np.array([1.0, 0, 0]) if abs(g[0]) < 0.9 else np.array([0, 1.0, 0])
    e1 = np.cross(g, helper)
    e1 /= np.linalg.norm(e1)
    return e1, np.cross(g, e1), g


def read_scene(path):
    with open(path) as f:
        return yaml.safe_load(f)


def piece_grids(scene, grid_override=None):
    """[(name, nu, nv, offset)] in scene order: the natural particle numbering (src/model.c), piece by piece,
    each row by row (i fastest), so particle offset + j * nu + i is node (i, j) of the piece. grid_override is
    the run's -grid N (one-piece scenes). The one implementation of the numbering in postprocess/: energy.py,
    garment_quality.py and the validation scripts use it. KeyError for a piece with neither grid nor
    boundaries nodes."""
    out, offset = [], 0
    for piece in scene["pieces"]:
        if "grid" in piece:
            nu, nv = piece["grid"]
        else:
            nodes = piece["boundaries"]["nodes"]
            nu, nv = nodes[0], nodes[1]
        if grid_override:
            nu = nv = grid_override
        out.append((piece.get("name", ""), nu, nv, offset))
        offset += nu * nv
    return out


def particle_name(grids, g):
    """"piece (i, j)": the piece and grid node of natural particle g, for grids = piece_grids(...)."""
    for name, nu, nv, offset in grids:
        if offset <= g < offset + nu * nv:
            return f"{name} ({(g - offset) % nu}, {(g - offset) // nu})"
    raise IndexError(f"particle {g} is beyond the {grids[-1][3] + grids[-1][1] * grids[-1][2] if grids else 0} particles of the pieces")


def piece_positions(x, nu, nv, offset):
    """Positions of one piece as an array (nv, nu, 3): [j, i] is particle (i, j)."""
    return x[offset:offset + nu * nv].reshape(nv, nu, 3)
