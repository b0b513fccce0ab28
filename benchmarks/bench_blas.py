"""Benchmark: the kernel's cost per step under two builds of its BLAS, in paired processes.

The kernel links the OpenBLAS of the scipy-openblas32 wheel (the build NumPy and SciPy
ship). An earlier build linked the system's OpenBLAS (Debian 0.3.21), which falls back to
generic kernels on CPUs it does not know. Give that build's extension with ``--other``
(a copy of ``_kernel*.so`` from such a build): the two run in alternating child processes,
each printing the BLAS core it runs and its microseconds per step on the study case's
run-up (median of repeats inside the child, then median over the pairs). Without
``--other`` it measures the installed kernel alone, also under ``OPENBLAS_CORETYPE``
values given with ``--cores`` (e.g. ``Prescott``, the generic fallback).

Usage::

    python benchmarks/bench_blas.py [--other OLD_KERNEL.so] [--cores Prescott,Haswell]
"""

from __future__ import annotations

import argparse
import importlib.util
import json
import os
import statistics
import subprocess
import sys
from pathlib import Path


def child(kernel_path: str | None, steps: int, repeats: int) -> None:
    """Run inside a child process: load the kernel (optionally another build), time it."""
    if kernel_path:
        spec = importlib.util.spec_from_file_location("pygear.kernel._kernel", kernel_path)
        module = importlib.util.module_from_spec(spec)
        sys.modules["pygear.kernel._kernel"] = module
        spec.loader.exec_module(module)
    sys.path.insert(0, str(Path(__file__).resolve().parent))
    from bench_newmark import kernel_run, problem_for
    from threadpoolctl import threadpool_info

    problem = problem_for(steps)
    kernel_run(problem, 1000)  # warm-up
    times = []
    for _ in range(repeats):
        result = kernel_run(problem, steps)
        times.append(result.solver_wall_s / result.steps * 1e6)
    numpy_paths = ("numpy.libs", "scipy.libs")
    cores = [
        f"{info['version']} {info['architecture']}"
        for info in threadpool_info()
        if info.get("user_api") == "blas" and not any(p in info["filepath"] for p in numpy_paths)
    ]
    print(json.dumps({"us_per_step": statistics.median(times), "blas": cores}))


def measure(kernel_path: str | None, env: dict, steps: int, repeats: int) -> dict:
    command = [sys.executable, __file__, "--child", "--steps", str(steps)]
    command += ["--repeats", str(repeats)]
    if kernel_path:
        command += ["--kernel", kernel_path]
    output = subprocess.run(command, env=env, capture_output=True, text=True, check=True).stdout
    return json.loads(output.strip().splitlines()[-1])


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--other", help="another build's _kernel*.so to compare against")
    parser.add_argument("--cores", default="", help="OPENBLAS_CORETYPE values, comma-separated")
    parser.add_argument("--steps", type=int, default=100_000)
    parser.add_argument("--repeats", type=int, default=5, help="timed runs per process")
    parser.add_argument("--pairs", type=int, default=3, help="alternating process pairs")
    parser.add_argument("--child", action="store_true", help=argparse.SUPPRESS)
    parser.add_argument("--kernel", help=argparse.SUPPRESS)
    args = parser.parse_args()
    if args.child:
        child(args.kernel, args.steps, args.repeats)
        return

    base_env = {k: v for k, v in os.environ.items() if k != "OPENBLAS_CORETYPE"}
    variants = [("installed kernel", None, base_env)]
    if args.other:
        variants.append(("--other kernel", args.other, base_env))
    for core in filter(None, args.cores.split(",")):
        variants.append((f"installed, OPENBLAS_CORETYPE={core}", None, base_env | {
            "OPENBLAS_CORETYPE": core}))
    results: dict[str, list[dict]] = {name: [] for name, _, _ in variants}
    for _ in range(args.pairs):
        for name, path, env in variants:
            results[name].append(measure(path, env, args.steps, args.repeats))
    reference = statistics.median(r["us_per_step"] for r in results["installed kernel"])
    print(f"study case run-up, {args.steps} steps, {args.pairs} alternating processes each")
    for name, runs in results.items():
        value = statistics.median(r["us_per_step"] for r in runs)
        print(f"{name:<36} {value:7.3f} us/step  ({value / reference:5.2f} x installed)  "
              f"BLAS {', '.join(runs[0]['blas'])}")


if __name__ == "__main__":
    main()
