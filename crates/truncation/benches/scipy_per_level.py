"""Issue #35's reference: scipy.ndimage.label at each of the 1000 planes of
the benchmark map, the per-level relabelling that the one-sweep union-find
replaces. 8-connectivity (a 3x3 structure of ones), as the stage's default
`Connectivity::Eight`; planes z_k = z_max (1000 - k) / 1000 above the lowest
point, touched where h - h_min >= z (the stage's convention).

    cargo run -p hypercontact-truncation --release --example bench_map -- 2048 /tmp/map-2048.npy
    python3 crates/truncation/benches/scipy_per_level.py /tmp/map-2048.npy

Prints wall and process CPU seconds of the labelling loop (the threshold
comparison included, as the union-find's time includes its grouping of the
pixels by plane). A second argument names a text file to receive N at every
plane, one per line, to set against the stage's `patches` column.
"""

import sys
import time

import numpy as np
from scipy import ndimage

LEVELS = 1000


def main() -> None:
    heights = np.load(sys.argv[1] if len(sys.argv) > 1 else "map-2048.npy")
    above = heights - np.nanmin(heights)
    z_max = np.nanmax(above)
    eight = np.ones((3, 3), dtype=bool)
    patches = np.empty(LEVELS + 1, dtype=np.int64)
    wall, cpu = time.perf_counter(), time.process_time()
    for k in range(LEVELS + 1):
        z = z_max * (LEVELS - k) / LEVELS
        patches[k] = ndimage.label(above >= z, structure=eight)[1]
    wall, cpu = time.perf_counter() - wall, time.process_time() - cpu
    print(
        f"{heights.shape[0]} x {heights.shape[1]}, {LEVELS + 1} planes: "
        f"{wall:.2f} s wall, {cpu:.2f} s CPU; N at plane 500 = {patches[500]}"
    )
    if len(sys.argv) > 2:
        np.savetxt(sys.argv[2], patches, fmt="%d")


if __name__ == "__main__":
    main()
