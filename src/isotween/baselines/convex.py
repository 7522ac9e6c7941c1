"""Fold-free morph of triangulated solids by convex-combination weights.

Floater and Gotsman 1999 ("How to morph tilings injectively"); Surazhsky and
Gotsman 2001 ("Guaranteed intersection-free polygon morphing"):

1. Every connected component of the faces (a filled region with its holes)
   is completed into a triangulated disc with a fixed convex boundary: the
   region's exterior inside a 32-gon around both shapes, and every hole,
   are meshed compatibly in source and target
   (`isotween.correspondence.compatible_mesh.compatible_meshes`) and glued
   to the region along its rings. The target is first brought to the
   source by the best rotation and translation (least squares), which is
   put back, interpolated, in every frame.
2. Every vertex off the 32-gon is a convex combination of its neighbours,
   with normalised mean-value weights (Floater 2003), in each shape.
3. At time t the weights are blended linearly; the sparse linear system
   (32-gon fixed) then has a unique solution that is an embedding (Tutte's
   theorem as extended by Floater), so no triangle flips and no ring
   crosses itself or another ring of its region, in any frame.

Only the input vertices are returned; the first and the last frame are the
inputs exactly. ``info``: ``components`` (per component: ``vertices``,
``faces`` of the completed disc, ``rotation`` in radians).
"""

import numpy as np
from scipy.sparse import coo_matrix, identity
from scipy.sparse.csgraph import connected_components
from scipy.sparse.linalg import splu

from ..errors import IncompatibleShapesError, IsotweenError, MethodError

__all__ = ["interpolate", "SIDES"]

SIDES = 32  # vertices of the fixed convex boundary (a regular polygon)
MARGIN = 1.5  # its radius over the largest distance of a ring vertex from its centre


def interpolate(source, target, t):
    """Frames of the convex-combination morph.

    Parameters
    ----------
    source, target : Shape
        Compatible triangle meshes, every vertex in a face, no target
        triangle flipped against the source.
    t : (F,) float
        Frame times, 0 first and 1 last.

    Returns
    -------
    frames : (F, n) complex
    info : dict

    Raises
    ------
    MethodError
        No faces, vertices in no face (polylines), a target triangle flipped
        against the source, a vertex where two boundary loops meet, or a
        component whose exterior or holes cannot be meshed compatibly (the
        message names the component and why).
    """
    if source.faces is None or not len(source.faces):
        raise MethodError("method 'convex' needs solid regions (a triangle mesh); the shapes have no faces")
    f = source.faces
    loose = np.setdiff1d(np.arange(source.n_vertices), f)
    if loose.size:
        raise MethodError(f"method 'convex' needs solid regions: {loose.size} vertex(es) lie in no face "
                          f"(open polylines or outlines), first: vertex {loose[0]}")
    zs, zt = source.z, target.z
    a_s, a_t = _areas(zs, f), _areas(zt, f)
    if np.any(a_s == 0):
        raise MethodError(f"method 'convex': triangle {np.flatnonzero(a_s == 0)[0]} of the source has zero area")
    bad = np.flatnonzero(np.sign(a_s) != np.sign(a_t))
    if bad.size:
        raise MethodError(f"method 'convex' needs two valid meshes: {bad.size} target triangle(s) are flipped "
                          f"against the source, first: triangle {bad[0]} {f[bad[0]].tolist()}")
    f = np.where((a_s < 0)[:, None], f[:, ::-1], f)  # counter-clockwise in the source (and target)
    t = np.asarray(t, dtype=np.float64)
    frames = np.empty((len(t), len(zs)), dtype=complex)
    n_comp, label = connected_components(
        coo_matrix((np.ones(2 * len(f)), (f[:, [0, 1]].ravel(), f[:, [1, 2]].ravel())),
                   shape=(len(zs),) * 2), directed=False)
    info = {"components": []}
    for c in range(n_comp):
        verts = np.flatnonzero(label == c)
        local = np.full(len(zs), -1)
        local[verts] = np.arange(len(verts))
        fc = local[f[label[f[:, 0]] == c]]
        try:
            z, extra = _component(zs[verts], zt[verts], fc, t)
        except IsotweenError as exc:
            raise MethodError(f"method 'convex', component {c} (vertex {verts[0]} ...): {exc}") from None
        frames[:, verts] = z
        info["components"].append(extra)
    frames[0], frames[-1] = zs, zt  # the inputs exactly
    return frames, info


def _component(zs, zt, f, t):
    """(F, n) complex frames of one component; see `interpolate`."""
    loops = _boundary_loops(f, len(zs))
    outer = int(np.argmax([abs(_ring_area(zs[p])) for p in loops]))
    loops = [loops[outer]] + loops[:outer] + loops[outer + 1:]
    cs, ct = zs.mean(), zt.mean()
    rot = np.sum(np.conj(zs - cs) * (zt - ct))
    theta = float(np.angle(rot)) if abs(rot) > 0 else 0.0
    za = (zt - ct) * np.exp(-1j * theta) + cs  # the target brought to the source rigidly
    ring = loops[0]
    radius = MARGIN * max(np.abs(zs[ring] - cs).max(), np.abs(za[ring] - cs).max())
    circle = cs + radius * np.exp(2j * np.pi * np.arange(SIDES) / SIDES)
    # the completed disc: component vertices, then the 32-gon, then the added interior vertices
    ws, wa, faces = [zs], [za], [f]
    count = len(zs) + SIDES
    ws.append(circle)
    wa.append(circle)
    boundary = np.arange(len(zs), count)
    pieces = [(np.r_[boundary, ring], [circle, zs[ring]], [circle, za[ring]])]
    pieces += [(p, [zs[p]], [za[p]]) for p in loops[1:]]
    for given, rs, ra in pieces:
        ms, ma = _mesh(rs, ra)
        k = len(given)
        extra = ms.n_vertices - k
        index = np.r_[given, count + np.arange(extra)]
        faces.append(index[ms.faces])
        ws.append(ms.z[k:])
        wa.append(ma.z[k:])
        count += extra
    ws, wa, faces = np.concatenate(ws), np.concatenate(wa), np.vstack(faces)
    Ws, Wa = _weights(ws, faces), _weights(wa, faces)
    free = np.setdiff1d(np.arange(count), boundary)
    out = np.empty((len(t), len(zs)), dtype=complex)
    eye = identity(len(free), format="csc")
    As, Aa = Ws[free][:, free], Wa[free][:, free]
    bs, ba = Ws[free][:, boundary] @ circle, Wa[free][:, boundary] @ circle
    for k, tk in enumerate(t):
        A = (eye - (1 - tk) * As - tk * Aa).tocsc()  # blended convex-combination weights
        b = (1 - tk) * bs + tk * ba
        sol = splu(A).solve(np.c_[b.real, b.imag])
        z = sol[:len(zs), 0] + 1j * sol[:len(zs), 1]  # free starts with the component's vertices
        out[k] = (z - cs) * np.exp(1j * tk * theta) + cs + tk * (ct - cs)  # rigid part, interpolated
    return out, {"vertices": int(count), "faces": int(len(faces)), "rotation": theta}


def _mesh(rings_s, rings_a):
    """Compatible meshes of corresponding rings (complex arrays); ring vertices kept first."""
    from ..correspondence.compatible_mesh import compatible_meshes

    def xy(rings):
        return [np.c_[r.real, r.imag] for r in rings]

    try:
        ms, ma, _ = compatible_meshes(xy(rings_s), xy(rings_a))
    except IncompatibleShapesError as exc:
        raise MethodError(str(exc)) from None
    k = sum(len(r) for r in rings_s)
    if not (np.array_equal(ms.z[:k], np.concatenate(rings_s)) and np.array_equal(ma.z[:k], np.concatenate(rings_a))):
        raise MethodError("the completing mesh moved a ring vertex; the pieces cannot be glued")
    return ms, ma


def _boundary_loops(f, n):
    """Boundary loops of counter-clockwise faces f (F, 3), each a (k,) int array in order.

    Raises
    ------
    MethodError
        Two boundary loops meet at a vertex, or an edge has more than two faces.
    """
    half = np.stack([f, np.roll(f, -1, axis=1)], axis=-1).reshape(-1, 2)
    key = half[:, 0] * n + half[:, 1]
    twin = half[:, 1] * n + half[:, 0]
    if len(np.unique(key)) < len(key):
        raise MethodError("an edge is shared by more than two triangles (or two with the same orientation)")
    side = half[~np.isin(key, twin)]
    start, count = np.unique(side[:, 0], return_counts=True)
    if np.any(count > 1):
        raise MethodError(f"two boundary loops meet at vertex {start[count > 1][0]}")
    # list ranking by pointer doubling: the steps from each loop's first vertex
    pos = np.full(n, -1)
    pos[start] = np.arange(len(start))
    succ = np.empty(len(start), dtype=np.int64)
    succ[pos[side[:, 0]]] = pos[side[:, 1]]
    _, label = connected_components(
        coo_matrix((np.ones(len(succ)), (np.arange(len(succ)), succ)), shape=(len(succ),) * 2), directed=False)
    _, root = np.unique(label, return_index=True)
    jump = np.empty_like(succ)
    jump[succ] = np.arange(len(succ))  # the predecessor
    jump[root] = root
    rank = np.ones(len(succ), dtype=np.int64)
    rank[root] = 0
    while np.any(jump != jump[jump]):
        rank += rank[jump]
        jump = jump[jump]
    order = np.lexsort((rank, label))
    return np.split(start[order], np.cumsum(np.bincount(label))[:-1])


def _ring_area(z):
    return 0.5 * np.sum((np.conj(z) * np.roll(z, -1)).imag)


def _areas(z, f):
    a, b, c = z[f[:, 0]], z[f[:, 1]], z[f[:, 2]]
    return 0.5 * (np.conj(b - a) * (c - a)).imag


def _weights(z, f):
    """(N, N) sparse normalised mean-value weights (Floater 2003): rows sum to 1.

    For the corner at vertex i of a triangle (i, j, k) with angle a,
    w_ij += tan(a/2) / |z_j - z_i| and w_ik += tan(a/2) / |z_k - z_i|.
    """
    N = len(z)
    i, j, k = f.ravel(), np.roll(f, -1, axis=1).ravel(), np.roll(f, -2, axis=1).ravel()
    dj, dk = z[j] - z[i], z[k] - z[i]
    half = np.tan(np.abs(np.angle(dk / dj)) / 2)
    rows, cols = np.r_[i, i], np.r_[j, k]
    w = np.r_[half / np.abs(dj), half / np.abs(dk)]
    total = np.bincount(rows, weights=w, minlength=N)
    total[total == 0] = 1
    return coo_matrix((w / total[rows], (rows, cols)), shape=(N, N)).tocsr()
