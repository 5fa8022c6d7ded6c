#!/usr/bin/env python3
"""Synthetic label maps for the multi-label benchmarks (fixed seeds).

  labelmap.py body OUT.mha [NX NY NZ]   a whole-body-like map (default 512 512 400):
      a body (label 1) around a muscle layer (2); 100 organs, random rotated
      ellipsoids painted over one another inside it (3..102: they touch,
      overlap and meet along triple curves); 4 bones, hollow shells around a
      marrow (103..110: nested surfaces); 20 vessels, tubes one to three
      voxels in radius along random walks (111..130: thin structures).
  labelmap.py head OUT.mha [N]          a head-like map (default 256^3): scalp,
      skull, CSF, grey and white matter as nested, bumpy shells (1..5), two
      ventricles (6) and a thin falx of CSF between the hemispheres.
  labelmap.py head2 OUT.mha [N]         head's map (the same voxels), then three
      holes through the skull filled by the scalp (the skull's surface of
      genus 2, the scalp touching the CSF) and a straight tube (7, radius
      max(2, 0.03 N) voxels, an electrode's lead) from the white matter out
      of the head, crossing the grey matter, the CSF, the skull and the scalp.

OUT (or OUT,OUT2,...: the same map in each) by its extension picks how the
uint8 voxels are written, the ways users have label maps: .mha (raw data after the header, ElementDataFile LOCAL, which
both the tools here and VTK's vtkMetaImageReader read), .zip.mha (the same,
CompressedData), .nrrd (raw), .gz.nrrd (gzip encoding), .nii (NIfTI-1) or
.nii.gz; 1 mm voxels.
"""
import gzip
import struct
import sys
import zlib

import numpy as np


def write_mha(path, a, compressed=False):
    nz, ny, nx = a.shape
    data = np.ascontiguousarray(a, dtype=np.uint8).tobytes()
    if compressed:
        data = zlib.compress(data, 6)
    with open(path, "wb") as f:
        f.write(("ObjectType = Image\nNDims = 3\nBinaryData = True\nBinaryDataByteOrderMSB = False\n%s"
                 "Offset = 0 0 0\nElementSpacing = 1 1 1\nDimSize = %d %d %d\nElementType = MET_UCHAR\n"
                 "ElementDataFile = LOCAL\n"
                 % ("CompressedData = True\nCompressedDataSize = %d\n" % len(data) if compressed else "",
                    nx, ny, nz)).encode())
        f.write(data)


def write_nrrd(path, a, gz):
    nz, ny, nx = a.shape
    data = np.ascontiguousarray(a, dtype=np.uint8).tobytes()
    with open(path, "wb") as f:
        f.write(("NRRD0004\ntype: uint8\ndimension: 3\nspace: left-posterior-superior\nsizes: %d %d %d\n"
                 "space directions: (1,0,0) (0,1,0) (0,0,1)\nkinds: domain domain domain\nencoding: %s\n"
                 "space origin: (0,0,0)\n\n" % (nx, ny, nz, "gzip" if gz else "raw")).encode())
        f.write(gzip.compress(data, 6) if gz else data)


def write_nifti(path, a):
    """NIfTI-1, one file, uint8, qform (code 1, identity rotation): RAS."""
    nz, ny, nx = a.shape
    h = bytearray(352)
    struct.pack_into("<i", h, 0, 348)
    struct.pack_into("<8h", h, 40, 3, nx, ny, nz, 1, 1, 1, 1)
    struct.pack_into("<hh", h, 70, 2, 8)  # datatype uint8, bitpix
    struct.pack_into("<8f", h, 76, 1, 1, 1, 1, 0, 0, 0, 0)  # qfac, pixdim
    struct.pack_into("<f", h, 108, 352)  # vox_offset
    struct.pack_into("<f", h, 112, 1)  # scl_slope
    struct.pack_into("<hh", h, 252, 1, 0)  # qform_code, sform_code
    struct.pack_into("<4s", h, 344, b"n+1\0")
    data = bytes(h) + np.ascontiguousarray(a, dtype=np.uint8).tobytes()
    with (gzip.open(path, "wb", 6) if path.endswith(".gz") else open(path, "wb")) as f:
        f.write(data)


def write(path, a):
    if path.endswith(".zip.mha"):
        write_mha(path, a, True)
    elif path.endswith(".mha"):
        write_mha(path, a)
    elif path.endswith(".nrrd"):
        write_nrrd(path, a, path.endswith(".gz.nrrd"))
    elif path.endswith(".nii") or path.endswith(".nii.gz"):
        write_nifti(path, a)
    else:
        sys.exit("labelmap.py: OUT ends in .mha, .zip.mha, .nrrd, .gz.nrrd, .nii or .nii.gz")


def rotation(rng):
    q, _ = np.linalg.qr(rng.normal(size=(3, 3)))
    return q


def paint_ellipsoid(a, centre, radii, rot, label, inside=None):
    """Set `label` where the point is in the ellipsoid (and where `inside`, a
    boolean of a's shape, holds). A slice at a time: memory of a slice."""
    r = max(radii)
    lo = [max(0, int(np.floor(c - r)) - 1) for c in centre]
    hi = [min(n, int(np.ceil(c + r)) + 2) for c, n in zip(centre, a.shape)]
    if any(h <= l for l, h in zip(lo, hi)):
        return
    y, x = np.meshgrid(np.arange(lo[1], hi[1]) + 0.5 - centre[1], np.arange(lo[2], hi[2]) + 0.5 - centre[2],
                       indexing="ij")
    m = rot / np.asarray(radii)  # row i of p @ m: a point's coordinates scaled, in the ellipsoid's axes
    for z in range(lo[0], hi[0]):
        dz = z + 0.5 - centre[0]
        q = sum(((dz * m[0, k] + y * m[1, k] + x * m[2, k]) ** 2 for k in range(3)))
        sel = q <= 1
        row = a[z, lo[1]:hi[1], lo[2]:hi[2]]
        if inside is not None:
            sel &= inside[z, lo[1]:hi[1], lo[2]:hi[2]]
        row[sel] = label


def body(nx, ny, nz):
    rng = np.random.default_rng(1)
    a = np.zeros((nz, ny, nx), np.uint8)
    c = np.array([nz, ny, nx]) / 2
    eye = np.eye(3)
    paint_ellipsoid(a, c, (0.48 * nz, 0.42 * ny, 0.46 * nx), eye, 1)
    paint_ellipsoid(a, c, (0.45 * nz, 0.37 * ny, 0.41 * nx), eye, 2)
    inner = a == 2
    for label in range(3, 103):
        centre = c + rng.uniform(-0.33, 0.33, 3) * np.array([nz, ny, nx])
        radii = rng.uniform(4, 0.09 * min(nx, ny, nz), 3)
        paint_ellipsoid(a, centre, radii, rotation(rng), label, inner)
    for k in range(4):  # bones: cortex shell (odd label) around marrow
        centre = c + rng.uniform(-0.3, 0.3, 3) * np.array([nz, ny, nx])
        radii = rng.uniform(12, 0.12 * min(nx, ny, nz), 3)
        rot = rotation(rng)
        paint_ellipsoid(a, centre, radii, rot, 103 + 2 * k, inner)
        paint_ellipsoid(a, centre, radii * 0.7, rot, 104 + 2 * k, inner)
    for label in range(111, 131):  # vessels
        p = c + rng.uniform(-0.3, 0.3, 3) * np.array([nz, ny, nx])
        d = rotation(rng)[0]
        radius = rng.uniform(1.0, 3.0)
        for _ in range(int(0.6 * max(nx, ny, nz))):
            paint_ellipsoid(a, p, (radius, radius, radius), eye, label, inner)
            d = d + rng.normal(scale=0.15, size=3)
            d /= np.linalg.norm(d)
            p = p + d
    return a


def head(n):
    rng = np.random.default_rng(2)
    c = n / 2
    bumps = [(rotation(rng)[0], rng.uniform(0.005, 0.02), rng.integers(2, 7)) for _ in range(12)]
    y, x = np.meshgrid(np.arange(n) + 0.5, np.arange(n) + 0.5, indexing="ij")
    a = np.zeros((n, n, n), np.uint8)
    for zi in range(n):  # a slice at a time
        p = np.stack([np.full_like(x, (zi + 0.5 - c) / 0.46), (y - c) / 0.40, (x - c) / 0.36], axis=-1) / n
        r = np.linalg.norm(p, axis=-1)
        u = p / np.maximum(r, 1e-9)[..., None]
        bump = sum(w * np.cos(f * np.arccos(np.clip(u @ k, -1, 1))) for k, w, f in bumps)  # low frequency
        fold = 0.015 * np.sin(40 * u[..., 0]) * np.sin(40 * u[..., 1])  # the cortex's folds
        s = r + bump
        t = a[zi]
        t[s <= 1.0] = 1   # scalp
        t[s <= 0.94] = 2  # skull
        t[s <= 0.86] = 3  # CSF
        t[s + fold <= 0.82] = 4  # grey matter
        t[s + 2 * fold <= 0.68] = 5  # white matter
        t[(np.abs(x - c) <= 1) & (t >= 4)] = 3  # the falx
    for side in (-1, 1):
        paint_ellipsoid(a, (c, c - 0.02 * n, c + side * 0.07 * n), (0.05 * n, 0.12 * n, 0.025 * n),
                        np.eye(3), 6, a == 5)
    return a


def paint_cylinder(a, p0, p1, radius, label, where=None):
    """Set `label` within `radius` of the segment p0-p1 (index space, voxel
    centres at i + 0.5; where `where(old labels)` holds). A slice at a time."""
    p0, p1 = np.asarray(p0, float), np.asarray(p1, float)
    d = p1 - p0
    length2 = d @ d
    lo = [max(0, int(np.floor(min(u, v) - radius)) - 1) for u, v in zip(p0, p1)]
    hi = [min(n, int(np.ceil(max(u, v) + radius)) + 2) for u, v, n in zip(p0, p1, a.shape)]
    y, x = np.meshgrid(np.arange(lo[1], hi[1]) + 0.5, np.arange(lo[2], hi[2]) + 0.5, indexing="ij")
    for z in range(lo[0], hi[0]):
        q = np.stack([np.full_like(x, z + 0.5), y, x], axis=-1) - p0
        t = np.clip((q @ d) / length2, 0, 1)
        dist = np.linalg.norm(q - t[..., None] * d, axis=-1)
        row = a[z, lo[1]:hi[1], lo[2]:hi[2]]
        sel = dist <= radius
        if where is not None:
            sel &= where(row)
        row[sel] = label


def along(a, c, d, test):
    """The largest t (voxels, steps of 1/4) with test(label at c + t d)."""
    best = None
    for k in range(4 * max(a.shape)):
        p = c + 0.25 * k * d
        i = np.floor(p).astype(int)
        if (i < 0).any() or (i >= a.shape).any():
            break
        if test(a[tuple(i)]):
            best = 0.25 * k
    return best


def head2(n):
    a = head(n)
    c = np.full(3, n / 2)
    unit = lambda v: np.asarray(v, float) / np.linalg.norm(v)
    for d in (unit((1, 0.3, 0.5)), unit((0.4, -0.8, 0.6)), unit((-0.2, 0.5, -0.9))):  # (z, y, x)
        far = c + 0.6 * n * d
        paint_cylinder(a, c, far, max(2.0, 0.04 * n), 1, lambda t: t == 2)
    d = unit((0.35, 0.45, 0.8))
    inner = along(a, c, d, lambda v: v == 5) - 2  # inside the white matter
    outer = along(a, c, d, lambda v: v == 1) + 3  # out of the head
    paint_cylinder(a, c + inner * d, c + outer * d, max(2.0, 0.03 * n), 7)
    return a


def main():
    kind, outs = sys.argv[1], sys.argv[2].split(",")
    rest = [int(v) for v in sys.argv[3:]]
    if kind == "body":
        nx, ny, nz = rest if rest else (512, 512, 400)
        a = body(nx, ny, nz)
    elif kind == "head":
        a = head(rest[0] if rest else 256)
    elif kind == "head2":
        a = head2(rest[0] if rest else 256)
    else:
        sys.exit("labelmap.py: body, head or head2")
    for out in outs:
        write(out, a)


if __name__ == "__main__":
    main()
