"""``isotween info FILE``: what a shape or sequence file holds."""

import click
import numpy as np

from ..paint import sequence_paint


def shape_lines(shape):
    """Vertices, edges, faces, components and bounding box, one line each."""
    v = shape.vertices
    if len(v):
        (x0, y0), (x1, y1) = v.min(axis=0), v.max(axis=0)
        box = f"x {x0:.6g} .. {x1:.6g}, y {y0:.6g} .. {y1:.6g} (diagonal {shape.bbox_diagonal():.6g})"
    else:
        box = "empty"
    lines = [
        f"vertices: {shape.n_vertices}",
        f"edges: {shape.n_edges}",
        f"faces: {shape.n_faces}",
        f"components: {shape.n_components}",
        f"bounding box: {box}",
    ]
    if shape.paths is not None:
        closed = sum(1 for _, c in shape.paths if c)
        lines.append(f"paths: {len(shape.paths)} ({closed} closed, {len(shape.paths) - closed} open)")
    if shape.uv is not None:
        lines.append("uv: yes")
    if shape.paint is not None:
        fills = sorted({_hex(p.fill) for p in shape.paint if p.fill is not None})
        lines.append(f"paint: {len(shape.regions or [])} region(s), fills {', '.join(fills) or 'none'}")
    return lines


def _hex(colour):
    return "#" + "".join(f"{round(255 * c):02x}" for c in colour[:3])


def sequence_lines(seq):
    """Frames and how the sequence was made, then its shape (frame 0)."""
    energy = f"{seq.energy[-1]:.6g}" if len(seq.energy) else "n/a"
    lines = [
        f"frames: {len(seq)}",
        f"method: {seq.method}",
        f"scheme: {seq.scheme}",
        f"iterations: {seq.iterations}",
        f"converged: {'yes' if seq.converged else 'no'}",
        f"energy: {energy}",
    ]
    _, paints = sequence_paint(seq)
    if paints is not None and len(paints):
        ends = [sorted({_hex(p.fill) for p in frame if p.fill is not None}) for frame in (paints[0], paints[-1])]
        lines.append(f"paint: fills {', '.join(ends[0]) or 'none'} -> {', '.join(ends[1]) or 'none'} (Oklab blend)")
    frames = seq.frames.reshape(-1, 2) if seq.frames.size else np.zeros((0, 2))
    lines += shape_lines(seq[0]) if len(seq) else []
    if len(frames):
        (x0, y0), (x1, y1) = frames.min(axis=0), frames.max(axis=0)
        lines.append(f"bounding box (all frames): x {x0:.6g} .. {x1:.6g}, y {y0:.6g} .. {y1:.6g}")
    return lines


@click.command("info")
@click.argument("file")
def info_command(file):
    """Print what FILE holds: vertices, edges, faces, components, bounding box.

    FILE is a shape (.obj .off .svg .json .npz), a sequence file (.npz .json
    with frames) or a folder of frame files.
    """
    from ..io import is_sequence_file, load, load_sequence

    lines = sequence_lines(load_sequence(file)) if is_sequence_file(file) else shape_lines(load(file))
    click.echo("\n".join(lines))
