"""Compare our binned PSDs (ours_512.csv) with SurfaceTopography's on the
same 512x512 map (map_512.f64, row-major, axis 0 = x)."""
import numpy as np
from SurfaceTopography import Topography

n, pixel = 512, 1e-6
h = np.fromfile("map_512.f64", dtype="<f8").reshape(n, n)
ours = {}
for line in open("ours_512.csv").read().split("\n")[1:]:
    if line:
        case, q, c = line.split(",")
        ours.setdefault(case, ([], []))
        ours[case][0].append(float(q)); ours[case][1].append(float(c))

for name, periodic in [("hann", False), ("periodic", True)]:
    t = Topography(h, (n * pixel, n * pixel), periodic=periodic)
    tt = Topography(h.T, (n * pixel, n * pixel), periodic=periodic)
    theirs = {"x": t.power_spectrum_from_profile(nb_points_per_decade=10),
              "y": tt.power_spectrum_from_profile(nb_points_per_decade=10),
              "radial": t.power_spectrum_from_area(nb_points_per_decade=10)}
    for kind, (q, c) in theirs.items():
        q = q.compressed(); c = c.compressed()
        oq, oc = map(np.array, ours[f"{kind}_{name}"])
        if len(q) != len(oq):
            print(f"{kind}_{name}: bin count differs {len(oq)} vs {len(q)}"); continue
        print(f"{kind:6} {name:9} bins {len(q):3}  max rel diff q {np.max(np.abs(oq / q - 1)):.2e}  "
              f"C {np.max(np.abs(oc / c - 1)):.2e}")
