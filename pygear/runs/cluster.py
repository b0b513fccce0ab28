"""Dask clients for batch runs and sweeps: a local cluster, a running scheduler, or a
SLURM/PBS cluster through dask-jobqueue.

Dask is imported only when a client is opened, so ``pygear`` commands that never
scale out do not pay for the import.  A local cluster's worker processes are forked
from one fork server that has imported pygear's point and scene code (the kernel
among it) once, so no worker imports it again, and when the client closes, the fork
server and multiprocessing's resource tracker stop with the workers: the command
leaves no process behind.
"""

from __future__ import annotations

import contextlib
import importlib
import multiprocessing
import os
import re
import signal
import sys
import threading
from collections.abc import Iterator, Mapping
from typing import Any

from ..errors import CaseError

__all__ = [
    "CLUSTER_KINDS",
    "FILE_LOCK",
    "WORKER_MODULES",
    "local_worker_server",
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
        dask = sys.modules.get("dask")  # loaded in every worker; a plain run never loads it
        if dask is None:
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
    kwargs = {
        "cores": cores,
        "processes": cores,
        "memory": options.get("memory", DEFAULT_MEMORY),
        "scheduler_options": {"dashboard": False, "dashboard_address": ":0"},  # no 8787 clash
    }
    for name in ("queue", "walltime"):
        if options.get(name) is not None:
            kwargs[name] = options[name]
    return cluster_class(**kwargs)


WORKER_MODULES = (
    "distributed",
    "dask.array",
    "netCDF4",
    "pygear.analysis.time.transient",
    "pygear.analysis.signals.analyze",
    "pygear.runs.sweep_points",
    "pygear.runs.batch",
    "pygear.runs.dlc",
)
"""What the fork server of the local workers imports before it forks them: a sweep
point's, batch scene's or design load case's code, xarray's Dask arrays and NetCDF.
Imported once per command instead of once per worker on its first task (1-1.5 s each
on the study case's run-up points)."""


def _helper_pids() -> dict[str, int | None]:
    """Process ids of multiprocessing's fork server and resource tracker (None: not
    running), read without starting them."""
    found: dict[str, int | None] = {}
    for module, attribute in (
        ("multiprocessing.forkserver", "_forkserver"),
        ("multiprocessing.resource_tracker", "_resource_tracker"),
    ):
        helper = getattr(sys.modules.get(module), attribute, None)
        found[module] = getattr(helper, "_forkserver_pid", getattr(helper, "_pid", None))
    return found


def _stop_helpers(running_before: dict[str, int | None], tracker: bool = True) -> None:
    """Stop the fork server and resource tracker the local workers started.

    Both are children of this process that live until it exits (the tracker ends only
    once the fork server, which holds its pipe, has ended): stopped here, in that
    order, and waited for, a command that ran a local cluster leaves no process behind.
    The fork server is killed rather than asked: its workers are gone and it holds
    nothing, and its orderly exit (unloading the modules it imported) took 0.3 s.
    Helpers that were running before the cluster started are left alone.

    ``tracker=False`` (after a Ctrl-C) leaves the resource tracker to end with this
    process: a cluster interrupted while it started may still hold semaphores, which a
    tracker stopped now would report as leaked and unlink under their owners' feet (a
    warning and a traceback each at exit); it ends, quietly, once this process has.
    """
    now = _helper_pids()
    for module, attribute in (
        ("multiprocessing.forkserver", "_forkserver"),
        ("multiprocessing.resource_tracker", "_resource_tracker"),
    ):
        if running_before.get(module) is not None or now.get(module) is None:
            continue
        if module == "multiprocessing.resource_tracker" and not tracker:
            continue
        if module == "multiprocessing.forkserver":
            with contextlib.suppress(ProcessLookupError):
                os.kill(now[module], signal.SIGKILL)
        stop = getattr(getattr(sys.modules.get(module), attribute, None), "_stop", None)
        if callable(stop):
            stop()  # closes its pipe and waits for it


def _start_fork_server() -> bool:
    """Start the fork server of local workers, importing :data:`WORKER_MODULES`, unless
    one runs; False where there is none (not POSIX: workers are spawned)."""
    if "forkserver" not in multiprocessing.get_all_start_methods():
        return False
    from multiprocessing import forkserver

    if _helper_pids()["multiprocessing.forkserver"] is None:
        from multiprocessing import resource_tracker

        forkserver.set_forkserver_preload(list(WORKER_MODULES))
        # the tracker first: starting it unblocks SIGINT, which the server must inherit
        resource_tracker.ensure_running()
        with _sigint_blocked():
            forkserver.ensure_running()  # returns at once; the server imports on its own
    return True


@contextlib.contextmanager
def _sigint_blocked() -> Iterator[None]:
    """SIGINT blocked in this thread while the fork server starts: the server, and every
    worker it forks, inherit the blocked signal, so a Ctrl-C at the terminal (sent to the
    whole process group) reaches this process alone, which closes the cluster in order
    (:func:`dask_client`) instead of every worker dying with its own traceback."""
    if not hasattr(signal, "pthread_sigmask"):
        yield
        return
    previous = signal.pthread_sigmask(signal.SIG_BLOCK, {signal.SIGINT})
    try:
        yield
    finally:
        signal.pthread_sigmask(signal.SIG_SETMASK, previous)  # nested: stays blocked


@contextlib.contextmanager
def _forked_workers() -> Iterator[None]:
    """Local worker processes forked from a fork server that imported
    :data:`WORKER_MODULES` (POSIX; elsewhere workers are spawned, as Dask's default)."""
    if not _start_fork_server():
        yield
        return
    import dask

    with dask.config.set({"distributed.worker.multiprocessing-method": "forkserver"}):
        yield


@contextlib.contextmanager
def local_worker_server(local: bool = True) -> Iterator[None]:
    """Start the local workers' fork server at once, and stop what it started at the end.

    A command that will start a local cluster calls this first: the server imports
    :data:`WORKER_MODULES` (1-1.5 s) while the command loads its own modules and checks
    its input, instead of after.  Nothing runs on the input before the checks pass; a
    refused input only stops the server again.  ``local=False`` (a running scheduler,
    a job queue) does nothing.
    """
    if not local:
        yield
        return
    running_before = _helper_pids()
    interrupted = False
    try:
        _start_fork_server()
        yield
    except KeyboardInterrupt:
        interrupted = True
        raise
    finally:
        _stop_helpers(running_before, tracker=not interrupted)


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
    started = client = None
    helpers = _helper_pids()
    interrupted: list[bool] = []
    with contextlib.ExitStack() as stack:
        if scheduler is None and cluster is None and processes:
            # the fork server first: starting multiprocessing's helpers unblocks SIGINT;
            # stopped last, after the cluster closed
            stack.callback(lambda: _stop_helpers(helpers, tracker=not interrupted))
            stack.enter_context(_forked_workers())
        try:
            # a Ctrl-C while the cluster starts waits until it can be closed again
            with _sigint_blocked():
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
                        scheduler_kwargs=NO_DASHBOARD,
                    )
                try:
                    client = distributed.Client(target, set_as_default=False)
                except OSError as error:
                    raise CaseError(
                        f"--scheduler {scheduler!r}: cannot connect ({error})"
                    ) from None
                if started is not None:  # our own workers: one task, one BLAS thread each
                    client.run(one_blas_thread)
            yield client
        except KeyboardInterrupt:
            interrupted.append(True)
            _quiet_dask()  # the cluster closes below: its complaints are no news
            if started is not None and client is not None:
                with contextlib.suppress(Exception):  # the workers say nothing either
                    client.run(_quiet_dask)
            raise
        finally:
            try:
                if client is not None:
                    client.close()
            finally:
                if started is not None:
                    _close_cluster(started)


def one_blas_thread() -> None:
    """Limit this worker process to one BLAS thread.  A worker runs one task at a time
    (``threads_per_worker=1``), but OpenBLAS starts a thread per core in every process:
    two workers on two cores would run four BLAS threads, each solve waiting on the
    others (a 144 x 144 solve took 225 ms instead of 1.8 ms on a loaded machine)."""
    from threadpoolctl import threadpool_limits

    threadpool_limits(1, user_api="blas")


NO_DASHBOARD = {"dashboard": False, "dashboard_address": "127.0.0.1:0"}
"""The scheduler's options: no dashboard, and its bare HTTP server on a free port of the
loopback interface.  Dask binds that server to port 8787 even without a dashboard, and
warns when another cluster holds the port; a port of 0 is never "in use"."""


def _quiet_dask() -> None:
    """Dask's loggers at CRITICAL and its warnings ignored for the rest of the command:
    after a Ctrl-C the cluster shuts down with work in flight, and what Dask says about
    that (cancelled futures, killed workers, leaked semaphores) is not the user's news."""
    import logging
    import warnings

    for name in ("distributed", "dask", "tornado", "asyncio"):
        logging.getLogger(name).setLevel(logging.CRITICAL)
    warnings.filterwarnings("ignore")


def _close_cluster(cluster) -> None:
    """Close a cluster this command started and wait for its workers to end; a second
    Ctrl-C while it closes does not leave the workers running."""
    try:
        cluster.close()
    except KeyboardInterrupt:
        _quiet_dask()
        cluster.close()
        raise
