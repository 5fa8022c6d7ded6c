"""noisy_labels.py OUT.nrrd SEED N LABELS: an N^3 label map of LABELS labels
and the background, each voxel the largest of LABELS + 1 smoothed white
noises (Gaussian, 1 voxel), a 2-voxel background border, voxels of 7:1
anisotropy drawn from the seed: the hardest kind of map for the conforming
mesher (thin, pinched and touching pieces everywhere)."""
import sys
import numpy as np

out, seed, n, k = sys.argv[1], int(sys.argv[2]), int(sys.argv[3]), int(sys.argv[4])
rng = np.random.default_rng(seed)
f = rng.standard_normal((k + 1, n, n, n))
w = np.fft.fftfreq(n)
kernel = np.exp(-2 * np.pi ** 2 * (w[:, None, None] ** 2 + w[None, :, None] ** 2 + w[None, None, :] ** 2))
f = np.stack([np.real(np.fft.ifftn(np.fft.fftn(a) * kernel)) for a in f])
lab = np.argmax(f, axis=0).astype(np.uint8)
for a in range(3):
    lab.swapaxes(0, a)[:2] = 0
    lab.swapaxes(0, a)[-2:] = 0
sp = rng.uniform(0.3, 3, 3)
with open(out, "wb") as o:
    o.write(("NRRD0004\ntype: uint8\ndimension: 3\nspace: left-posterior-superior\nsizes: %d %d %d\n"
             "space directions: (%g,0,0) (0,%g,0) (0,0,%g)\nspace origin: (1,2,3)\n"
             "kinds: domain domain domain\nencoding: raw\n\n" % (n, n, n, sp[0], sp[1], sp[2])).encode())
    o.write(np.ascontiguousarray(lab.transpose(2, 1, 0)).tobytes())
