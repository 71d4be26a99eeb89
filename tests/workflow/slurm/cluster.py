"""A throwaway single-node SLURM cluster on this machine, for tests (root only).

    python tests/slurm/cluster.py start [DIR]   # prints `export SLURM_CONF=DIR/slurm.conf`
    python tests/slurm/cluster.py stop DIR

or, from Python, ``with LocalCluster() as cluster: ...`` (``cluster.env`` has ``SLURM_CONF``).

What it does: installs Debian's ``slurmctld slurmd slurm-client munge`` with apt when they are
missing (root only); writes a ``slurm.conf`` into a fresh folder (one node ``localhost`` at
127.0.0.1 with this machine's CPUs and memory, ``select/cons_tres`` + ``CR_Core_Memory`` so
jobs of one CPU share the node, ``MinJobAge=300`` s so ``squeue`` still reports finished jobs
for the executor plugin, job completions logged to ``jobcomp.txt``, no accounting daemon);
starts ``munged -F`` (as user munge; only when no munged answers yet), ``slurmctld -D -i`` and
``slurmd -D -N localhost`` in the background, and waits until ``sinfo`` shows the node idle.
Stopping cancels every job first (``scancel``; job steps would outlive ``slurmd`` otherwise),
then ends exactly the processes it started, by process id, and removes the folder.

Everything stays on this machine: the daemons talk over 127.0.0.1 on two free ports picked at
start, munge over its Unix socket. No systemd is needed.
"""

from __future__ import annotations

import json
import os
import shutil
import signal
import socket
import subprocess
import sys
import tempfile
import time
from pathlib import Path

from conftest import apt_install

PACKAGES = ["slurmctld", "slurmd", "slurm-client", "munge"]
BINARIES = (
    "munged",
    "munge",
    "unmunge",
    "slurmctld",
    "slurmd",
    "sinfo",
    "sbatch",
    "squeue",
    "scancel",
    "scontrol",
    "srun",
)
PARTITION = "uavdamp"
SYSTEM_CONF = Path("/etc/slurm/slurm.conf")
# Where SLURM clients look when SLURM_CONF is unset and SYSTEM_CONF is absent (slurmd's configless
# cache). The job-step plugin drops SLURM_CONF from the environment of its inner `srun`, so the
# jobs find the throwaway cluster's config through this link.
RUN_CONF = Path("/run/slurm/conf/slurm.conf")
MIN_JOB_AGE_S = 300  # >= 3 x the plugin's status interval (its default 40 s, 2 s in the tests)


class ClusterUnavailable(RuntimeError):
    """The cluster cannot be started here; the message says why (tests skip with it)."""


def _free_port() -> int:
    with socket.socket(socket.AF_INET, socket.SOCK_STREAM) as sock:
        sock.bind(("127.0.0.1", 0))
        return sock.getsockname()[1]


def _mem_total_mb() -> int:
    for line in Path("/proc/meminfo").read_text().splitlines():
        if line.startswith("MemTotal:"):
            return int(line.split()[1]) // 1024
    raise ClusterUnavailable("no MemTotal in /proc/meminfo")


def _missing_binaries() -> list[str]:
    return [name for name in BINARIES if shutil.which(name) is None and not Path("/usr/sbin", name).exists()]


def ensure_packages(log=print) -> None:
    """Install the Debian packages when a binary is missing; ClusterUnavailable when that cannot be."""
    if not _missing_binaries():
        return
    why = apt_install(PACKAGES, log)
    if why is not None:
        raise ClusterUnavailable(f"SLURM/munge not installed ({', '.join(_missing_binaries())}): {why}")
    if _missing_binaries():
        raise ClusterUnavailable(f"still missing after apt-get: {', '.join(_missing_binaries())}")


def _sbin(name: str) -> str:
    return shutil.which(name) or str(Path("/usr/sbin", name))


def _munge_works() -> bool:
    try:
        cred = subprocess.run(["munge", "-n"], capture_output=True, timeout=10)
        if cred.returncode != 0:
            return False
        check = subprocess.run(["unmunge"], input=cred.stdout, capture_output=True, timeout=10)
        return check.returncode == 0
    except (OSError, subprocess.TimeoutExpired):
        return False


class LocalCluster:
    """One node, one partition, on 127.0.0.1; see the module docstring."""

    def __init__(self, root: Path | None = None, cpus: int | None = None, log=print):
        self.root = Path(root) if root else Path(tempfile.mkdtemp(prefix="uavdamp-slurm-"))
        self.cpus = cpus or os.cpu_count() or 1
        self.log = log
        self.pids: dict[str, int] = {}
        self._procs: dict[str, subprocess.Popen] = {}
        self.conf = self.root / "slurm.conf"
        self.jobcomp = self.root / "log" / "jobcomp.txt"
        self.partition = PARTITION
        self.started_s: float | None = None

    # -- environment for clients (sbatch, squeue, snakemake and the jobs it submits) --
    @property
    def env(self) -> dict[str, str]:
        return {"SLURM_CONF": str(self.conf)}

    def run(self, *cmd: str, timeout: float = 30, check: bool = True) -> subprocess.CompletedProcess:
        result = subprocess.run(
            list(cmd), env=dict(os.environ, **self.env), capture_output=True, text=True, timeout=timeout
        )
        if check and result.returncode != 0:
            raise RuntimeError(f"{' '.join(cmd)} failed ({result.returncode}): {result.stderr.strip()}")
        return result

    # -- start --
    def _write_conf(self) -> None:
        for sub in ("state", "spool", "run", "log"):
            (self.root / sub).mkdir(parents=True, exist_ok=True)
        self.root.chmod(0o755)  # slurmctld runs as user slurm and must reach its folders
        for sub in ("state", "run", "log"):
            shutil.chown(self.root / sub, "slurm", "slurm")
        self.jobcomp.touch()
        shutil.chown(self.jobcomp, "slurm", "slurm")
        mem_mb = int(_mem_total_mb() * 0.9)
        ctld_port, slurmd_port = _free_port(), _free_port()
        while slurmd_port == ctld_port:
            slurmd_port = _free_port()
        r = self.root
        self.conf.write_text(f"""\
# written by tests/slurm/cluster.py: a throwaway single-node cluster, 127.0.0.1 only
ClusterName=uavdamp
SlurmctldHost=localhost(127.0.0.1)
SlurmctldPort={ctld_port}
SlurmdPort={slurmd_port}
SlurmUser=slurm
SlurmdUser=root
AuthType=auth/munge
CommunicationParameters=NoCtldInAddrAny,NoInAddrAny
CredType=cred/munge
StateSaveLocation={r}/state
SlurmdSpoolDir={r}/spool
SlurmctldPidFile={r}/run/slurmctld.pid
SlurmdPidFile={r}/run/slurmd.pid
SlurmctldLogFile={r}/log/slurmctld.log
SlurmdLogFile={r}/log/slurmd.log
SlurmctldDebug=info
SlurmdDebug=info
ProctrackType=proctrack/linuxproc
TaskPlugin=task/none
MpiDefault=none
SchedulerType=sched/backfill
SelectType=select/cons_tres
SelectTypeParameters=CR_Core_Memory
ReturnToService=2
MinJobAge={MIN_JOB_AGE_S}
KillWait=5
InactiveLimit=0
AccountingStorageType=accounting_storage/none
JobAcctGatherType=jobacct_gather/none
JobCompType=jobcomp/filetxt
JobCompLoc={self.jobcomp}
NodeName=localhost NodeAddr=127.0.0.1 CPUs={self.cpus} RealMemory={mem_mb} State=UNKNOWN
PartitionName={self.partition} Nodes=localhost Default=YES MaxTime=INFINITE State=UP
""")

    def _spawn(self, name: str, cmd: list[str], user: str | None = None) -> None:
        out = open(self.root / "log" / f"{name}.console", "wb")
        proc = subprocess.Popen(
            cmd,
            stdout=out,
            stderr=subprocess.STDOUT,
            stdin=subprocess.DEVNULL,
            env=dict(os.environ, **self.env),
            user=user,
            start_new_session=True,
        )
        out.close()
        self._procs[name] = proc
        self.pids[name] = proc.pid
        self._save_pids()

    def _save_pids(self) -> None:
        (self.root / "pids.json").write_text(json.dumps(self.pids))

    def _start_munge(self) -> None:
        if _munge_works():
            self.log("munged already answers; using it (and leaving it running)")
            return
        key = Path("/etc/munge/munge.key")
        if not key.exists():
            subprocess.run(["mungekey", "--create"], check=True, capture_output=True)
            shutil.chown(key, "munge", "munge")
            key.chmod(0o600)
        run_dir = Path("/run/munge")
        run_dir.mkdir(parents=True, exist_ok=True)
        shutil.chown(run_dir, "munge", "munge")
        run_dir.chmod(0o755)
        self._spawn("munged", [_sbin("munged"), "-F"], user="munge")
        self._wait(_munge_works, 15, "munged")

    def _wait(self, ready, timeout: float, what: str) -> None:
        end = time.monotonic() + timeout
        while time.monotonic() < end:
            for name, proc in self._procs.items():
                if proc.poll() is not None:
                    raise ClusterUnavailable(
                        f"{name} exited with {proc.returncode} while waiting for {what}: " + self._tail(name)
                    )
            if ready():
                return
            time.sleep(0.2)
        raise ClusterUnavailable(
            f"{what} not ready after {timeout:.0f} s: " + self._tail("slurmctld") + self._tail("slurmd")
        )

    def _tail(self, name: str) -> str:
        texts = []
        for path in (self.root / "log" / f"{name}.console", self.root / "log" / f"{name}.log"):
            if path.exists():
                texts.append(path.read_text(errors="replace")[-1500:])
        return f"\n--- {name} ---\n" + "\n".join(texts)

    def node_state(self) -> str:
        result = self.run("sinfo", "-h", "-N", "-o", "%T", timeout=10, check=False)
        return result.stdout.strip() if result.returncode == 0 else ""

    def start(self, timeout: float = 60) -> LocalCluster:
        t0 = time.monotonic()
        if os.geteuid() != 0:
            raise ClusterUnavailable("not root: starting slurmctld/slurmd/munged needs root")
        ensure_packages(self.log)
        if SYSTEM_CONF.exists():
            raise ClusterUnavailable(
                f"{SYSTEM_CONF} exists (a real SLURM install?): jobs would use it, not the throwaway cluster"
            )
        _stop_leftover()
        if RUN_CONF.is_symlink() and not RUN_CONF.exists():
            RUN_CONF.unlink()  # dangling: left by a throwaway cluster whose folder is gone
        if RUN_CONF.exists() or RUN_CONF.is_symlink():
            raise ClusterUnavailable(f"{RUN_CONF} exists: another SLURM cluster (or a leftover one) is here")
        self._write_conf()
        RUN_CONF.parent.mkdir(parents=True, exist_ok=True)
        RUN_CONF.symlink_to(self.conf)
        try:
            self._start_munge()
            self._spawn("slurmctld", [_sbin("slurmctld"), "-D", "-i", "-f", str(self.conf)])
            self._wait(
                lambda: self.run("scontrol", "ping", timeout=10, check=False).stdout.count("UP") > 0,
                timeout,
                "slurmctld",
            )
            self._spawn("slurmd", [_sbin("slurmd"), "-D", "-N", "localhost", "-f", str(self.conf)])
            self._wait(lambda: self.node_state() == "idle", timeout, "node idle in sinfo")
        except BaseException:
            self.stop(remove=False)
            raise
        self.started_s = time.monotonic() - t0
        self.log(f"SLURM cluster up in {self.started_s:.1f} s: SLURM_CONF={self.conf}")
        return self

    # -- queries for tests --
    def job_record(self, jobid: str) -> dict[str, str]:
        """`scontrol show job` as a dict (finished jobs stay for MinJobAge); {} when unknown."""
        result = self.run("scontrol", "show", "job", "-o", str(jobid), check=False)
        if result.returncode != 0:
            return {}
        record = {}
        for field in result.stdout.split():
            key, _, value = field.partition("=")
            record.setdefault(key, value)
        return record

    def completed_jobs(self) -> dict[str, dict[str, str]]:
        """Job completion records (jobcomp/filetxt), by job id: JobState, JobName, NodeList, ..."""
        records = {}
        for line in self.jobcomp.read_text().splitlines():
            record = {}
            for field in line.split():
                key, _, value = field.partition("=")
                record.setdefault(key, value)
            if "JobId" in record:
                records[record["JobId"]] = record
        return records

    # -- stop --
    def cancel_all_jobs(self, timeout: float = 30) -> None:
        if "slurmctld" not in self._procs or self._procs["slurmctld"].poll() is not None:
            return
        ids = self.run("squeue", "-h", "-o", "%i", check=False).stdout.split()
        if ids:
            self.run("scancel", *ids, check=False)
        end = time.monotonic() + timeout
        while time.monotonic() < end:
            active = self.run("squeue", "-h", "-t", "PD,R,CG,S", "-o", "%i", check=False).stdout.split()
            if not active:
                return
            time.sleep(0.5)
        self.log(f"jobs still active after scancel: {active}")

    def stop(self, remove: bool = True) -> None:
        try:
            self.cancel_all_jobs()
        except (RuntimeError, subprocess.TimeoutExpired, OSError) as exc:
            self.log(f"scancel failed: {exc}")
        for name in ("slurmd", "slurmctld", "munged"):
            pid = self.pids.get(name)
            if pid is None:
                continue
            proc = self._procs.get(name)
            _terminate(pid, proc)
            del self.pids[name]
            self._procs.pop(name, None)
            self._save_pids()
        _unlink_run_conf(self.conf)
        if remove:
            shutil.rmtree(self.root, ignore_errors=True)

    def __enter__(self) -> LocalCluster:
        return self.start()

    def __exit__(self, *exc) -> None:
        self.stop()


def _is_process(pid: int, name: str) -> bool:
    """True when `pid` runs the program `name` (guards against a reused process id)."""
    try:
        argv0 = Path(f"/proc/{pid}/cmdline").read_bytes().split(b"\0")[0].decode()
    except OSError:
        return False
    return Path(argv0).name == name


def _terminate(pid: int, proc: subprocess.Popen | None, grace: float = 10) -> None:
    """SIGTERM exactly this process, SIGKILL it after `grace` s; reap it when it is our child."""
    try:
        os.kill(pid, signal.SIGTERM)
    except ProcessLookupError:
        return
    end = time.monotonic() + grace
    while time.monotonic() < end:
        if proc is not None:
            if proc.poll() is not None:
                return
        else:
            try:
                os.kill(pid, 0)
            except ProcessLookupError:
                return
        time.sleep(0.1)
    try:
        os.kill(pid, signal.SIGKILL)
    except ProcessLookupError:
        return
    if proc is not None:
        proc.wait(timeout=5)


def _unlink_run_conf(conf: Path) -> None:
    """Remove RUN_CONF when it is our link (never someone else's file)."""
    if RUN_CONF.is_symlink() and Path(os.readlink(RUN_CONF)) == conf:
        RUN_CONF.unlink()


def _stop_from_dir(root: Path) -> None:
    """`stop DIR` from another process: scancel, then end the PIDs recorded in DIR/pids.json."""
    pids = json.loads((root / "pids.json").read_text())
    env = dict(os.environ, SLURM_CONF=str(root / "slurm.conf"))
    if "slurmctld" in pids:
        ids = subprocess.run(["squeue", "-h", "-o", "%i"], env=env, capture_output=True, text=True).stdout.split()
        if ids:
            subprocess.run(["scancel", *ids], env=env, capture_output=True)
            time.sleep(2)
    for name in ("slurmd", "slurmctld", "munged"):
        if name in pids and _is_process(pids[name], name):
            _terminate(pids[name], None)
    _unlink_run_conf(root / "slurm.conf")
    shutil.rmtree(root, ignore_errors=True)


def _stop_leftover() -> None:
    """Stop a throwaway cluster of this script left running by a killed test (its PIDs are on record)."""
    if not RUN_CONF.is_symlink():
        return
    root = Path(os.readlink(RUN_CONF)).parent
    if root.name.startswith("uavdamp-slurm-") and (root / "pids.json").exists():
        print(f"stopping a leftover throwaway cluster in {root}", file=sys.stderr)
        _stop_from_dir(root)


def main(argv: list[str]) -> int:
    if len(argv) >= 2 and argv[1] == "start":
        root = Path(argv[2]) if len(argv) > 2 else None
        cluster = LocalCluster(root, log=lambda msg: print(msg, file=sys.stderr))
        try:
            cluster.start()
        except ClusterUnavailable as exc:
            print(f"cannot start the cluster: {exc}", file=sys.stderr)
            return 1
        # the daemons were started in their own sessions: they outlive this process
        print(f"export SLURM_CONF={cluster.conf}")
        print(f"# stop with: python {argv[0]} stop {cluster.root}", file=sys.stderr)
        return 0
    if len(argv) == 3 and argv[1] == "stop":
        _stop_from_dir(Path(argv[2]))
        return 0
    print(__doc__, file=sys.stderr)
    return 2


if __name__ == "__main__":
    sys.exit(main(sys.argv))
