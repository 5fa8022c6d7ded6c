#!/usr/bin/env python3
"""Benchmark helper (not a test): the figures scripts/bench.d/seg2mesh_quality.sh
prints for a mesh with label pairs (.vtp, as seg2mesh and mesh3_labels_peer
write it), measured the same way for every mesher.
  interface_metrics.py MESH.vtp MESHINFO.json REPAIRED.mha
MESHINFO.json: `meshinfo MESH.vtp --image MAP --json` (the interface
certificate against the map repaired as seg2mesh --fast repairs it);
REPAIRED.mha: that map (img2wc --labels all MAP REPAIRED.mha). Prints one
line of key=value:
  triangles, min_angle (degrees), under24 (% of triangles with an angle
  under 24 degrees), labels=ok/all (each label's surface certified, 0 the
  background's, i.e. the union of the others'), present=meshed/all (labels
  of the map with a triangle), interfaces=ok/all (pairs of K(X) and of the
  mesh), patches=placed/all (K(X)'s patches a mesh patch was placed on),
  components=found/all (the 6-connected voxel components of every label of
  REPAIRED, 0 included, with a triangle of that label within a voxel: one
  of the voxels around its centroid's voxel, 27, is of the component),
  wrong_side (voxel centres on the wrong side, over the labels checked:
  sides_checked, those whose surface is closed, manifold and oriented),
  verdict (the certificate's: ok or the first failed check), lost (the
  largest components lost, label:voxels, six at most)."""
import json
import sys
import zlib

import numpy as np
import vtk
from vtk.util import numpy_support


def read_vtp(path):
    """Points, triangles and label pairs of a .vtp with cell data "labels"."""
    r = vtk.vtkXMLPolyDataReader()
    r.SetFileName(path)
    r.Update()
    pd = r.GetOutput()
    v = numpy_support.vtk_to_numpy(pd.GetPoints().GetData()).astype(float)
    t = numpy_support.vtk_to_numpy(pd.GetPolys().GetConnectivityArray()).reshape(-1, 3)
    return v, t, numpy_support.vtk_to_numpy(pd.GetCellData().GetArray("labels")).reshape(-1, 2)


def smallest_angles(v, t):
    p = v[t]
    smallest = np.full(len(t), 180.0)
    for k in range(3):
        a = p[:, (k + 1) % 3] - p[:, k]
        b = p[:, (k + 2) % 3] - p[:, k]
        c = np.einsum('ij,ij->i', a, b) / np.maximum(np.linalg.norm(a, axis=1) * np.linalg.norm(b, axis=1), 1e-300)
        smallest = np.minimum(smallest, np.degrees(np.arccos(np.clip(c, -1, 1))))
    return smallest


def read_mha(path):
    """A MetaImage with its data in the file (img2wc writes it): the array
    (z, y, x) and world -> continuous index (x, y, z)."""
    raw = open(path, "rb").read()
    head, pos = {}, 0
    while True:
        end = raw.index(b"\n", pos)
        key, _, value = raw[pos:end].decode().partition("=")
        head[key.strip()] = value.strip()
        pos = end + 1
        if key.strip() == "ElementDataFile":
            break
    n = [int(v) for v in head["DimSize"].split()]
    types = {"MET_UCHAR": "u1", "MET_CHAR": "i1", "MET_USHORT": "<u2", "MET_SHORT": "<i2", "MET_UINT": "<u4",
             "MET_INT": "<i4"}
    data = raw[pos:]
    if head.get("CompressedData", "False") == "True":
        data = zlib.decompress(data)
    a = np.frombuffer(data, dtype=types[head["ElementType"]]).reshape(n[::-1]).astype(np.int64)
    origin = np.array(head["Offset"].split(), dtype=float)
    spacing = np.array(head["ElementSpacing"].split(), dtype=float)
    # ITK writes row i of TransformMatrix as the direction of axis i.
    axes = np.array(head.get("TransformMatrix", "1 0 0 0 1 0 0 0 1").split(), dtype=float).reshape(3, 3)
    return a, lambda p: ((p - origin) @ axes.T) / spacing


def components(a):
    """Per voxel, a global id of its label's 6-connected component; the
    labels of the components."""
    nz, ny, nx = a.shape
    ids = np.zeros(a.shape, np.int64)
    owner = []
    for label in np.unique(a):
        im = vtk.vtkImageData()
        im.SetDimensions(nx, ny, nz)
        im.GetPointData().SetScalars(numpy_support.numpy_to_vtk((a == label).astype(np.uint8).ravel(), deep=1))
        cf = vtk.vtkImageConnectivityFilter()
        cf.SetInputData(im)
        cf.SetScalarRange(1, 1)
        cf.SetExtractionModeToAllRegions()
        cf.SetLabelModeToSizeRank()
        cf.Update()
        r = numpy_support.vtk_to_numpy(cf.GetOutput().GetPointData().GetScalars()).reshape(a.shape).astype(np.int64)
        inside = a == label
        ids[inside] = r[inside] - 1 + len(owner)
        owner += [int(label)] * int(cf.GetNumberOfExtractedRegions())
    return ids, np.array(owner)


def found_components(v, t, pairs, a, to_index, ids, owner):
    """The components with a triangle of their label within a voxel."""
    centre = np.rint(to_index(v[t].mean(axis=1))).astype(np.int64)  # (x, y, z)
    hit = np.zeros(len(owner), bool)
    nz, ny, nx = a.shape
    for dz in (-1, 0, 1):
        for dy in (-1, 0, 1):
            for dx in (-1, 0, 1):
                x = np.clip(centre[:, 0] + dx, 0, nx - 1)
                y = np.clip(centre[:, 1] + dy, 0, ny - 1)
                z = np.clip(centre[:, 2] + dz, 0, nz - 1)
                lab = a[z, y, x]
                for side in (0, 1):
                    hit[ids[z, y, x][lab == pairs[:, side]]] = True
    return hit


def main():
    mesh, info = sys.argv[1], json.load(open(sys.argv[2]))
    a, to_index = read_mha(sys.argv[3])
    ids, owner = components(a)
    v, t, pairs = read_vtp(mesh)
    hit = found_components(v, t, pairs, a, to_index, ids, owner)
    smallest = smallest_angles(v, t)
    cert = info["interface_image"]
    labels = cert["labels"]
    ok = sum(l["verdict"] == "ok" for l in labels)
    inmap = [l for l in labels if l["verdict"] != "not in the image" and l["label"] != 0]
    present = sum(l["triangles"] > 0 for l in inmap)
    pairs = cert["interfaces"]
    pairs_ok = sum("failure" not in i and all(p["verdict"] == "ok" for p in i["patches"])
                   and len(i["patches"]) == i["complex_patches"] for i in pairs)
    patches = sum(i["complex_patches"] for i in pairs)
    placed = sum(len({p["complex_patch"] for p in i["patches"] if p["complex_patch"] >= 0}) for i in pairs)
    comps = "%d/%d" % (hit.sum(), len(hit))
    wrong = sum(l["voxel_sides"]["wrong_side"] for l in labels if "voxel_sides" in l)
    checked = sum("voxel_sides" in l for l in labels)
    sizes = np.bincount(ids.ravel(), minlength=len(owner))
    lost = sorted(((int(sizes[c]), int(owner[c])) for c in np.nonzero(~hit)[0]), reverse=True)
    print("triangles=%d min_angle=%.2f under24=%.2f labels=%d/%d present=%d/%d interfaces=%d/%d patches=%d/%d "
          "components=%s wrong_side=%d sides_checked=%d/%d verdict=%s%s" %
          (len(smallest), smallest.min() if len(smallest) else 0, 100.0 * np.mean(smallest < 24) if len(smallest) else 0,
           ok, len(labels), present, len(inmap), pairs_ok, len(pairs), placed, patches, comps, wrong, checked,
           len(labels), "ok" if cert["verdict"] == "ok" else cert["verdict"],
           " lost=" + ",".join("%d:%d" % (l, n) for n, l in lost[:6]) if lost else ""))


main()
