#!/usr/bin/env python3
"""Peer comparison of viscoslide's periodic spectral solver with Tamaas on
elastic periodic contact (v = 0); not run in CI.

Same 512^2 self-affine surface (generated with Tamaas' filter generator,
written to .npy and read by the Rust example ``periodic_elastic``), five
nominal pressures from 0.05 % to 1 % of E*, the same relative tolerance given
to both solvers. Reports contact fraction and mean gap of both, their
relative differences, and wall times (Tamaas' solver construction + solve;
viscoslide's operator construction + solve, single-threaded and with all
cores).

Usage: python3 scripts/tamaas_compare.py [--n 512] [--tol 1e-10] [--out DIR]
Needs: pip install tamaas (which brings numpy); cargo.
"""

import argparse
import json
import os
import subprocess
import sys
import time

import numpy as np
import tamaas as tm

LENGTH = 0.01  # m
YOUNG = 1e7  # Pa
POISSON = 0.5
E_STAR = YOUNG / (1 - POISSON**2)
FRACTIONS = [5e-4, 1e-3, 2.5e-3, 5e-3, 1e-2]  # p0 / E*
RMS_SLOPE = 0.2


def make_surface(n, seed):
    """Self-affine surface (H = 0.8, wave numbers 4..n/4 in units of
    2 pi / L), scaled to the rms slope RMS_SLOPE (spectral definition)."""
    gen = tm.SurfaceGeneratorFilter2D([n, n])
    spec = tm.Isopowerlaw2D()
    spec.q0, spec.q1, spec.q2, spec.hurst = 4, 4, n // 4, 0.8
    gen.spectrum = spec
    gen.random_seed = seed
    h = np.array(gen.buildSurface(), dtype=float)
    h -= h.mean()
    hq = np.fft.fft2(h)
    k = np.fft.fftfreq(n, d=1.0 / n) * 2 * np.pi / LENGTH
    q2 = k[:, None] ** 2 + k[None, :] ** 2
    slope = np.sqrt(np.sum(q2 * np.abs(hq) ** 2)) / (n * n)
    return np.ascontiguousarray(h * RMS_SLOPE / slope)


def tamaas_solve(h, p0, tol):
    n = h.shape[0]
    model = tm.ModelFactory.createModel(tm.model_type.basic_2d, [LENGTH, LENGTH], [n, n])
    model.E, model.nu = YOUNG, POISSON
    start = time.perf_counter()
    solver = tm.PolonskyKeerRey(model, h, tol)
    solver.max_iter = 100000
    solver.solve(p0)
    seconds = time.perf_counter() - start
    p = np.array(model.traction)
    # Gap between the rigid surface and the deformed solid: u - h, zero on
    # the contact set (where it is constant to the tolerance).
    gap = np.array(model.displacement) - h
    contact = p > 0
    gap -= gap[contact].mean()
    return {
        "contact_fraction": float(np.mean(p > 0)),
        "mean_gap": float(np.mean(np.maximum(gap, 0.0))),
        "mean_pressure": float(p.mean()),
        "gap_spread_in_contact": float(np.ptp(gap[contact])),
        "seconds": seconds,
    }


def tamaas_worker(surface_path, pressures, tol, threads):
    """Run the Tamaas solves in a fresh interpreter so that OMP_NUM_THREADS
    takes effect before Tamaas is loaded."""
    env = dict(os.environ)
    env.pop("OMP_NUM_THREADS", None)
    if threads is not None:
        env["OMP_NUM_THREADS"] = str(threads)
    cmd = [sys.executable, os.path.abspath(__file__), "--worker", surface_path,
           "--tol", repr(tol), "--pressures", ",".join(repr(p) for p in pressures)]
    out = subprocess.run(cmd, env=env, check=True, capture_output=True, text=True).stdout
    return [json.loads(line) for line in out.splitlines() if line.startswith("{")]


def viscoslide_solve(binary, surface_path, pressures, tol, threads):
    env = dict(os.environ)
    env.pop("RAYON_NUM_THREADS", None)
    if threads is not None:
        env["RAYON_NUM_THREADS"] = str(threads)
    cmd = [binary, surface_path, repr(LENGTH), repr(YOUNG), repr(POISSON), repr(tol),
           ",".join(repr(p) for p in pressures)]
    out = subprocess.run(cmd, env=env, check=True, capture_output=True, text=True).stdout
    return [json.loads(line) for line in out.splitlines() if line.startswith("{")]


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--n", type=int, default=512)
    ap.add_argument("--tol", type=float, default=1e-10)
    ap.add_argument("--seed", type=int, default=1)
    ap.add_argument("--out", default="target/tamaas_compare")
    ap.add_argument("--worker", help=argparse.SUPPRESS)
    ap.add_argument("--pressures", help=argparse.SUPPRESS)
    args = ap.parse_args()
    if args.worker:
        h = np.load(args.worker)
        for p in args.pressures.split(","):
            print(json.dumps(tamaas_solve(h, float(p), args.tol)), flush=True)
        return
    root = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
    out = os.path.join(root, args.out)
    os.makedirs(out, exist_ok=True)
    h = make_surface(args.n, args.seed)
    surface_path = os.path.join(out, "surface.npy")
    np.save(surface_path, h)
    subprocess.run(["cargo", "build", "--release", "--example", "periodic_elastic"],
                   cwd=root, check=True)
    binary = os.path.join(root, "target", "release", "examples", "periodic_elastic")
    pressures = [f * E_STAR for f in FRACTIONS]
    cores = os.cpu_count()
    print(f"tamaas {tm.__version__} (backend {tm.TamaasInfo.backend}), {args.n}^2, "
          f"tol {args.tol:g}, {cores} cores", file=sys.stderr)
    tam1 = tamaas_worker(surface_path, pressures, args.tol, 1)
    vs1 = viscoslide_solve(binary, surface_path, pressures, args.tol, 1)
    tamn = tamaas_worker(surface_path, pressures, args.tol, None)
    vsn = viscoslide_solve(binary, surface_path, pressures, args.tol, None)
    rows = []
    print("| p0/E* | A/A0 Tamaas | A/A0 viscoslide | rel. diff | mean gap Tamaas [m] | "
          "mean gap viscoslide [m] | rel. diff |")
    print("|---|---|---|---|---|---|---|")
    for f, t, v in zip(FRACTIONS, tam1, vs1):
        da = abs(v["contact_fraction"] - t["contact_fraction"]) / t["contact_fraction"]
        dg = abs(v["mean_gap"] - t["mean_gap"]) / t["mean_gap"]
        print(f"| {f:g} | {t['contact_fraction']:.6f} | {v['contact_fraction']:.6f} | {da:.1e} | "
              f"{t['mean_gap']:.9e} | {v['mean_gap']:.9e} | {dg:.1e} |")
    print()
    print(f"| p0/E* | Tamaas 1 thread [s] | viscoslide 1 thread [s] | ratio | "
          f"Tamaas {cores} threads [s] | viscoslide {cores} threads [s] | ratio | "
          "viscoslide iterations / matvecs |")
    print("|---|---|---|---|---|---|---|---|")
    for f, t1, v1, tn, vn in zip(FRACTIONS, tam1, vs1, tamn, vsn):
        print(f"| {f:g} | {t1['seconds']:.3f} | {v1['seconds']:.3f} | "
              f"{v1['seconds'] / t1['seconds']:.2f} | {tn['seconds']:.3f} | {vn['seconds']:.3f} | "
              f"{vn['seconds'] / tn['seconds']:.2f} | {v1['iterations']} / {v1['matvecs']} |")
        rows.append({"p0_over_estar": f, "tamaas_1": t1, "tamaas_all": tn,
                     "viscoslide_1": v1, "viscoslide_all": vn})
    with open(os.path.join(out, "results.json"), "w") as fh:
        json.dump(rows, fh, indent=1)


if __name__ == "__main__":
    main()
