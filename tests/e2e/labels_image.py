"""labels_image.py OUT.nrrd: a fixed 3-label segmentation, 32x26x20 int16
voxels of 0.6 x 0.7 x 0.8 mm, origin (10, -20, 5), axes rotated 30 degrees
about z: label 1 a ball, label 2 a box touching it (neighbouring labels),
label 5 a solid torus (genus 1). Background 0."""
import math, struct, sys
nx, ny, nz = 32, 26, 20
c, s = math.cos(math.pi / 6), math.sin(math.pi / 6)
vox = []
for k in range(nz):
    for j in range(ny):
        for i in range(nx):
            v = 0
            if (i - 8) ** 2 + (j - 8) ** 2 + (k - 10) ** 2 <= 25: v = 1
            elif 14 <= i <= 20 and 4 <= j <= 12 and 6 <= k <= 14: v = 2
            elif (math.hypot(i - 22, j - 17) - 4) ** 2 + (k - 10) ** 2 <= 4: v = 5
            vox.append(v)
hdr = ("NRRD0004\ntype: int16\ndimension: 3\nspace: left-posterior-superior\nsizes: %d %d %d\n"
       "space directions: (%r,%r,0) (%r,%r,0) (0,0,0.8)\nspace origin: (10,-20,5)\nendian: little\nencoding: raw\n\n"
       % (nx, ny, nz, 0.6 * c, 0.6 * s, -0.7 * s, 0.7 * c))
open(sys.argv[1], 'wb').write(hdr.encode() + struct.pack('<%dh' % len(vox), *vox))
