"""Dask clients for batch runs and sweeps: a local cluster, a running scheduler, or a
SLURM/PBS cluster through dask-jobqueue.

Dask is imported only when a client is opened, so ``pygear`` commands that never
scale out do not pay for the import.
"""

from __future__ import annotations

import contextlib
import importlib
import re
import signal
import threading
from collections.abc import Iterator, Mapping
from typing import Any

from ..errors import CaseError

__all__ = [
    "CLUSTER_KINDS",
    "FILE_LOCK",
    "dask_client",
    "task_files",
    "jobqueue_cluster",
    "validate_cluster_options",
]

FILE_LOCK = threading.Lock()
"""Held while a task writes NetCDF files or figures.  Workers may be threads of one
process (``processes=False``): HDF5 is usually built without thread safety and
xarray locks only its file-level calls, and pyplot keeps global state."""


@contextlib.contextmanager
def task_files() -> Iterator[None]:
    """Write or read a task's own files: under :data:`FILE_LOCK`, with Dask's
    synchronous scheduler in force.

    Inside a Dask worker xarray otherwise guards every HDF5 call with a cluster-wide
    lock held by the scheduler, one network round trip each (about 70 ms a point
    file); a task's files are its own, so a lock of the process is enough.
    """
    with FILE_LOCK:
        try:
            import dask
        except ImportError:
            yield
            return
        with dask.config.set(scheduler="synchronous"):
            yield


CLUSTER_KINDS = {"slurm": "SLURMCluster", "pbs": "PBSCluster"}
"""Job-queue systems reached through dask-jobqueue, and the cluster class of each."""

CLUSTER_OPTIONS = ("queue", "walltime", "memory", "cores", "jobs")
"""Options of a job-queue cluster (the ``--queue`` ... ``--jobs`` switches)."""

DEFAULT_MEMORY = "4GB"
"""Memory of one job when none is given."""

_WALLTIME = re.compile(r"^(\d+-)?\d+:\d{2}:\d{2}$")


def _distributed():
    try:
        return importlib.import_module("distributed")
    except ImportError:
        raise CaseError(
            "batch runs and sweeps need Dask: pip install 'dask[distributed]'"
        ) from None


def validate_cluster_options(
    workers: int,
    scheduler: str | None = None,
    cluster: str | None = None,
    cluster_options: Mapping[str, Any] | None = None,
) -> dict[str, Any]:
    """Check the scale-out options before any work; return the job-queue options.

    Raises
    ------
    CaseError
        Naming the option and the rule it breaks.
    """
    if isinstance(workers, bool) or not isinstance(workers, int) or workers < 1:
        raise CaseError(f"--workers must be a whole number >= 1 (got {workers!r})")
    if scheduler is not None and cluster is not None:
        raise CaseError("--scheduler and --cluster exclude each other: give one")
    if scheduler is not None and (not isinstance(scheduler, str) or not scheduler.strip()):
        raise CaseError(
            f"--scheduler must be an address such as tcp://host:8786 (got {scheduler!r})"
        )
    options = {k: v for k, v in dict(cluster_options or {}).items() if v is not None}
    if cluster is None:
        if options:
            raise CaseError(
                f"--{next(iter(options))} applies to a job-queue cluster: add --cluster slurm|pbs"
            )
        return {}
    if cluster not in CLUSTER_KINDS:
        raise CaseError(f"--cluster must be one of {', '.join(CLUSTER_KINDS)} (got {cluster!r})")
    unknown = sorted(set(options) - set(CLUSTER_OPTIONS))
    if unknown:
        raise CaseError(
            f"cluster option {unknown[0]!r} is unknown (known: {', '.join(CLUSTER_OPTIONS)})"
        )
    for name in ("cores", "jobs"):
        value = options.get(name)
        if value is not None and (
            isinstance(value, bool) or not isinstance(value, int) or value < 1
        ):
            raise CaseError(f"--{name} must be a whole number >= 1 (got {value!r})")
    walltime = options.get("walltime")
    if walltime is not None and not _WALLTIME.match(str(walltime)):
        raise CaseError(f"--walltime must read HH:MM:SS or D-HH:MM:SS (got {walltime!r})")
    memory = options.setdefault("memory", DEFAULT_MEMORY)
    try:
        from dask.utils import parse_bytes

        if parse_bytes(str(memory)) <= 0:
            raise ValueError
    except ImportError:
        pass  # checked again when the cluster starts
    except (ValueError, TypeError):
        raise CaseError(f"--memory must be an amount such as 4GB (got {memory!r})") from None
    options.setdefault("cores", 1)
    return options


def jobqueue_cluster(kind: str, options: Mapping[str, Any]):
    """A dask-jobqueue cluster of ``kind`` ("slurm" or "pbs"), not yet scaled.

    Each job runs ``cores`` single-threaded worker processes (a point is Python and
    LAPACK calls, so processes scale better than threads) with ``memory`` between them.

    Raises
    ------
    CaseError
        When dask-jobqueue is not installed.
    """
    # importing dask_jobqueue replaces the SIGINT handler (Ctrl-C would exit at once
    # instead of raising KeyboardInterrupt): keep ours
    handler = signal.getsignal(signal.SIGINT)
    try:
        jobqueue = importlib.import_module("dask_jobqueue")
    except ImportError:
        raise CaseError(
            f"--cluster {kind} needs dask-jobqueue, which is not installed: "
            "pip install dask-jobqueue"
        ) from None
    finally:
        if handler is not None and threading.current_thread() is threading.main_thread():
            signal.signal(signal.SIGINT, handler)
    cluster_class = getattr(jobqueue, CLUSTER_KINDS[kind])
    cores = options.get("cores", 1)
    kwargs = {"cores": cores, "processes": cores, "memory": options.get("memory", DEFAULT_MEMORY)}
    for name in ("queue", "walltime"):
        if options.get(name) is not None:
            kwargs[name] = options[name]
    return cluster_class(**kwargs)


@contextlib.contextmanager
def dask_client(
    *,
    workers: int = 2,
    scheduler: str | None = None,
    cluster: str | None = None,
    cluster_options: Mapping[str, Any] | None = None,
    processes: bool = True,
) -> Iterator[Any]:
    """A ``distributed.Client``, closed (with any cluster it started) on exit.

    Parameters
    ----------
    workers : int
        Workers of the local cluster (or of the job-queue cluster when no ``jobs``).
    scheduler : str, optional
        Address of a running scheduler; its workers are used and left running.
    cluster : {"slurm", "pbs"}, optional
        Start a job-queue cluster with ``cluster_options`` (queue, walltime,
        memory, cores per job, jobs).
    processes : bool
        Local cluster only: one process per worker (True) or threads in this process.
    """
    options = validate_cluster_options(workers, scheduler, cluster, cluster_options)
    distributed = _distributed()
    started = None
    if scheduler is not None:
        target = scheduler
    elif cluster is not None:
        started = target = jobqueue_cluster(cluster, options)
        if options.get("jobs"):
            started.scale(jobs=options["jobs"])
        else:
            started.scale(n=workers)
    else:
        started = target = distributed.LocalCluster(
            n_workers=workers,
            threads_per_worker=1,
            processes=processes,
            dashboard_address=None,
        )
    try:
        try:
            client = distributed.Client(target, set_as_default=False)
        except OSError as error:
            raise CaseError(f"--scheduler {scheduler!r}: cannot connect ({error})") from None
        try:
            yield client
        finally:
            client.close()
    finally:
        if started is not None:
            started.close()
