"""Median wall times of SurfaceTopography's 1-D (x, y) and radial PSDs on an
n x n map. Usage: python st_timing.py N RUNS"""
import sys, time
import numpy as np
import SurfaceTopography
from SurfaceTopography import Topography

n = int(sys.argv[1]); runs = int(sys.argv[2])
pixel = 1e-6
rng = np.random.default_rng(4)
# self-affine-ish map by Fourier filtering (content does not affect timing)
qx = np.fft.fftfreq(n)[:, None]; qy = np.fft.rfftfreq(n)[None, :]
q = np.hypot(qx, qy); q[0, 0] = 1
h = np.fft.irfft2(np.fft.rfft2(rng.standard_normal((n, n))) * q ** -1.8, s=(n, n))
h *= 1e-6 / h.std()

def median(f):
    f()
    t = []
    for _ in range(runs):
        s = time.perf_counter(); f(); t.append(time.perf_counter() - s)
    return float(np.median(t))

print(f"SurfaceTopography {SurfaceTopography.__version__}, numpy {np.__version__}, n = {n}, runs = {runs}")
for name, periodic in [("hann", False), ("periodic", True)]:
    t = Topography(h, (n * pixel, n * pixel), periodic=periodic)
    tt = Topography(h.T, (n * pixel, n * pixel), periodic=periodic)
    x = median(lambda: t.power_spectrum_from_profile(nb_points_per_decade=10))
    y = median(lambda: tt.power_spectrum_from_profile(nb_points_per_decade=10))
    r = median(lambda: t.power_spectrum_from_area(nb_points_per_decade=10))
    print(f"{name:9} x {x:.4f} s   y {y:.4f} s   radial {r:.4f} s", flush=True)
