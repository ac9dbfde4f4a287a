#!/usr/bin/env python3
"""The hostile-input suite: runs every case of cases.txt against the real binaries.

    run_suite.py --bin BUILD/bin [--src REPO] [--jobs 2] [--timeout 30] [--only REGEX] [--keep]

Each case is one line of cases.txt (see its header). A case FAILS as
  CRASH   the process died by a signal (SIGSEGV, SIGABRT...),
  HANG    it ran past the timeout (its process group is killed),
  SILENT  it exited 0 where an error was due,
  UNCLEAR it refused, but without the expected words naming what and where,
  WRONG   good or recoverable input refused, or the output check failed.
Prints PASS/FAIL per case, a summary per category and per failure kind, and
`N passed, M failed`; exits 1 if any case failed.
"""
import argparse
import concurrent.futures
import math
import os
import re
import shlex
import shutil
import signal
import subprocess
import sys
import tempfile
import time

HERE = os.path.dirname(os.path.abspath(__file__))
HELP_LINE = re.compile(r'^  (\S+)\s+(\(unset\)|\[\]|"[^"]*"|\S+)\s+(\S.*)$')


class Case:
    def __init__(self, cid, category, expect, want, command, check, where):
        self.id, self.category, self.expect = cid, category, expect
        self.want, self.command, self.check, self.where = want, command, check, where
        self.known = False  # a product bug recorded, not fixed yet: reported, not counted


def nested(path, value):
    """'slam.map.x', '0' -> 'slam { map { x: 0 } }' (protobuf text format)."""
    parts = path.split(".")
    text = f"{parts[-1]}: {value}"
    for p in reversed(parts[:-1]):
        text = f"{p} {{ {text} }}"
    return text


def num(text):
    v = float(text)
    return str(int(v)) if v.is_integer() and abs(v) < 1e15 else repr(v)


def option_values(allowed):
    """Bad values for one option from its 'allowed' text: [(label, value, regex-after-path)]."""
    out = []
    if allowed.startswith("one of "):
        return [("choice", '"no_such_choice"', r' is "no_such_choice", allowed: one of')]
    if allowed.startswith("not empty"):
        return [("empty", '""', r" is empty")]
    lo = re.search(r"(>=|>) (-?[0-9.e+]+)", allowed)
    hi = re.search(r"(<=|<) (-?[0-9.e+]+)", allowed)
    if lo:
        v = float(lo.group(2))
        bad = v - 1 if lo.group(1) == ">=" else v
        out.append(("below", num(bad), r" is \S+, allowed"))
    if hi:
        v = float(hi.group(2))
        bad = math.floor(v) + 1 if hi.group(1) == "<=" else v
        out.append(("above", num(bad), r" is \S+, allowed"))
    if lo or hi:
        # An integer field refuses nan as text-format syntax, a float one by its range.
        out.append(("nan", "nan", r" is nan, allowed|: nan[ }]*'?:\d+:\d+: Expected integer"))
    return out


def expand_options(cid, category, help_cmd, template, env, where):
    """One case per bad value of every option the binary's help lists with a rule."""
    r = subprocess.run(help_cmd, shell=True, capture_output=True, text=True, env=env, timeout=60)
    text = r.stdout + r.stderr
    if "Options (--set" not in text:
        return [Case(cid + ".help", category, "fail-help", "", help_cmd, "",
                     f"{where}: '{help_cmd}' lists no options (expected 'Options (--set')")]
    text = text.split("Options (--set", 1)[1]
    cases = []
    for line in text.splitlines()[1:]:
        m = HELP_LINE.match(line)
        if not m:
            continue
        path, default, allowed = m.groups()
        for label, value, after in option_values(allowed.strip()):
            rx = "(" + re.escape(path) + r"(\[[^]]*\])?(" + after + "))"
            if label == "nan":
                rx = "(" + re.escape(path) + r"(\[[^]]*\])?" + r" is nan, allowed|" \
                     + re.escape(path.split(".")[-1]) + r": nan[ }]*'?:\d+:\d+: Expected integer)"
            # an unsigned field refuses a negative value as text-format syntax, naming it
            rx = rx[:-1] + "|" + re.escape(path.split(".")[-1] + ": " + value) \
                + r"[ }]*'?:\d+:\d+: Expected)"
            cmd = template.replace("{opt}", shlex.quote(nested(path, value)))
            cases.append(Case(f"{cid}.{path}.{label}", category, "error", rx, cmd, "",
                              f"{where} ({path} {allowed.strip()})"))
    return cases


def read_table(path, subst, env):
    cases = []
    with open(path) as f:
        for n, raw in enumerate(f, 1):
            line = raw.rstrip("\n")
            if not line.strip() or line.lstrip().startswith("#"):
                continue
            where = f"cases.txt:{n}"
            fields = [x.strip() for x in line.split(" | ")]
            if fields[0].startswith("@options"):
                _, cid, category = fields[0].split()
                cases += expand_options(cid, category, subst(fields[1]), subst(fields[2]), env,
                                        where)
                continue
            if len(fields) < 5:
                sys.exit(f"{where}: expected 'id | category | expect | regex | command"
                         f" [| check]', got {len(fields)} fields")
            cid, category, expect, want, command = fields[:5]
            check = fields[5] if len(fields) > 5 else ""
            known = expect.endswith(" known")
            expect = expect.split()[0]
            if expect not in ("error", "ok", "skipped"):
                sys.exit(f"{where}: expect is '{expect}', allowed error|ok|skipped [known]")
            case = Case(cid, category, expect, want, subst(command), subst(check), where)
            case.known = known
            cases.append(case)
    ids = [c.id for c in cases]
    dup = {i for i in ids if ids.count(i) > 1}
    if dup:
        sys.exit(f"{path}: duplicate case ids {sorted(dup)}")
    return cases


def count_poses(path):
    try:
        with open(path, errors="replace") as f:
            return sum(1 for l in f if l.strip() and not l.startswith("#"))
    except OSError:
        return -1


def run_check(check):
    """'poses FILE OP N' or 'exists FILE' or 'absent FILE' -> error text or ''."""
    if not check:
        return ""
    w = shlex.split(check)
    if w[0] == "poses":
        n, want = count_poses(w[1]), int(w[3])
        ok = {">=": n >= want, "==": n == want, "<=": n <= want}[w[2]]
        return "" if ok else f"{w[1]} has {n} poses, expected {w[2]} {want}"
    if w[0] == "exists":
        return "" if os.path.exists(w[1]) else f"{w[1]} was not written"
    if w[0] == "absent":
        return "" if not os.path.exists(w[1]) else f"{w[1]} was written"
    return f"unknown check '{check}'"


def run_case(case, work, timeout, env):
    out = os.path.join(work, "cases", re.sub(r"[^A-Za-z0-9_.-]", "_", case.id))
    os.makedirs(out, exist_ok=True)
    os.chmod(out, 0o777)
    cmd = case.command.replace("{out}", out)
    check = case.check.replace("{out}", out)
    if case.expect == "fail-help":
        return case, "FAIL", "UNCLEAR", case.where, 0.0
    t0 = time.monotonic()
    p = subprocess.Popen(["bash", "-c", cmd], stdout=subprocess.PIPE, stderr=subprocess.STDOUT,
                         stdin=subprocess.DEVNULL, start_new_session=True, env=env, cwd=out)
    try:
        data, _ = p.communicate(timeout=timeout)
        rc = p.returncode
    except subprocess.TimeoutExpired:
        os.killpg(p.pid, signal.SIGKILL)
        data, _ = p.communicate()
        rc = None
    dt = time.monotonic() - t0
    if os.path.exists(os.path.join(out, "run", "supervisor.sock")):  # a dfsup case that went up
        subprocess.run([os.path.join(os.path.dirname(HERE), "..", "deploy", "dfsup"), "--run-dir",
                        os.path.join(out, "run"), "down"], capture_output=True, timeout=120)
    text = data.decode(errors="replace")
    with open(os.path.join(out, "output.log"), "w") as f:
        f.write(f"$ {cmd}\n{text}\nrc={rc}\n")
    tail = " / ".join(text.strip().splitlines()[-3:])[-600:]
    fatal = {signal.SIGSEGV, signal.SIGABRT, signal.SIGBUS, signal.SIGFPE, signal.SIGILL}
    if rc is None:
        return case, "FAIL", "HANG", f"still running after {timeout} s: {tail}", dt
    sig = -rc if rc < 0 else (rc - 128 if rc > 128 and (rc - 128) in fatal else 0)
    if rc == 127:
        return case, "FAIL", "WRONG", f"command not found (not built?): {tail}", dt
    if sig:
        return case, "FAIL", "CRASH", f"died by {signal.Signals(sig).name}: {tail}", dt
    missing = [w for w in case.want.split(" && ") if w and not re.search(w, text)]
    if case.expect == "error":
        if rc == 0:
            return case, "FAIL", "SILENT", f"exit 0, expected an error matching {case.want!r}: " \
                                           f"{tail}", dt
        if missing:
            return case, "FAIL", "UNCLEAR", f"exit {rc} without {missing[0]!r}: {tail}", dt
        return case, "PASS", "", "", dt
    if rc != 0:
        return case, "FAIL", "WRONG", f"exit {rc}, expected 0: {tail}", dt
    if missing:
        return case, "FAIL", "WRONG", f"output lacks {missing[0]!r}: {tail}", dt
    bad = run_check(check)
    if bad:
        return case, "FAIL", "WRONG", bad, dt
    return case, "PASS", "", "", dt


def main():
    ap = argparse.ArgumentParser(description=__doc__,
                                 formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--bin", required=True, help="folder of the built binaries (build/bin)")
    ap.add_argument("--src", default=os.path.dirname(os.path.dirname(HERE)))
    ap.add_argument("--cases", default=os.path.join(HERE, "cases.txt"))
    ap.add_argument("--jobs", type=int, default=2)
    ap.add_argument("--timeout", type=float, default=30.0, help="seconds per case (HANG after)")
    ap.add_argument("--only", help="run only the cases whose id matches this regex")
    ap.add_argument("--keep", action="store_true", help="keep the work folder")
    args = ap.parse_args()
    bin_dir = os.path.abspath(args.bin)
    work = tempfile.mkdtemp(prefix="df-hostile-")
    os.chmod(work, 0o755)
    data = os.path.join(work, "data")
    subprocess.run([sys.executable, os.path.join(HERE, "make_data.py"), bin_dir, data],
                   check=True)
    ns = f"hostile{os.getpid()}"
    as_root = os.geteuid() == 0
    env = dict(os.environ)
    env.pop("CYCLONEDDS_URI", None)  # services choose UDP on loopback without a RouDi
    env["DF_BUILD"] = os.path.dirname(bin_dir)
    subst_map = {
        "{bin}": bin_dir, "{data}": data, "{src}": args.src, "{ns}": ns, "{py}": sys.executable,
        "{udp}": "--set " + shlex.quote(f'dds {{ transport: "udp" ns: "{ns}" }}'),
        # root reads any file: unreadable-file cases run as nobody
        "{nobody}": "runuser -u nobody --" if as_root else "",
    }

    def subst(text):
        for k, v in subst_map.items():
            text = text.replace(k, v)
        return text
    cases = read_table(args.cases, subst, env)
    if args.only:
        cases = [c for c in cases if re.search(args.only, c.id)]
    if as_root and not shutil.which("runuser"):
        print("note: running as root without runuser: unreadable-file cases are skipped")
        cases = [c for c in cases if "runuser" not in c.command]
    print(f"{len(cases)} cases, {args.jobs} at a time, {args.timeout:g} s each at most;"
          f" work folder {work}", flush=True)
    results = []
    t0 = time.monotonic()
    with concurrent.futures.ThreadPoolExecutor(args.jobs) as pool:
        futures = [pool.submit(run_case, c, work, args.timeout, env) for c in cases]
        for fut in concurrent.futures.as_completed(futures):
            case, verdict, kind, why, dt = fut.result()
            if case.known:
                if verdict == "PASS":
                    print(f"PASS {case.id} (a known bug no longer shows: drop 'known' in "
                          f"{case.where})", flush=True)
                else:
                    print(f"KNOWN {case.id} [{kind}] {why} ({case.where})", flush=True)
                    verdict, kind = "KNOWN", kind
            results.append((case, verdict, kind))
            if case.known:
                pass
            elif verdict == "PASS":
                print(f"PASS {case.id} ({dt:.1f} s)", flush=True)
            else:
                print(f"FAIL {case.id} [{kind}] {why} ({case.where})", flush=True)
    cats = {}
    for case, verdict, kind in results:
        c = cats.setdefault(case.category, {"cases": 0, "passed": 0, "CRASH": 0, "HANG": 0,
                                            "SILENT": 0, "UNCLEAR": 0, "WRONG": 0})
        c["cases"] += 1
        if verdict == "KNOWN":
            c["known"] = c.get("known", 0) + 1
        c["passed" if verdict == "PASS" else kind] += 1
    print(f"\n{'category':<18}{'cases':>6}{'passed':>7}{'crashes':>8}{'hangs':>6}{'silent':>7}"
          f"{'unclear':>8}{'wrong':>6}{'known':>6}")
    for name in sorted(cats):
        c = cats[name]
        print(f"{name:<18}{c['cases']:>6}{c['passed']:>7}{c['CRASH']:>8}{c['HANG']:>6}"
              f"{c['SILENT']:>7}{c['UNCLEAR']:>8}{c['WRONG']:>6}{c.get('known', 0):>6}")
    total = {k: sum(c[k] for c in cats.values()) for k in ("CRASH", "HANG", "SILENT",
                                                            "UNCLEAR", "WRONG")}
    passed = sum(1 for _, v, _ in results if v == "PASS")
    known = sum(1 for _, v, _ in results if v == "KNOWN")
    failed = len(results) - passed - known
    print("(crashes..wrong count every failing case, known ones included; known: product bugs"
          " recorded in cases.txt, not fixed yet)")
    print(f"crashes {total['CRASH']}, hangs {total['HANG']}, silent {total['SILENT']}, "
          f"unclear {total['UNCLEAR']}, wrong {total['WRONG']} "
          f"({time.monotonic() - t0:.0f} s)")
    print(f"{passed} passed, {failed} failed" + (f", {known} known failures" if known else ""))
    if args.keep or failed:
        print(f"outputs kept in {work}/cases/<id>/output.log")
    else:
        shutil.rmtree(work, ignore_errors=True)
    sys.exit(1 if failed else 0)


if __name__ == "__main__":
    main()
