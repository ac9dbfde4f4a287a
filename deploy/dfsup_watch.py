"""dfsup's RouDi side: who holds RouDi, its health as df_health reports it, and healing.

Healing (FACTS.md §6): iceoryx 2.0.3's RouDi can deadlock when a process is SIGKILLed, and a
restarted RouDi leaves the running processes on an orphaned segment. What works: stop every
process of the host that uses shared memory, remove the stale iceoryx files, start RouDi, start
the services again in priority order. The watcher (`dfsup watch`, a supervised program) does that
when RouDi exits, is restarted behind its back, is reported stuck by df_health, or when df_health
stops reporting.
"""
import json
import os
import pwd
import signal
import time
import xmlrpc.client

ROUDI_LOCK = "/tmp/roudi.lock"
USER = pwd.getpwuid(os.getuid()).pw_name
# What RouDi leaves behind when it is killed (iceoryx 2.0.3, default names).
ICEORYX_FILES = ["/dev/shm/iceoryx_mgmt", f"/dev/shm/{USER}", "/tmp/roudi",
                 "/tmp/iox-unique-roudi.lock", ROUDI_LOCK]
RUNNING_STATES = ("RUNNING", "STARTING", "BACKOFF")
HEALTH_FILE = "health.json"
HEAL_LOG = "heal.log"
PROGRAMS_FILE = "programs.json"


def stamp():
    t = time.time()
    return time.strftime("%Y-%m-%dT%H:%M:%S", time.localtime(t)) + f".{int(t * 1000) % 1000:03d}"


def roudi_running():
    """True when some process holds RouDi's lock file (a RouDi runs on this machine)."""
    import fcntl
    try:
        with open(ROUDI_LOCK) as f:
            try:
                fcntl.flock(f, fcntl.LOCK_EX | fcntl.LOCK_NB)
                fcntl.flock(f, fcntl.LOCK_UN)
                return False
            except OSError:
                return True
    except OSError:
        return False


def lock_holder(path=ROUDI_LOCK):
    """Pid of the process holding a flock on path (from /proc/locks), or None."""
    try:
        st = os.stat(path)
        want = f"{os.major(st.st_dev):02x}:{os.minor(st.st_dev):02x}:{st.st_ino}"
        with open("/proc/locks") as f:
            for line in f:
                parts = line.split()
                if len(parts) >= 6 and parts[1] == "FLOCK" and parts[5] == want:
                    return int(parts[4])
    except (OSError, ValueError):
        pass
    return None


def alive(pid):
    """True for a live process (zombies count as gone)."""
    try:
        with open(f"/proc/{pid}/stat") as f:
            state = f.read().rsplit(")", 1)[1].split()[0]
        return state != "Z"
    except (OSError, IndexError):
        return False


def stopped_by_signal(pid):
    """True when the process is stopped (SIGSTOP): it ignores every signal but SIGKILL."""
    try:
        with open(f"/proc/{pid}/stat") as f:
            return f.read().rsplit(")", 1)[1].split()[0] == "T"
    except (OSError, IndexError):
        return False


def run_dir_of(pid):
    """The dfsup run dir whose supervisord is pid or one of its ancestors, or None."""
    for _ in range(8):
        try:
            with open(f"/proc/{pid}/cmdline", "rb") as f:
                argv = f.read().decode(errors="replace").split("\0")
            with open(f"/proc/{pid}/stat") as f:
                ppid = int(f.read().rsplit(")", 1)[1].split()[1])
        except (OSError, ValueError, IndexError):
            return None
        if any("supervisord" in a for a in argv[:2]) and "-c" in argv:
            conf = argv[argv.index("-c") + 1]
            if conf.endswith("supervisord.conf"):
                return os.path.dirname(os.path.abspath(conf))
        if ppid <= 1:
            return None
        pid = ppid
    return None


def roudi_owner():
    """(pid, run dir or None) of the RouDi holding the lock, or (None, None) if none runs."""
    if not roudi_running():
        return None, None
    pid = lock_holder()
    return pid, (run_dir_of(pid) if pid else None)


def clean_iceoryx_files():
    """Removes RouDi's stale files; only call when no RouDi runs. Returns what was removed."""
    if roudi_running():
        return []
    removed = []
    for path in ICEORYX_FILES:
        try:
            os.remove(path)
            removed.append(path)
        except FileNotFoundError:
            pass
        except OSError as e:
            removed.append(f"{path} (not removed: {e.strerror})")
    return removed


def read_health(run_dir):
    """(status dict or None, age of the file in seconds or None)."""
    path = os.path.join(run_dir, HEALTH_FILE)
    try:
        age = time.time() - os.path.getmtime(path)
        with open(path) as f:
            return json.load(f), age
    except (OSError, ValueError):
        return None, None


class Watcher:
    """Diagnoses RouDi from supervisord's view and df_health's file; heals in order."""

    def __init__(self, rpc, run_dir, log, stale_s=5.0, stop_grace_s=1.5, suspect_s=1.0,
                 suspect_window_s=10.0):
        self.rpc = rpc
        # After a service of the host died by a signal (when iceoryx 2.0's RouDi may deadlock),
        # one probe cycle started after the death that fails or runs suspect_s is enough to heal
        # (a sound probe takes well under a millisecond); otherwise df_health's probe_failures.
        self.suspect_s = suspect_s
        self.suspect_window_s = suspect_window_s
        self.pids = {}
        self.crash = None  # (time.time() of the death, name, probe cycles completed then)
        self.run_dir = run_dir
        self.log = log
        self.stale_s = stale_s
        self.stop_grace_s = stop_grace_s
        with open(os.path.join(run_dir, PROGRAMS_FILE)) as f:
            self.meta = json.load(f)
        self.roudi_pid = self.info("roudi")["pid"]
        self.heals = 0

    def info(self, name):
        return self.rpc.supervisor.getProcessInfo(name)

    def diagnose(self):
        """Why RouDi needs healing now, or None."""
        r = self.info("roudi")
        if r["statename"] not in ("RUNNING", "STARTING"):
            return f"RouDi {r['statename'].lower()} ({self.last_exit('roudi') or r['description']})"
        if r["pid"] != self.roudi_pid:
            return f"RouDi restarted outside the watcher (pid {self.roudi_pid} -> {r['pid']})"
        if not self.meta.get("health"):
            return None
        h = self.info("health")
        if h["statename"] != "RUNNING":
            return None
        status, age = read_health(self.run_dir)
        self.note_deaths(status)
        up_s = time.time() - h["start"]
        if status is None or status.get("pid") != h["pid"]:
            if up_s > self.stale_s * 2:
                return f"df_health (pid {h['pid']}) wrote no status for {up_s:.0f} s"
            return None
        if age > self.stale_s:
            return f"df_health (pid {h['pid']}) stopped reporting {age:.1f} s ago"
        roudi = status.get("roudi", {})
        if roudi.get("state") == "stuck":
            return (f"RouDi stuck: {roudi.get('consecutive_failures')} probe failures in a row "
                    f"({roudi.get('last_error')})")
        return self.suspect(status, age)

    def note_deaths(self, status):
        """Remembers when a service of the host (or df_health) last died by a signal."""
        names = [s["name"] for s in self.meta["services"]] + ["health"]
        for p in self.rpc.supervisor.getAllProcessInfo():
            n = p["name"]
            if n not in names:
                continue
            old = self.pids.get(n)
            self.pids[n] = p["pid"] or old
            died = old and (p["pid"] != old or p["statename"] not in RUNNING_STATES)
            if died and "terminated by SIG" in self.last_exit(n):
                cycles = (status or {}).get("roudi", {}).get("cycles", 0)
                self.crash = (time.time(), n, cycles)

    def suspect(self, status, age):
        """Why RouDi counts as stuck after a recent death by signal, or None."""
        if self.crash is None:
            return None
        t, name, cycles = self.crash
        since = time.time() - t
        if since > self.suspect_window_s:
            self.crash = None
            return None
        roudi = status.get("roudi", {})
        running = roudi.get("cycle_running_s", 0.0) + age
        # A new df_health's first cycles open its ports: only a probe that worked before counts.
        if roudi.get("ok_cycles", 0) == 0:
            return None
        if running >= self.suspect_s and running < since:
            return (f"RouDi stuck: a probe cycle started {since - running:.1f} s after {name} "
                    f"died by a signal has been blocked for {running:.1f} s")
        if roudi.get("cycles", 0) > cycles and roudi.get("consecutive_failures", 0) > 0:
            return (f"RouDi stuck: a probe cycle after {name} died by a signal failed "
                    f"({roudi.get('last_error')})")
        return None

    def last_exit(self, name):
        """supervisord's last 'exited: NAME (...)' reason, e.g. 'terminated by SIGKILL'."""
        try:
            with open(os.path.join(self.run_dir, "supervisord.log"), errors="replace") as f:
                lines = [ln for ln in f.readlines()[-400:] if f"exited: {name} (" in ln]
            return lines[-1].split(f"exited: {name} (", 1)[1].rsplit(")", 1)[0] if lines else ""
        except OSError:
            return ""

    def stop(self, names, grace_s):
        """Stops programs: their stop signal, then SIGKILL of the group after grace_s."""
        pids = {}
        for n in names:
            i = self.info(n)
            if i["statename"] not in RUNNING_STATES:
                continue
            pids[n] = i["pid"]
            # stopProcess first: supervisord then counts the exit as a stop. A SIGKILL before
            # it is an unexpected exit that autorestart answers with a new process, which the
            # heal's startProcess then finds ALREADY_STARTED (measured on a loaded CI machine).
            try:
                self.rpc.supervisor.stopProcess(n, False)
            except Exception:  # already stopping or stopped
                pass
            if i["pid"] and stopped_by_signal(i["pid"]):  # SIGSTOPped: the stop signal waits
                try:
                    os.killpg(i["pid"], signal.SIGKILL)
                except ProcessLookupError:
                    pass
        deadline = time.monotonic() + grace_s
        while time.monotonic() < deadline and any(self.info(n)["statename"] in
                                                  RUNNING_STATES + ("STOPPING",) for n in pids):
            time.sleep(0.05)
        killed = []
        for n, pid in pids.items():
            if self.info(n)["statename"] in RUNNING_STATES + ("STOPPING",) and pid:
                try:
                    os.killpg(pid, signal.SIGKILL)
                    killed.append(f"{n} (pid {pid})")
                except ProcessLookupError:
                    pass
        deadline = time.monotonic() + 5
        while time.monotonic() < deadline and any(self.info(n)["statename"] in
                                                  RUNNING_STATES + ("STOPPING",) for n in pids):
            time.sleep(0.05)
        return list(pids), killed

    def start(self, name):
        """startProcess that takes a program supervisord has already started again as done."""
        try:
            self.rpc.supervisor.startProcess(name, False)
        except xmlrpc.client.Fault as e:
            if "ALREADY_STARTED" not in e.faultString:
                raise
            self.log(f"heal {self.heals}: {name} was already started again (pid "
                     f"{self.info(name)['pid']})")

    def heal(self, reason):
        t0 = time.monotonic()
        self.crash = None
        self.pids = {}
        self.heals += 1
        self.log(f"heal {self.heals} because {reason}")
        services = [s["name"] for s in sorted(self.meta["services"], key=lambda s: s["priority"])]
        if self.meta.get("health"):
            services.append("health")
        restart = [n for n in services if self.info(n)["statename"] in RUNNING_STATES]
        # Processes of a stuck RouDi hang in iceoryx when they stop (measured: none of them
        # exits within 1.5 s, nor does RouDi): short grace then.
        stuck = reason.startswith("RouDi stuck") or "df_health" in reason
        grace_s = 0.3 if stuck else self.stop_grace_s
        stopped, killed = self.stop(list(reversed(restart)), grace_s)
        self.log(f"heal {self.heals}: stopped {', '.join(stopped) or 'no service'}"
                 + (f"; SIGKILL to {', '.join(killed)}" if killed else ""))
        _, roudi_killed = self.stop(["roudi"], grace_s)
        deadline = time.monotonic() + 5
        while roudi_running() and time.monotonic() < deadline:
            time.sleep(0.05)
        holder = lock_holder()
        if roudi_running():
            self.log(f"heal {self.heals}: FAILED: {ROUDI_LOCK} still held by pid {holder}")
            return False
        removed = clean_iceoryx_files()
        self.log(f"heal {self.heals}: RouDi stopped"
                 + (" (SIGKILL)" if roudi_killed else "")
                 + f"; removed {', '.join(removed) or 'nothing'}")
        self.start("roudi")
        deadline = time.monotonic() + 10
        while not roudi_running():
            if time.monotonic() > deadline:
                self.log(f"heal {self.heals}: FAILED: RouDi did not start within 10 s "
                         f"(see {self.run_dir}/logs/roudi.log)")
                return False
            time.sleep(0.02)
        self.roudi_pid = self.info("roudi")["pid"]
        for n in restart:
            self.start(n)
        self.log(f"heal {self.heals}: RouDi pid {self.roudi_pid}; started "
                 f"{', '.join(restart) or 'no service'}; {time.monotonic() - t0:.2f} s")
        return True
