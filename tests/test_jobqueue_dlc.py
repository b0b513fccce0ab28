"""``pygear batch --dlc --cluster slurm|pbs`` through dask-jobqueue, against a stand-in
scheduler: ``sbatch``/``qsub`` scripts on PATH that keep the job script and run it
here, in a session of its own, and ``scancel``/``qdel`` that end that session.

What is checked is pygear's side of a job queue: the job script dask-jobqueue writes
from the command's options (queue, wall time, memory, one single-threaded worker per
core), the submission and cancellation commands it calls, and that the workers the jobs
start run the load cases and are stopped when the batch ends.
"""

from __future__ import annotations

import json
import os
import subprocess
import sys
import time
from pathlib import Path

import pytest
from test_dlc import small_case

SUBMIT = """#!/bin/bash
# stand-in for {name}: keep the job script, run it here in its own session
script="${{@: -1}}"
n=$(ls "$FAKE_QUEUE_DIR"/job_*.sh 2>/dev/null | wc -l)
copy="$FAKE_QUEUE_DIR/job_$n.sh"
cp "$script" "$copy"
setsid bash "$copy" > "$copy.log" 2>&1 < /dev/null &
echo "$!" >> "$FAKE_QUEUE_DIR/submitted"
echo "{reply}"
"""

CANCEL = """#!/bin/bash
# stand-in for {name}: end the job's session
echo "$1" >> "$FAKE_QUEUE_DIR/cancelled"
kill -TERM -- "-$1" 2>/dev/null
exit 0
"""

QUEUES = {
    "slurm": {
        "submit": ("sbatch", "Submitted batch job $!"),
        "cancel": "scancel",
        "directives": ("#SBATCH -p testq", "#SBATCH -t 00:20:00", "#SBATCH --mem=2G",
                       "#SBATCH --cpus-per-task=1"),  # fmt: skip
    },
    "pbs": {
        "submit": ("qsub", "$!.fakeserver"),
        "cancel": "qdel",
        # 2 GB = 1907.3 MiB, which dask-jobqueue writes rounded up in MB (its MiB)
        "directives": ("#PBS -q testq", "#PBS -l walltime=00:20:00",
                       "#PBS -l select=1:ncpus=1:mem=1908MB"),  # fmt: skip
    },
}


def _stand_in(bin_dir: Path, kind: str) -> None:
    bin_dir.mkdir(exist_ok=True)
    submit, reply = QUEUES[kind]["submit"]
    cancel = QUEUES[kind]["cancel"]
    for name, text in (
        (submit, SUBMIT.format(name=submit, reply=reply)),
        (cancel, CANCEL.format(name=cancel)),
    ):
        path = bin_dir / name
        path.write_text(text)
        path.chmod(0o755)


def _alive(pid: int) -> bool:
    try:
        os.kill(pid, 0)
    except ProcessLookupError:
        return False
    return True


@pytest.mark.slow
@pytest.mark.parametrize("kind", ["slurm", "pbs"])
def test_dlc_batch_on_a_job_queue(tmp_path, kind):
    directory = small_case(tmp_path, f"dlc_{kind}", (10.0,), (1, 2), 0.1)
    queue = tmp_path / "queue"
    queue.mkdir()
    _stand_in(tmp_path / "bin", kind)
    env = {**os.environ, "PATH": f"{tmp_path / 'bin'}:{os.environ['PATH']}",
           "FAKE_QUEUE_DIR": str(queue)}  # fmt: skip
    out = tmp_path / "out"
    command = [sys.executable, "-m", "pygear", "batch", str(directory), "--dlc", "--out",
               str(out), "--cluster", kind, "--queue", "testq", "--walltime", "00:20:00",
               "--memory", "2GB", "--jobs", "1", "--json"]  # fmt: skip
    done = subprocess.run(command, env=env, capture_output=True, text=True, timeout=900)
    assert done.returncode == 0, done.stderr[-3000:]
    report = json.loads(done.stdout)["dlc"][0]
    assert [r["status"] for r in report["load_cases"]] == ["ok", "ok"]
    assert report["load_spectrum"] is not None and Path(report["load_spectrum"]).is_file()
    # one job submitted with the options as the queue's directives, running a worker
    scripts = sorted(queue.glob("job_*.sh"))
    assert len(scripts) == 1
    script = scripts[0].read_text()
    for directive in QUEUES[kind]["directives"]:
        assert directive in script, (directive, script)
    assert "distributed.cli.dask_worker" in script and "--nthreads 1" in script
    # the journal's workers are the job's processes, and the job was cancelled at the end
    journal = (out / f"dlc_{kind}" / "dlc" / "dlc_journal.log").read_text().split()
    assert journal.count("completed") == 2
    job = int((queue / "submitted").read_text().split()[0])
    assert (queue / "cancelled").read_text().split() == [str(job)]
    deadline = time.monotonic() + 60
    while _alive(job) and time.monotonic() < deadline:
        time.sleep(0.2)
    assert not _alive(job)
