"""Shared helpers of the postprocess tools: read a clothsim checkpoint (or XDMF .h5 frame) and a scene.

Positions come from /state/position, shape (N, 3), in global (natural) particle order: pieces in scene
order, each row by row (DESIGN.md "Files written"). Grid sizes come from the scene (or its -grid override).
"""
import h5py
import numpy as np
import yaml


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
    """[(name, nu, nv, offset)] in scene order; grid_override is the run's -grid N (one-piece scenes)."""
    out, offset = [], 0
    for piece in scene["pieces"]:
        if "grid" in piece:
            nu, nv = piece["grid"]
        else:
            nodes = piece["boundaries"]["nodes"]
            nu, nv = nodes[0], nodes[1]
        if grid_override:
            nu = nv = grid_override
        out.append((piece["name"], nu, nv, offset))
        offset += nu * nv
    return out


def piece_positions(x, nu, nv, offset):
    """Positions of one piece as an array (nv, nu, 3): [j, i] is particle (i, j)."""
    return x[offset:offset + nu * nv].reshape(nv, nu, 3)
