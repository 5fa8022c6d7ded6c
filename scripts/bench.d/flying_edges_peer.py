#!/usr/bin/env python3
"""The peer of seg2mesh --fast: VTK's vtkDiscreteFlyingEdges3D on every
nonzero label of a label image (no smoothing; each interface made twice, once
per label), written as a binary zlib-compressed .vtp as VTK writes it.
  flying_edges_peer.py IN.{mha,nii.gz} OUT.vtp
Prints one line: labels, triangles, and the seconds of read, contour, write.
(VTK's Debian NRRD reader needs MPI: give .mha or .nii.gz.)"""
import sys
import time

import numpy as np
import vtk
from vtk.util import numpy_support

src, out = sys.argv[1], sys.argv[2]
t0 = time.time()
reader = vtk.vtkNIFTIImageReader() if src.endswith((".nii", ".nii.gz")) else vtk.vtkMetaImageReader()
reader.SetFileName(src)
reader.Update()
image = reader.GetOutput()
labels = np.unique(numpy_support.vtk_to_numpy(image.GetPointData().GetScalars()))
labels = [int(v) for v in labels if v != 0]
t1 = time.time()
fe = vtk.vtkDiscreteFlyingEdges3D()
fe.SetInputData(image)
for i, v in enumerate(labels):
    fe.SetValue(i, v)
fe.ComputeNormalsOff()
fe.ComputeGradientsOff()
fe.ComputeScalarsOn()
fe.Update()
t2 = time.time()
w = vtk.vtkXMLPolyDataWriter()
w.SetFileName(out)
w.SetInputData(fe.GetOutput())
w.Write()
t3 = time.time()
print("labels %d triangles %d read %.2f contour %.2f write %.2f" %
      (len(labels), fe.GetOutput().GetNumberOfPolys(), t1 - t0, t2 - t1, t3 - t2))
