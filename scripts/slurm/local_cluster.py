"""A one-node Slurm cluster on localhost: munged, slurmctld and slurmd, each with its own config,
state and logs under a temporary folder; stopped by their pids (never by name) and the folder
removed at the end, even on failure. Needs root and the Debian packages slurm-wlm and munge.

Used by the tiles test (tests/tiles/cli_tiles_test.py), and to try the Slurm scripts on one machine:
  python3 scripts/slurm/local_cluster.py [--cpus N] -- COMMAND [ARGS...]
runs COMMAND with SLURM_CONF pointing at the cluster (sbatch, squeue... reach it) and exits with
COMMAND's status (docs/tiles.md, "On Slurm")."""
import argparse
import os
import pathlib
import shutil
import signal
import socket
import subprocess
import sys
import tempfile
import time

MUNGE_KEY = pathlib.Path("/etc/munge/munge.key")
DAEMONS = ("munged", "slurmctld", "slurmd", "sbatch")


def missing_programs():
    """The programs the cluster needs that are not installed (scripts/install_deps.sh installs them)."""
    found = {name: shutil.which(name) or shutil.which(name, path="/usr/sbin:/usr/bin") for name in DAEMONS}
    return [name for name, path in found.items() if not path] + ([] if MUNGE_KEY.exists() else [str(MUNGE_KEY)])


def free_ports(count):
    sockets = [socket.socket() for _ in range(count)]
    try:
        for s in sockets:
            s.bind(("127.0.0.1", 0))
        return [s.getsockname()[1] for s in sockets]
    finally:
        for s in sockets:
            s.close()


class SlurmCluster:
    def __init__(self, cpus=2):
        self.cpus = cpus
        self.root = pathlib.Path(tempfile.mkdtemp(prefix="terramesh-slurm-"))
        self.host = socket.gethostname().split(".")[0]
        self.conf = self.root / "slurm.conf"
        self.env = dict(os.environ, SLURM_CONF=str(self.conf))
        self.pid_files = []

    def program(self, name):
        return shutil.which(name) or shutil.which(name, path="/usr/sbin:/usr/bin")

    def start(self):
        self.pid_files = [self.root / "munged.pid", self.root / "slurmctld.pid", self.root / "slurmd.pid"]
        key = self.root / "munge.key"
        shutil.copyfile(MUNGE_KEY, key)
        os.chmod(key, 0o400)
        os.chmod(self.root, 0o700)
        subprocess.run([self.program("munged"), "-S", str(self.root / "munge.sock"), f"--key-file={key}",
                        f"--pid-file={self.pid_files[0]}", f"--log-file={self.root / 'munged.log'}",
                        f"--seed-file={self.root / 'munge.seed'}", "-f"], check=True, env=self.env)
        ctld_port, slurmd_port = free_ports(2)
        for folder in ("state", "spool"):
            (self.root / folder).mkdir()
        self.conf.write_text(f"""ClusterName=terrameshtest
SlurmctldHost={self.host}
SlurmUser=root
AuthType=auth/munge
AuthInfo=socket={self.root / 'munge.sock'}
CredType=cred/munge
SlurmctldPort={ctld_port}
SlurmdPort={slurmd_port}
StateSaveLocation={self.root / 'state'}
SlurmdSpoolDir={self.root / 'spool'}
SlurmctldPidFile={self.pid_files[1]}
SlurmdPidFile={self.pid_files[2]}
SlurmctldLogFile={self.root / 'slurmctld.log'}
SlurmdLogFile={self.root / 'slurmd.log'}
ProctrackType=proctrack/linuxproc
TaskPlugin=task/none
SelectType=select/cons_tres
SelectTypeParameters=CR_CPU
MpiDefault=none
ReturnToService=2
SlurmdParameters=config_overrides
NodeName={self.host} NodeAddr=127.0.0.1 CPUs={self.cpus} State=UNKNOWN
PartitionName=test Nodes={self.host} Default=YES MaxTime=INFINITE State=UP
""")
        subprocess.run([self.program("slurmctld"), "-f", str(self.conf)], check=True, env=self.env)
        subprocess.run([self.program("slurmd"), "-f", str(self.conf)], check=True, env=self.env)
        self.wait_until_idle()

    def wait_until_idle(self, timeout_s=60):
        deadline = time.monotonic() + timeout_s
        state = ""
        while time.monotonic() < deadline:
            result = subprocess.run([self.program("sinfo"), "-h", "-o", "%T"], env=self.env, capture_output=True, text=True)
            state = result.stdout.strip()
            if result.returncode == 0 and state == "idle":
                return
            time.sleep(0.5)
        raise RuntimeError(f"the Slurm node did not become idle within {timeout_s} s (state {state!r}); "
                           f"logs in {self.root}:\n{self.logs()}")

    def logs(self):
        text = []
        for name in ("munged.log", "slurmctld.log", "slurmd.log"):
            path = self.root / name
            if path.exists():
                text.append(f"--- {name}\n" + "\n".join(path.read_text(errors="replace").splitlines()[-20:]))
        return "\n".join(text)

    def stop(self):
        """Stops the daemons this cluster started, by the pids in their pid files, slurmd first."""
        for pid_file in reversed(self.pid_files):
            try:
                pid = int(pid_file.read_text().split()[0])
            except (OSError, ValueError, IndexError):
                continue
            try:
                os.kill(pid, signal.SIGTERM)
            except ProcessLookupError:
                continue
            for _ in range(100):
                try:
                    os.kill(pid, 0)
                except ProcessLookupError:
                    break
                time.sleep(0.1)
            else:
                try:
                    os.kill(pid, signal.SIGKILL)
                except ProcessLookupError:
                    pass
        shutil.rmtree(self.root, ignore_errors=True)


def main():
    parser = argparse.ArgumentParser(description="run a command against a one-node Slurm cluster on localhost")
    parser.add_argument("--cpus", type=int, default=os.cpu_count() or 1, help="CPUs of the node (default: all)")
    parser.add_argument("command", nargs=argparse.REMAINDER, help="-- COMMAND [ARGS...]")
    args = parser.parse_args()
    command = args.command[1:] if args.command[:1] == ["--"] else args.command
    if not command:
        parser.error("give a command after --")
    missing = missing_programs()
    if missing:
        print("local_cluster.py: missing " + ", ".join(missing) + " (scripts/install_deps.sh installs them)",
              file=sys.stderr)
        return 2
    cluster = SlurmCluster(cpus=args.cpus)
    try:
        cluster.start()
        return subprocess.run(command, env=cluster.env).returncode
    finally:
        cluster.stop()


if __name__ == "__main__":
    sys.exit(main())
