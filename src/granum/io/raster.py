"""A small software rasteriser with a depth buffer: shaded spheres, triangles and thick segments.

Snapshots must render without a display or an OpenGL context, on any machine granum runs on, so
pictures are drawn with NumPy alone. Every primitive covers a box of pixels; all the pixels of
many primitives of similar box size are generated at once (one array operation per group), each
pixel gets a depth, and the nearest fragment wins (a z-buffer). Overlapping spheres therefore
intersect correctly, which a painter's algorithm with discs would not do. Cost grows with the
number of covered pixels, about 10^7 fragments per second.

Coordinates: pixel ``(x, y)`` has its centre at ``(x + 0.5, y + 0.5)``, ``y`` grows downwards;
depths are distances along the viewing direction (larger is farther), in any consistent unit.
Colours are RGB floats in [0, 1].
"""

from __future__ import annotations

import numpy as np

# Light direction in camera space (x right, y up, z towards the viewer): from the upper left, in
# front of the scene, like a desk lamp; used for all shading.
_LIGHT = np.array([-0.45, 0.55, 0.70]) / np.linalg.norm([-0.45, 0.55, 0.70])
_HALF = (_LIGHT + np.array([0.0, 0.0, 1.0])) / np.linalg.norm(_LIGHT + np.array([0.0, 0.0, 1.0]))
_AMBIENT, _DIFFUSE, _SPECULAR, _SHININESS = 0.28, 0.72, 0.35, 40.0
# Fragments generated per batch: bounds memory (about 100 bytes each) for any scene size.
_BATCH = 1 << 21


def _pow2(n: np.ndarray) -> np.ndarray:
    return 1 << np.ceil(np.log2(np.maximum(n, 1))).astype(np.int64)


class Canvas:
    """An RGB image with a depth buffer, ``width`` x ``height`` pixels, filled with ``background``."""

    def __init__(self, width: int, height: int, background=(0.2, 0.2, 0.2)):
        self.width, self.height = int(width), int(height)
        n = self.width * self.height
        self.depth = np.full(n, np.inf)
        self.rgb = np.empty((n, 3))
        self.rgb[:] = np.clip(np.asarray(background, float), 0.0, 1.0)

    # ---- fragments -------------------------------------------------------------------------
    def _boxes(self, x0, y0, x1, y1):
        """Yield ``(prim, px, py)``: the pixels of each primitive's box [x0, x1] x [y0, y1] on the image.

        Boxes are grouped by their size rounded up to powers of two, so that each group is one
        dense array operation with at most 4x waste.
        """
        W, H = self.width, self.height
        ax0 = np.clip(np.floor(x0), 0, W - 1).astype(np.int64)
        ay0 = np.clip(np.floor(y0), 0, H - 1).astype(np.int64)
        ax1 = np.clip(np.floor(x1), -1, W - 1).astype(np.int64)
        ay1 = np.clip(np.floor(y1), -1, H - 1).astype(np.int64)
        visible = (x1 >= 0) & (y1 >= 0) & (x0 < W) & (y0 < H) & (ax1 >= ax0) & (ay1 >= ay0)
        idx = np.nonzero(visible)[0]
        if idx.size == 0:
            return
        bw, bh = _pow2(ax1[idx] - ax0[idx] + 1), _pow2(ay1[idx] - ay0[idx] + 1)
        key = bw * (1 << 32) + bh
        for k in np.unique(key):
            group = idx[key == k]
            gw, gh = int(k >> 32), int(k & 0xFFFFFFFF)
            step = max(1, _BATCH // (gw * gh))
            ix, iy = np.arange(gw), np.arange(gh)
            for s in range(0, group.size, step):
                g = group[s:s + step]
                shape = (g.size, gh, gw)
                px = np.broadcast_to(ax0[g][:, None, None] + ix[None, None, :], shape)
                py = np.broadcast_to(ay0[g][:, None, None] + iy[None, :, None], shape)
                inside = (px <= ax1[g][:, None, None]) & (py <= ay1[g][:, None, None])
                prim = np.broadcast_to(g[:, None, None], shape)
                yield prim[inside], px[inside], py[inside]

    def _resolve(self, pix: np.ndarray, z: np.ndarray) -> np.ndarray:
        """Indices of the fragments that are the nearest at their pixel so far; updates the depths.

        ``minimum.at`` reduces all fragments of a pixel in one pass (no sort); a fragment wins
        where its depth is the new minimum. Exact ties (rare) may both write; either is correct.
        """
        np.minimum.at(self.depth, pix, z)
        return np.nonzero(z == self.depth[pix])[0]

    # ---- primitives ----------------------------------------------------------------------------
    def spheres(self, cx, cy, rpx, depth, radius, color) -> None:
        """Shaded spheres.

        :param cx, cy: (M,) centres on the image [px]; ``rpx``: (M,) radii on the image [px].
        :param depth: (M,) depth of the centres; ``radius``: (M,) radii in depth units.
        :param color: (M, 3) colours.
        """
        cx, cy, rpx = (np.asarray(a, float) for a in (cx, cy, rpx))
        depth, radius, color = np.asarray(depth, float), np.asarray(radius, float), np.asarray(color, float)
        for prim, px, py in self._boxes(cx - rpx, cy - rpx, cx + rpx, cy + rpx):
            dx = (px + 0.5 - cx[prim]) / rpx[prim]
            dy = (py + 0.5 - cy[prim]) / rpx[prim]
            d2 = dx * dx + dy * dy
            keep = d2 <= 1.0
            prim, px, py, dx, dy, d2 = prim[keep], px[keep], py[keep], dx[keep], dy[keep], d2[keep]
            nz = np.sqrt(1.0 - d2)
            win = self._resolve(py * self.width + px, depth[prim] - radius[prim] * nz)
            normal = np.stack([dx[win], -dy[win], nz[win]], axis=1)
            self._shade(py[win] * self.width + px[win], color[prim[win]], normal)

    def triangles(self, xy, depth, color, normal) -> None:
        """Flat-shaded triangles, lit on both sides.

        :param xy: (F, 3, 2) vertices on the image [px]; ``depth``: (F, 3) their depths (> 0).
        :param color: (F, 3) colours; ``normal``: (F, 3) unit normals in camera space.
        """
        xy, depth = np.asarray(xy, float), np.asarray(depth, float)
        color, normal = np.asarray(color, float), np.asarray(normal, float)
        a, b, c = xy[:, 0], xy[:, 1], xy[:, 2]
        area = (b[:, 0] - a[:, 0]) * (c[:, 1] - a[:, 1]) - (b[:, 1] - a[:, 1]) * (c[:, 0] - a[:, 0])
        ok = np.abs(area) > 1e-12  # seen edge-on: nothing to fill
        lo, hi = xy.min(axis=1), xy.max(axis=1)
        lo[~ok], hi[~ok] = 1.0, -1.0
        lit = np.where(np.einsum("fi,fi->f", normal, normal) > 0, np.abs(normal @ _LIGHT), 1.0)
        flat = color * (_AMBIENT + _DIFFUSE * lit)[:, None]
        for prim, px, py in self._boxes(lo[:, 0], lo[:, 1], hi[:, 0], hi[:, 1]):
            x, y = px + 0.5, py + 0.5
            A, B, C, S = a[prim], b[prim], c[prim], area[prim]
            l0 = ((B[:, 0] - x) * (C[:, 1] - y) - (B[:, 1] - y) * (C[:, 0] - x)) / S
            l1 = ((C[:, 0] - x) * (A[:, 1] - y) - (C[:, 1] - y) * (A[:, 0] - x)) / S
            l2 = 1.0 - l0 - l1
            keep = (l0 >= 0) & (l1 >= 0) & (l2 >= 0)
            prim, px, py = prim[keep], px[keep], py[keep]
            zi = depth[prim]
            # depth is not linear on the image under perspective; its inverse is
            z = 1.0 / (l0[keep] / zi[:, 0] + l1[keep] / zi[:, 1] + l2[keep] / zi[:, 2])
            pix = py * self.width + px
            win = self._resolve(pix, z)
            self.rgb[pix[win]] = flat[prim[win]]

    def segments(self, p0, p1, z0, z1, halfwidth, color) -> None:
        """Thick segments shaded as cylinders (hairlines when ``halfwidth`` < 1 px).

        :param p0, p1: (K, 2) end points on the image [px]; ``z0``, ``z1``: (K,) their depths.
        :param halfwidth: (K,) half width on the image [px]; ``color``: (K, 3) colours.
        """
        p0, p1 = np.asarray(p0, float), np.asarray(p1, float)
        z0, z1, color = np.asarray(z0, float), np.asarray(z1, float), np.asarray(color, float)
        hw = np.maximum(np.asarray(halfwidth, float), 0.5)
        lo, hi = np.minimum(p0, p1) - hw[:, None], np.maximum(p0, p1) + hw[:, None]
        d = p1 - p0
        len2 = np.maximum(np.einsum("ki,ki->k", d, d), 1e-12)
        for prim, px, py in self._boxes(lo[:, 0], lo[:, 1], hi[:, 0], hi[:, 1]):
            q = np.stack([px + 0.5, py + 0.5], axis=1) - p0[prim]
            t = np.clip(np.einsum("ki,ki->k", q, d[prim]) / len2[prim], 0.0, 1.0)
            off = q - t[:, None] * d[prim]
            s = np.sqrt(np.einsum("ki,ki->k", off, off)) / hw[prim]
            keep = s <= 1.0
            prim, px, py, t, s = prim[keep], px[keep], py[keep], t[keep], s[keep]
            pix = py * self.width + px
            win = self._resolve(pix, z0[prim] + t * (z1[prim] - z0[prim]))
            bright = _AMBIENT + _DIFFUSE * np.sqrt(1.0 - s[win] ** 2)
            self.rgb[pix[win]] = np.clip(color[prim[win]] * bright[:, None], 0.0, 1.0)

    def _shade(self, pix, color, normal) -> None:
        """Phong lighting of the pixels ``pix`` with unit camera-space normals."""
        diffuse = np.clip(normal @ _LIGHT, 0.0, None)
        spec = _SPECULAR * np.clip(normal @ _HALF, 0.0, None) ** _SHININESS
        self.rgb[pix] = np.clip(color * (_AMBIENT + _DIFFUSE * diffuse)[:, None] + spec[:, None], 0.0, 1.0)

    def image(self) -> np.ndarray:
        """The picture as an (height, width, 3) uint8 array."""
        return (np.clip(self.rgb, 0.0, 1.0) * 255.0 + 0.5).astype(np.uint8).reshape(self.height, self.width, 3)
