"""Processes of a local sweep: one cluster per command, workers that start with the
kernel loaded, and nothing left running when the command returns.

Each check runs a sweep in a fresh interpreter (a session of its own), reads its
children with psutil before it exits, and looks for any process of its session
after it has exited.
"""

from __future__ import annotations

import json
import os
import subprocess
import sys
from pathlib import Path

import psutil

STUDY = Path(__file__).resolve().parent.parent / "cases" / "yang2016_planetary"

SWEEP = """
import json, sys
import distributed
import psutil

started = []


class CountedCluster(distributed.LocalCluster):
    def __init__(self, *args, **kwargs):
        started.append(kwargs.get("n_workers"))
        super().__init__(*args, **kwargs)


distributed.LocalCluster = CountedCluster
from pygear.cli import main

sys.argv = ["pygear", "sweep", {case!r}, "--workers", "2", "--out", {out!r},
            "--param", "planetary.sun_mesh.stiffness=linspace(3e8,7e8,3)",
            "--param", "planetary.ring_mesh.stiffness=4e8,5e8", "--json"]
code = main()
children = [" ".join(child.cmdline()) for child in psutil.Process().children(recursive=True)]
print(json.dumps({{"code": code, "clusters": started, "children": children}}))
"""


def _session_processes(session: int) -> list[str]:
    """Processes (zombies included) whose session is ``session``."""
    found = []
    for process in psutil.process_iter(["pid", "status", "name"]):
        try:
            if os.getsid(process.pid) == session:
                found.append(f"{process.pid} {process.info['name']} {process.info['status']}")
        except (ProcessLookupError, PermissionError, psutil.Error):
            continue
    return found


def test_sweep_command_leaves_no_process_behind(tmp_path):
    script = SWEEP.format(case=str(STUDY), out=str(tmp_path / "sweep"))
    process = subprocess.Popen(
        [sys.executable, "-c", script],
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
        text=True,
        start_new_session=True,  # its session id is its pid: every process it starts shares it
    )
    out, err = process.communicate(timeout=300)
    assert process.returncode == 0, err
    report = json.loads(out.strip().splitlines()[-1])
    assert report["code"] == 0
    assert report["clusters"] == [2]  # one local cluster for the six points
    assert report["children"] == []  # workers, fork server, resource tracker: all ended
    assert _session_processes(process.pid) == []
    assert len(list((tmp_path / "sweep").glob("point_*.nc"))) == 6


def test_local_workers_start_with_the_kernel_loaded():
    """The fork server imported the point code once; each worker forked from it has the
    kernel before its first task, and closing the client ends every child."""
    script = """
import json, sys
import psutil
from pygear.runs.cluster import dask_client

def loaded():
    return "pygear.kernel._kernel" in sys.modules and "pygear.runs.sweep_points" in sys.modules

with dask_client(workers=2) as client:
    workers = client.run(loaded)
children = psutil.Process().children(recursive=True)
print(json.dumps({"workers": list(workers.values()), "children": len(children)}))
"""
    result = subprocess.run(
        [sys.executable, "-c", script], capture_output=True, text=True, timeout=300
    )
    assert result.returncode == 0, result.stderr
    report = json.loads(result.stdout.strip().splitlines()[-1])
    assert report == {"workers": [True, True], "children": 0}


def test_local_workers_run_one_blas_thread():
    """Every local worker limits OpenBLAS to one thread (a thread per core in each of
    two workers oversubscribed the cores)."""
    script = """
import json
from threadpoolctl import threadpool_info
from pygear.runs.cluster import dask_client

def blas_threads():
    return [i["num_threads"] for i in threadpool_info() if i["user_api"] == "blas"]

with dask_client(workers=2) as client:
    threads = client.run(blas_threads)
print(json.dumps(list(threads.values())))
"""
    result = subprocess.run(
        [sys.executable, "-c", script], capture_output=True, text=True, timeout=300,
        env={**os.environ, "OPENBLAS_NUM_THREADS": "2"},
    )
    assert result.returncode == 0, result.stderr
    per_worker = json.loads(result.stdout.strip().splitlines()[-1])
    assert len(per_worker) == 2
    assert all(threads and max(threads) == 1 for threads in per_worker)

