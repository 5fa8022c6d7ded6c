"""Tetrahedral meshes as meshio reads them, for the e2e cases (numpy):
cells(m, kind[, key]) -> (cells of that type, their cell data `key`), each
over every block; volumes(p) and circumradii(p) of tetrahedra given as
their corners p[n, 4, 3]."""
import numpy as np


def cells(m, kind, key='gmsh:physical'):
    data = [(c.data, d) for c, d in zip(m.cells, m.cell_data[key]) if c.type == kind]
    return np.concatenate([c for c, _ in data]), np.concatenate([d for _, d in data])


def volumes(p):
    """Signed: (p1 - p0) x (p2 - p0) . (p3 - p0) / 6, positive for positively oriented ones."""
    return np.linalg.det(p[:, 1:] - p[:, :1]) / 6


def circumradii(p):
    e = p[:, 1:] - p[:, :1]  # circumcentre offset x: e x = |e|^2 / 2, row by row
    x = np.linalg.solve(e, 0.5 * (e * e).sum(2)[..., None])[..., 0]
    return np.sqrt((x * x).sum(1))
