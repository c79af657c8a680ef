#!/usr/bin/python3
"""Runs every catkin test target of a configured and built workspace, JOBS at a time, and prints how long each took.

    scripts/run_test_targets.py BUILD_DIR [--jobs N] [--log FILE] [--heavy-file FILE] [--only PATTERN]

The targets are the leaves of catkin's run_tests tree (`run_tests_<pkg>_gtest_<name>`, `..._rostest_...`,
`..._pyunit_...`, `..._roslaunch-check_...`): those no other run_tests target extends. Each runs as its own
`make <target>`, so one failing or hanging test does not stop the others; its output goes to the log. Most rostests
wait on simulated or wall-clock time and use little CPU, so JOBS may exceed the cores. Tests named in the heavy file
(one fnmatch pattern a line, # comments) are scenario-length simulations that need a core of their own: at most one
of them runs at a time, beside light ones. The longest tests of the last run on this machine (kept in
BUILD_DIR/test_durations.tsv) start first, so the workers end together. Results are the JUnit files catkin writes;
this script reports what ran, how long (wall clock and CPU), the ten slowest and the total, and exits 0 (the results
are counted from the JUnit files).
"""
import argparse
import fnmatch
import os
import re
import subprocess
import sys
import tempfile
import threading
import time


def leaf_targets(build_dir):
    out = subprocess.run(["make", "-C", build_dir, "help"], capture_output=True, text=True, check=True).stdout
    names = sorted({m.group(1) for m in re.finditer(r"^\.\.\. (run_tests_\S+)", out, re.M)})
    return [n for n in names if not any(o.startswith(n + "_") for o in names)]


def read_patterns(path):
    if not path or not os.path.exists(path):
        return []
    with open(path) as f:
        return [line.split("#", 1)[0].strip() for line in f if line.split("#", 1)[0].strip()]


def read_durations(path):
    durations = {}
    if os.path.exists(path):
        with open(path) as f:
            for line in f:
                parts = line.split("\t")
                if len(parts) == 2:
                    try:
                        durations[parts[0]] = float(parts[1])
                    except ValueError:
                        pass
    return durations


def short(target):
    return target[len("run_tests_"):]


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("build_dir")
    parser.add_argument("--jobs", type=int, default=2)
    parser.add_argument("--log", default=None, help="all the tests' output (default BUILD_DIR/run_tests.log)")
    parser.add_argument("--heavy-file", default=None, help="patterns of tests of which at most one runs at a time")
    parser.add_argument("--only", default="*", help="run only the targets matching this pattern (without run_tests_)")
    args = parser.parse_args()
    if args.jobs < 1:
        parser.error("--jobs must be at least 1")
    build_dir = os.path.abspath(args.build_dir)
    log_path = args.log or os.path.join(build_dir, "run_tests.log")
    durations_path = os.path.join(build_dir, "test_durations.tsv")

    targets = [t for t in leaf_targets(build_dir) if fnmatch.fnmatch(short(t), args.only)]
    heavy_patterns = read_patterns(args.heavy_file)
    last = read_durations(durations_path)
    heavy = {t for t in targets if any(fnmatch.fnmatch(short(t), p) for p in heavy_patterns)}
    # The longest of the last run first; without a last run (a fresh clone): heavy tests, then rostests, then the rest.
    unknown = lambda t: 1e9 + (2 if t in heavy else 1 if "_rostest_" in t else 0)  # noqa: E731
    queue = sorted(targets, key=lambda t: -last.get(t, unknown(t)))
    print(f"[tests] {len(targets)} test targets on {args.jobs} workers, {len(heavy)} of them heavy (one at a time)",
          flush=True)

    lock = threading.Lock()
    took = {}
    cpu = {}
    log = open(log_path, "w")
    start_all = time.monotonic()

    def run(target):
        start = time.monotonic()
        with tempfile.TemporaryFile(mode="w+", errors="replace") as out:
            proc = subprocess.Popen(["make", "-C", build_dir, target], stdout=out, stderr=subprocess.STDOUT)
            # wait4: the CPU time of make and of every process it waited for (the test and what the test started).
            _, status, usage = os.wait4(proc.pid, 0)
            proc.returncode = os.waitstatus_to_exitcode(status)
            out.seek(0)
            text = out.read()
        seconds = time.monotonic() - start
        cpu_s = usage.ru_utime + usage.ru_stime
        with lock:
            took[target] = seconds
            cpu[target] = cpu_s
            log.write(f"===== {target} ({seconds:.1f} s, {cpu_s:.1f} s CPU, make exit {proc.returncode})\n{text}\n")
            log.flush()
            failed = proc.returncode != 0 or re.search(r"RESULT: FAIL|\[  FAILED  \]", text)
            done = len(took)
            print(f"[tests] {done:3d}/{len(targets)} {seconds:6.1f} s {cpu_s:6.1f} s CPU  {'FAILED ' if failed else ''}"
                  f"{short(target)}", flush=True)

    heavy_running = [False]
    wake = threading.Condition(lock)

    def worker():
        while True:
            with lock:
                while True:
                    if not queue:
                        return
                    target = next((t for t in queue if t not in heavy or not heavy_running[0]), None)
                    if target is not None:
                        break
                    wake.wait()  # only heavy tests are left and one runs
                queue.remove(target)
                if target in heavy:
                    heavy_running[0] = True
            run(target)
            with lock:
                if target in heavy:
                    heavy_running[0] = False
                wake.notify_all()

    threads = [threading.Thread(target=worker) for _ in range(args.jobs)]
    for t in threads:
        t.start()
    for t in threads:
        t.join()
    log.close()

    total = time.monotonic() - start_all
    with open(durations_path, "w") as f:
        for target, seconds in sorted(took.items()):
            f.write(f"{target}\t{seconds:.1f}\n")
    print("[tests] the ten slowest:")
    for target, seconds in sorted(took.items(), key=lambda kv: -kv[1])[:10]:
        print(f"[tests]   {seconds:6.1f} s  {cpu[target]:6.1f} s CPU  {short(target)}")
    print(f"[tests] all {len(took)} test targets in {total:.0f} s wall clock ({sum(took.values()):.0f} s of test time, "
          f"{sum(cpu.values()):.0f} s CPU)", flush=True)
    return 0


if __name__ == "__main__":
    sys.exit(main())
