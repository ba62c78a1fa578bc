#!/usr/bin/env python3
"""Peer comparison of viscoslide's contact iteration with ASPHER on elastic
periodic contact (v = 0, the relaxed modulus); not run in CI.

The heights are those of the paper experiment (``configs/paper_experiment.toml``:
251 scales, H = 0.82, rms slope 0.5, seed 1), written by ``viscoslide surface
generate`` at every grid and read by both codes. viscoslide solves them with
``viscoslide solve`` (periodic spectral operator, preconditioned active-set
iteration, coarse-to-fine cascade from 64^2); ASPHER with ``solve_nested``
(periodic backend, nested grids from 64^2, |q| spectral preconditioner,
Polonsky-Keer CG). Same nominal pressure (94 kPa), same E* = E0 / (1 - nu^2),
relative tolerance 1e-8 in both (each code's own residual measure).

With ``--viscoelastic``, the same heights are also solved viscoelastically
as the paper experiment (the SBR-like creep spectrum at 1e-4 m/s) with
``[solver] precision = "mixed"`` and with ``"f64"``, in the same run: the
viscoelastic mixed solve against ASPHER's elastic one (issue #28's target:
at most half its time).

Counts are fine-grid equivalents: an operator application on a grid of a
quarter of the cells counts 1/4 (viscoslide's ``matvecs``; for ASPHER the
same sum over its ``stage_stats``). Checks that both found the same contact
set and pressure.

Usage: python3 scripts/aspher_compare.py [--levels 512,1024,2048] [--out DIR]
Needs: pip install aspher==0.1.3 (its build needs Debian's libeigen3-dev),
numpy; a release build of viscoslide (cargo build --release).
"""

import argparse
import json
import os
import subprocess
import sys
import time

import numpy as np

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
CONFIG = os.path.join(ROOT, "configs", "paper_experiment.toml")
MATERIAL = os.path.join(ROOT, "configs", "data", "sbr_like_material.toml")
LENGTH = 2.5032990e-4  # m, as in the config
PRESSURE = 94e3  # Pa
POISSON = 0.5


def viscoslide(binary, args):
    return subprocess.run([binary] + args, check=True, capture_output=True, text=True)


def relaxed_modulus(binary):
    out = viscoslide(binary, ["material", "show", os.path.join(ROOT, "configs",
                                                               "material_sbr_like.toml")]).stdout
    for line in out.splitlines():
        if "relaxed modulus" in line:
            return float(line.split("=")[1].split()[0])
    raise RuntimeError("no relaxed modulus in `material show`")


def elastic_config(path, heights, speed=0.0, precision="f64"):
    with open(path, "w") as fh:
        fh.write(f"""[material]
model = "file"
file = "{MATERIAL}"
poisson = {POISSON}

[surface]
file = "{heights}"
length = {LENGTH!r}
detrend = "none"   # the generated periodic heights as they are, as ASPHER reads them

[loading]
mean_pressure = {PRESSURE!r}
speed = {speed!r}

[solver]
formulation = "periodic"
precision = "{precision}"

[analysis]
enabled = false
""")


def aspher_solve(heights, e_star, tol):
    import aspher
    h = np.load(heights)
    n = h.shape[0]
    gap = np.ascontiguousarray(h.max() - h)
    start = time.perf_counter()
    r = aspher.solve_nested(n, gap, PRESSURE, domain_size=LENGTH, E_star=e_star,
                            coarsest=64, backend="periodic", tol=tol)
    seconds = time.perf_counter() - start
    equivalent = 0.0
    for stage in r.stage_stats:
        side = int(stage["name"].split(":")[1])
        equivalent += stage["matvec_count"] * (side / n) ** 2
    return {
        "converged": bool(r.converged),
        "contact_fraction": float(r.contact_area),
        "matvecs_fine": int(r.matvec_count),
        "matvecs_equivalent": equivalent,
        "preconditioner_applications": int(r.precond_count),
        "iterations_fine": int(r.iterations),
        "approach": float(r.approach),
        "seconds": seconds,
        "pressure": np.asarray(r.pressure).reshape(n, n),
    }


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--levels", default="512,1024,2048")
    ap.add_argument("--tol", type=float, default=1e-8)
    ap.add_argument("--out", default="target/aspher_compare")
    ap.add_argument("--viscoelastic", action="store_true",
                    help="also solve the heights viscoelastically (1e-4 m/s) in mixed and f64 precision")
    args = ap.parse_args()
    out = os.path.join(ROOT, args.out)
    os.makedirs(out, exist_ok=True)
    subprocess.run(["cargo", "build", "--release"], cwd=ROOT, check=True)
    binary = os.path.join(ROOT, "target", "release", "viscoslide")
    e0 = relaxed_modulus(binary)
    e_star = e0 / (1 - POISSON**2)
    import aspher  # noqa: F401  (fail early when it is missing)
    print(f"E0 = {e0:.6e} Pa, E* = {e_star:.6e} Pa, p0 = {PRESSURE:g} Pa, tol {args.tol:g}, "
          f"{os.cpu_count()} cores", file=sys.stderr)
    rows = []
    for n in [int(x) for x in args.levels.split(",")]:
        level = os.path.join(out, f"n{n}")
        surface = os.path.join(level, "surface")
        if not os.path.exists(os.path.join(surface, "heights.npy")):
            viscoslide(binary, ["surface", "generate", "--config", CONFIG,
                                "--set", f"surface.generate.n={n}", "--out", surface])
        heights = os.path.join(surface, "heights.npy")
        cfg = os.path.join(level, "elastic.toml")
        elastic_config(cfg, heights)
        solved = os.path.join(level, "viscoslide")
        start = time.perf_counter()
        viscoslide(binary, ["solve", cfg, "--backend", "cpu", "--set",
                            f"solver.tolerance={args.tol!r}", "--out", solved])
        vs_seconds = time.perf_counter() - start
        with open(os.path.join(solved, "summary.json")) as fh:
            s = json.load(fh)
        fine = s["matvecs_by_level"][-1] if s["matvecs_by_level"] else {"matvecs": s["matvecs"]}
        vs = {
            "contact_fraction": s["contact_area_fraction"],
            "matvecs_equivalent": s["matvecs"],
            "matvecs_fine": fine["matvecs"],
            "preconditioner_applications": s["preconditioner_applications"],
            "iteration_seconds": s["timings"]["iteration_s"],
            "seconds": vs_seconds,
            "approach": s["approach"],
        }
        if args.viscoelastic:
            for precision in ("mixed", "f64"):
                vcfg = os.path.join(level, f"viscoelastic_{precision}.toml")
                elastic_config(vcfg, heights, speed=1e-4, precision=precision)
                vdir = os.path.join(level, f"viscoelastic_{precision}")
                start = time.perf_counter()
                viscoslide(binary, ["solve", vcfg, "--backend", "cpu", "--set",
                                    f"solver.tolerance={args.tol!r}", "--out", vdir])
                seconds = time.perf_counter() - start
                with open(os.path.join(vdir, "summary.json")) as fh:
                    vsum = json.load(fh)
                vs[f"viscoelastic_{precision}"] = {
                    "seconds": seconds,
                    "matvecs": vsum["matvecs"],
                    "exact_matvecs": vsum["exact_matvecs"],
                    "friction_coefficient": vsum["friction_coefficient"],
                }
        asp = aspher_solve(heights, e_star, args.tol)
        p_vs = np.load(os.path.join(solved, "pressure.npy"))
        p_as = asp.pop("pressure")
        vs["contact_sets_differ_in"] = int(((p_vs > 0) != (p_as > 0)).sum())
        vs["pressure_max_difference"] = float(np.abs(p_vs - p_as).max() / p_vs.max())
        rows.append({"n": n, "viscoslide": vs, "aspher": asp})
        print(json.dumps(rows[-1]), file=sys.stderr, flush=True)
    print("| grid | A/A0 viscoslide | A/A0 ASPHER | cells differing | max dp / p_max | "
          "viscoslide matvecs (fine equiv. / fine grid) | + preconditioner | "
          "ASPHER matvecs (fine equiv. / fine grid) | viscoslide wall [s] | ASPHER wall [s] |")
    print("|---|---|---|---|---|---|---|---|---|---|")
    for r in rows:
        v, a = r["viscoslide"], r["aspher"]
        print(f"| {r['n']}^2 | {v['contact_fraction']:.6f} | {a['contact_fraction']:.6f} | "
              f"{v['contact_sets_differ_in']} | {v['pressure_max_difference']:.1e} | "
              f"{v['matvecs_equivalent']} / {v['matvecs_fine']} | "
              f"{v['preconditioner_applications']} | "
              f"{a['matvecs_equivalent']:.0f} / {a['matvecs_fine']} | "
              f"{v['seconds']:.2f} | {a['seconds']:.2f} |")
    if args.viscoelastic:
        print("\n| grid | viscoelastic mixed [s] | viscoelastic f64 [s] | ASPHER elastic [s] | "
              "mixed / ASPHER | mu mixed | mu f64 |")
        print("|---|---|---|---|---|---|---|")
        for r in rows:
            m, f = r["viscoslide"]["viscoelastic_mixed"], r["viscoslide"]["viscoelastic_f64"]
            a = r["aspher"]["seconds"]
            print(f"| {r['n']}^2 | {m['seconds']:.2f} | {f['seconds']:.2f} | {a:.2f} | "
                  f"{m['seconds'] / a:.2f} | {m['friction_coefficient']:.10e} | "
                  f"{f['friction_coefficient']:.10e} |")
    with open(os.path.join(out, "results.json"), "w") as fh:
        json.dump(rows, fh, indent=1)


if __name__ == "__main__":
    main()
