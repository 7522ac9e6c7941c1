"""Test shapes with known exact motions."""

import numpy as np

from isotween import Shape


def rotation(deg):
    a = np.deg2rad(deg)
    return np.array([[np.cos(a), -np.sin(a)], [np.sin(a), np.cos(a)]])


def ellipse(k=16, a=2.0, b=1.0):
    th = np.linspace(0, 2 * np.pi, k, endpoint=False)
    return Shape.from_polygon(np.c_[a * np.cos(th), b * np.sin(th)] + 0.1 * np.c_[np.cos(3 * th), 0 * th])


def grid_mesh(nx, ny, length=4.0, width=1.0):
    """Triangulated bar [0, length] x [0, width] with nx x ny vertices."""
    x, y = np.meshgrid(np.linspace(0, length, nx), np.linspace(0, width, ny), indexing="ij")
    v = np.c_[x.ravel(), y.ravel()]
    idx = np.arange(nx * ny).reshape(nx, ny)
    a, b, c, d = idx[:-1, :-1].ravel(), idx[1:, :-1].ravel(), idx[1:, 1:].ravel(), idx[:-1, 1:].ravel()
    faces = np.vstack([np.c_[a, b, c], np.c_[a, c, d]])
    return Shape.from_mesh(v, faces)


def bend(vertices, angle, length=None):
    """Bend a bar lying along x into an arc of `angle` radians (centre line kept)."""
    x, y = vertices[:, 0], vertices[:, 1]
    length = length or x.max()
    mid = 0.5 * (y.min() + y.max())
    R = length / angle
    r = R - (y - mid)
    return np.c_[r * np.sin(x / R), R - r * np.cos(x / R) + mid]


def chain(n, turns):
    """Straight chain and the same chain curled into an arc of `turns` turns, with equal edge lengths in both."""
    total = 2 * np.pi * turns
    step = total / (n - 1)
    R = 1.0
    s = np.arange(n) * step
    curled = np.c_[R * np.sin(s), R * (1 - np.cos(s))]
    chord = 2 * R * np.sin(step / 2)
    straight = np.c_[np.arange(n) * chord, np.zeros(n)]
    return Shape.from_polyline(straight), Shape.from_polyline(curled)
