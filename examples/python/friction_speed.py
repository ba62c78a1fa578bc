"""Friction against sliding speed for a material and a surface built in
Python, next to Persson's theory, plotted with matplotlib.

    python examples/python/friction_speed.py [OUT.png]

The paper's single-relaxation rubber (E_inf = 10 MPa, E_inf/E0 = 3,
tau = 10 ms) under a self-affine 1 cm pad (128 x 128 cells, H = 0.8,
16 scales, rms slope 0.02) at 3 kPa; 13 speeds from 1e-5 to 10 m/s (about
6 s on two cores).
"""

import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt
import numpy as np

import viscoslide as vs

out = sys.argv[1] if len(sys.argv) > 1 else "friction_speed.png"

rubber = vs.Material.sls(relaxed_modulus=1e7 / 3, glassy_modulus=1e7, creep_time=0.01)
pad = vs.Surface.self_affine(128, 0.01, 0.8, scales=16, rms_slope=0.02, rolloff_q0=5026.548, seed=1)
print(rubber)
print(pad)

speeds = np.logspace(-5, 1, 13)
curve = vs.friction_curve(pad, rubber, speeds, mean_pressure=3000.0, progress=True)
theory = vs.persson(pad, rubber, np.logspace(-5, 1, 200), mean_pressure=3000.0)

peak = int(np.argmax(curve["friction_coefficient"]))
print(f"friction peak mu = {curve['friction_coefficient'][peak]:.4e} at v = {speeds[peak]:.3e} m/s")
for v, mu, mu_d, area in zip(
    speeds, curve["friction_coefficient"], curve["friction_coefficient_dissipation"], curve["contact_area_fraction"]
):
    print(f"v = {v:9.3e} m/s   mu = {mu:.4e}   mu (dissipation) = {mu_d:.4e}   A/A0 = {area:.4f}")

fig, (ax_mu, ax_area) = plt.subplots(1, 2, figsize=(10, 4))
ax_mu.loglog(speeds, curve["friction_coefficient"], "o-", label="viscoslide (work of the pressure)")
ax_mu.loglog(speeds, curve["friction_coefficient_dissipation"], "x", label="viscoslide (dissipation)")
ax_mu.loglog(theory["speed"], theory["friction_coefficient"], "-", label="Persson's theory")
ax_mu.set_xlabel("sliding speed v [m/s]")
ax_mu.set_ylabel("friction coefficient")
ax_mu.legend()
ax_area.semilogx(speeds, curve["contact_area_fraction"], "o-", label="viscoslide")
ax_area.semilogx(theory["speed"], theory["contact_area_fraction"], "-", label="Persson's theory")
ax_area.set_xlabel("sliding speed v [m/s]")
ax_area.set_ylabel("contact area fraction A/A0")
ax_area.legend()
fig.tight_layout()
fig.savefig(out, dpi=120)
print(f"wrote {out}")
