"""A measured topography read through SurfaceTopography (any of its
instrument formats) and solved by viscoslide.

    python examples/python/measured_topography.py [SCAN]

SCAN defaults to out/measured/scan_low.x3p, a measured-like profilometer
scan (256 x 256 points on 5 mm, tilted) that
``cargo run --release --example measured_scans -- out/measured`` writes.
The scan is levelled (plane removed) by SurfaceTopography, converted to
metres, and solved as a finite, non-periodic pad of the paper's rubber at
3 kPa, sliding at the friction peak of a 1 cm pad (v = 1.17e-2 m/s).
"""

import os
import sys

import SurfaceTopography

import viscoslide as vs

path = sys.argv[1] if len(sys.argv) > 1 else "out/measured/scan_low.x3p"
if not os.path.exists(path):
    sys.exit(f"{path} not found: run `cargo run --release --example measured_scans -- out/measured` first")

reader = SurfaceTopography.open_topography(path)
topography = reader.topography().to_unit("m").detrend("height")
print(f"{path}: {topography.nb_grid_pts} points, {topography.physical_sizes} m, "
      f"rms height {topography.rms_height_from_area():.3e} m, rms slope {topography.rms_gradient():.3e}")

rubber = vs.Material.sls(relaxed_modulus=1e7 / 3, glassy_modulus=1e7, creep_time=0.01)
result = vs.solve(topography, rubber, speed=1.17e-2, mean_pressure=3000.0, progress=True)
print(result)
analysis = result.analysis()
print(f"contact spots: {analysis['spots']['count']}, anisotropy gamma = {analysis['gamma']:.3f}")
if len(sys.argv) > 2:
    print("wrote", len(result.write(sys.argv[2])), "files to", sys.argv[2])
