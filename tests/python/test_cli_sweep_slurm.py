"""`lrdslam sweep --executor slurm` against a real Slurm: slurmctld and slurmd (Debian's 22.05) on
127.0.0.1 with a config in a temporary folder (auth/none, cons_tres), started here in the
foreground and stopped by their pids. The same deterministic table through Slurm as through the
local executor; a task cancelled with scancel shows as missing and the next invocation submits
just that index."""
import json
import os
import shutil
import signal
import socket
import subprocess
import time

import pytest

from cli import _fixture_bin, lrdslam

# The sweep machinery and Slurm are under test here, not the runs: they use the release build when
# ctest names one (tests/python/cli.py), as the input sequences do.
BIN = _fixture_bin()

GRID = ["--presets", "walking_xyz,static_xyz", "--frames", 40, "--modes", "static,geometric", "--repeats", 2,
        "--deterministic"]
DAEMONS = ("slurmctld", "slurmd", "sbatch", "squeue", "scancel", "sinfo")


def free_port():
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


CONF = """ClusterName=lrdtest
SlurmctldHost=localhost(127.0.0.1)
SlurmctldPort={ctld_port}
SlurmdPort={d_port}
AuthType=auth/none
CredType=cred/none
ProctrackType=proctrack/linuxproc
TaskPlugin=task/none
SelectType=select/cons_tres
SelectTypeParameters=CR_CPU
SchedulerType=sched/builtin
StateSaveLocation={dir}/state
SlurmdSpoolDir={dir}/spool
SlurmctldPidFile={dir}/slurmctld.pid
SlurmdPidFile={dir}/slurmd.pid
SlurmctldLogFile={dir}/slurmctld.log
SlurmdLogFile={dir}/slurmd.log
SlurmUser=root
SlurmdUser=root
ReturnToService=2
MpiDefault=none
JobCompType=jobcomp/none
AccountingStorageType=accounting_storage/none
JobAcctGatherType=jobacct_gather/none
NodeName=localhost NodeAddr=127.0.0.1 CPUs={cpus} State=UNKNOWN
PartitionName=lrdtest Nodes=localhost Default=YES MaxTime=INFINITE State=UP
"""


@pytest.fixture(scope="module")
def slurm(tmp_path_factory):
    missing = [p for p in DAEMONS if shutil.which(p) is None]
    if missing:
        if os.environ.get("CI"):
            pytest.fail(f"Slurm is not installed ({', '.join(missing)}): scripts/install-deps.sh installs it")
        pytest.skip(f"Slurm is not installed ({', '.join(missing)}): scripts/install-deps.sh installs it")
    if os.geteuid() != 0:
        pytest.skip("slurmd runs jobs as root here: run the test as root")
    d = tmp_path_factory.mktemp("slurm")
    (d / "state").mkdir()
    (d / "spool").mkdir()
    conf = d / "slurm.conf"
    conf.write_text(CONF.format(ctld_port=free_port(), d_port=free_port(), dir=d, cpus=os.cpu_count()))
    env = dict(os.environ, SLURM_CONF=str(conf))
    daemons = [subprocess.Popen(["slurmctld", "-D", "-i", "-f", str(conf)], env=env, stdout=subprocess.DEVNULL,
                                stderr=open(d / "slurmctld.err", "w"), start_new_session=True)]
    time.sleep(1)
    daemons.append(subprocess.Popen(["slurmd", "-D", "-N", "localhost", "-f", str(conf)], env=env,
                                    stdout=subprocess.DEVNULL, stderr=open(d / "slurmd.err", "w"),
                                    start_new_session=True))
    try:
        deadline = time.time() + 30
        while time.time() < deadline:
            r = subprocess.run(["sinfo", "-h", "-o", "%t"], env=env, capture_output=True, text=True)
            if r.stdout.strip() == "idle":
                break
            time.sleep(0.5)
        else:
            pytest.fail("Slurm did not come up:\n" + (d / "slurmctld.log").read_text()[-2000:])
        yield env
    finally:
        subprocess.run(["scancel", "--full", "-u", "root"], env=env, capture_output=True)
        for p in reversed(daemons):
            p.send_signal(signal.SIGTERM)
        for p in reversed(daemons):
            try:
                p.wait(timeout=15)
            except subprocess.TimeoutExpired:
                os.killpg(p.pid, signal.SIGKILL)
                p.wait()


def sweep(env, *args, check=True):
    r = subprocess.run([os.path.abspath(BIN), "sweep", *map(str, args)], env=env, capture_output=True, text=True,
                       timeout=240)
    assert not check or r.returncode == 0, r.stdout + r.stderr
    return r


def squeue(env):
    return subprocess.run(["squeue", "-h", "-r", "-o", "%i %T"], env=env, capture_output=True, text=True).stdout


def ate_table(results):
    return {(e["sequence"], e["mode"]): e["ate_rmse_m"]["runs"] for e in results["entries"]}


def test_slurm_sweep_cancel_resume_and_the_local_table(slurm, tmp_path):
    d = tmp_path / "slurm_sweep"
    # One task at a time, so the last ones are still pending when one is cancelled.
    first = sweep(slurm, "--out", d, *GRID, "--executor", "slurm", "--max-running", 1, "--cpus-per-task", 1)
    jobs = json.loads((d / "slurm" / "jobs.json").read_text())
    array = jobs[0]["array_job"]
    assert f"submitted job array {array} (8 tasks)" in first.stdout and jobs[0]["indices"] == list(range(8))
    subprocess.run(["scancel", f"{array}_6"], env=slurm, check=True)
    deadline = time.time() + 150
    while time.time() < deadline and squeue(slurm).strip():
        time.sleep(1)
    assert not squeue(slurm).strip(), "the sweep's jobs did not finish"
    status = sweep(slurm, "status", d).stdout
    assert "8 cells: 7 done, 0 failed, 1 missing" in status, status
    assert "missing: static_xyz__geometric__default__r0" in status  # index 6
    # The collect job ran after the array (afterany) and wrote the partial table.
    assert json.loads((d / "results.json").read_text())["missing"] == 1
    second = sweep(slurm, "--out", d, *GRID, "--executor", "slurm", "--wait")
    jobs = json.loads((d / "slurm" / "jobs.json").read_text())
    assert "8 cells, 1 to run" in second.stdout and jobs[1]["indices"] == [6]
    through_slurm = json.loads((d / "results.json").read_text())
    assert through_slurm["done"] == 8
    record = json.loads((d / "cells" / "static_xyz__geometric__default__r0" / "result.json").read_text())
    assert record["job_id"] == f"slurm:{jobs[1]['array_job']}_6"
    assert (d / "logs" / f"slurm-{jobs[1]['array_job']}_6.out").is_file()
    # The same deterministic table through the local executor.
    local = tmp_path / "local_sweep"
    lrdslam("sweep", "--out", local, *GRID)
    assert ate_table(json.loads((local / "results.json").read_text())) == ate_table(through_slurm)
