"""K-means zoning (Herraz et al., C4DO1D step 1) and connected zones (Herraz Sec. 2.3).

Features (Herraz Sec. 2.1, Eq. 1): the 4D vector (u, v, s, theta) per mesh cell, compared by
the Euclidean distance. theta is an axial angle (a feed direction and its opposite are the
same feed), so it enters as the doubled-angle point (cos 2 theta, sin 2 theta) / 2, whose
chord distance is |d theta| for small differences and wraps correctly at 0 = pi; an
optional per-feature weight scales each block (default 1: Herraz's plain metric).

Initial centroids (Herraz Sec. 2.2): K cells equally spread on a circle around the centre
of the parametric domain (radius 0.35), deterministic; then Lloyd iterations
(scipy.cluster.vq.kmeans2 with the given init) to a fixed point.

Disconnected clusters are split into connected zones (Herraz Sec. 2.3): a graph whose
vertices are the cells and whose edges join side-by-side cells of the same cluster;
its connected components (scipy.sparse.csgraph) are the zones.
"""

from __future__ import annotations

import numpy as np
from scipy.cluster.vq import kmeans2
from scipy.sparse import coo_matrix
from scipy.sparse.csgraph import connected_components

from .features import MeshFeatures

__all__ = ["feature_matrix", "kmeans_clusters", "connected_zones", "kmeans_zoning"]


def feature_matrix(f: MeshFeatures, weights=(1.0, 1.0, 1.0, 1.0)) -> np.ndarray:
    """(n*m, 5) rows (w_u u, w_v v, w_s s, w_t cos 2 theta / 2, w_t sin 2 theta / 2)."""
    wu, wv, ws, wt = (float(w) for w in weights)
    th = f.steepest.ravel()
    return np.column_stack([wu * f.u.ravel(), wv * f.v.ravel(), ws * f.slope.ravel(),
                            0.5 * wt * np.cos(2 * th), 0.5 * wt * np.sin(2 * th)])


def kmeans_clusters(f: MeshFeatures, k: int, weights=(1.0, 1.0, 1.0, 1.0),
                    max_iterations: int = 300) -> np.ndarray:
    """Cluster labels (n, m) in 0..k-1 from Lloyd's K-means with Herraz's initialization."""
    if isinstance(k, bool) or int(k) != k or k < 1:
        raise ValueError(f"K: expected an integer >= 1, got {k!r}")
    k = int(k)
    if k > f.size:
        raise ValueError(f"K: {k} zones asked from a mesh of only {f.size} cells")
    x = feature_matrix(f, weights)
    ang = 2 * np.pi * np.arange(k) / k
    cu, cv = 0.5 + 0.35 * np.cos(ang), 0.5 + 0.35 * np.sin(ang)
    if k == 1:
        cu, cv = np.array([0.5]), np.array([0.5])
    d2 = (f.u.ravel()[None, :] - cu[:, None]) ** 2 + (f.v.ravel()[None, :] - cv[:, None]) ** 2
    seeds = np.argmin(d2, axis=1)
    if len(np.unique(seeds)) < k:  # a mesh too coarse for distinct seeds: spread by index
        seeds = np.linspace(0, f.size - 1, k).round().astype(int)
    centroids = x[seeds].copy()
    labels = np.zeros(f.size, np.int64)
    for _ in range(max_iterations):
        centroids, new = kmeans2(x, centroids, iter=1, minit="matrix", missing="warn")
        if np.array_equal(new, labels) and _ > 0:
            break
        labels = new
    return labels.reshape(f.shape)


def connected_zones(labels: np.ndarray) -> np.ndarray:
    """Split each label into its 4-connected components: zone ids (n, m), 0..Z-1."""
    labels = np.asarray(labels)
    n, m = labels.shape
    idx = np.arange(n * m).reshape(n, m)
    rows, cols = [], []
    same_u = labels[1:, :] == labels[:-1, :]
    rows.append(idx[1:, :][same_u])
    cols.append(idx[:-1, :][same_u])
    same_v = labels[:, 1:] == labels[:, :-1]
    rows.append(idx[:, 1:][same_v])
    cols.append(idx[:, :-1][same_v])
    r, c = np.concatenate(rows), np.concatenate(cols)
    graph = coo_matrix((np.ones(len(r), np.int8), (r, c)), shape=(n * m, n * m))
    _, comp = connected_components(graph, directed=False)
    # relabel in first-occurrence order (C-order scan) so results compare with ==
    _, first, inv = np.unique(comp, return_index=True, return_inverse=True)
    rank = np.argsort(np.argsort(first))
    return rank[inv].reshape(n, m)


def kmeans_zoning(f: MeshFeatures, k: int, weights=(1.0, 1.0, 1.0, 1.0)) -> np.ndarray:
    """Herraz's zoning: K-means clusters split into connected zones, (n, m) zone ids."""
    return connected_zones(kmeans_clusters(f, k, weights))
