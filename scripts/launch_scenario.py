#!/usr/bin/env python3
"""railvib launcher: roslaunch that tells, by its exit code, whether the run worked.

usage: launch_scenario.py [-p PORT] [--finisher NODE] PACKAGE FILE.launch [ARG:=VALUE]...
       launch_scenario.py [-p PORT] [--finisher NODE] PATH/FILE.launch [ARG:=VALUE]...

`roslaunch` exits 0 whatever happens: a required node that crashed, was killed
or refused its configuration, a master that died. This runs the same launch
through roslaunch's own API (same output, same master handling, same
"REQUIRED process has died" shutdown) and watches every process:

  exit 0  the finisher (the node named `recorder` by default, which ends a
          scenario once every stream is complete) was the first required
          process to end, with exit code 0, and no process died with a
          non-zero code before it;
  exit 1  anything else: a node (or the master) died first or with a
          non-zero exit code; the line `railvib: launch failed: ...` says which;
  exit 2  the launch file could not be loaded;
  exit 130 interrupted (Ctrl-C) before the finisher ended.

A launch without a node named like the finisher (e.g. replay.launch) runs until
interrupted; it fails if any process dies with a non-zero exit code.

Nothing outlives the launcher: SIGTERM (or SIGHUP) ends the launch as Ctrl-C
does; a guardian process of its own session holds the process groups of the
master and the nodes, and ends them (SIGINT, SIGTERM, SIGKILL, each after a
grace period) if the launcher is killed with SIGKILL; and the launcher gets
SIGTERM when the process that started it (./railvib run) dies.
"""
import argparse
import ctypes
import os
import signal
import subprocess
import sys

try:
    import roslaunch
    import roslaunch.parent
    import roslaunch.pmon
    import roslaunch.rlutil
except ImportError:  # pragma: no cover
    sys.exit("railvib launcher: python3-roslaunch is required (./railvib setup installs it)")


class Watch(roslaunch.pmon.ProcessListener):
    """Every process death roslaunch reports while the launch runs (not those it kills to shut down)."""

    def __init__(self):
        self.deaths = []  # (process name, exit code) in order

    def process_died(self, process_name, exit_code):
        self.deaths.append((process_name, exit_code))


def node_of(process_name):
    """roslaunch names a node's process NAME-N (e.g. recorder-8)."""
    head, _, tail = process_name.rpartition("-")
    return head if tail.isdigit() else process_name


def verdict(deaths, required, finisher):
    """(ok, message) for the deaths reported, given the names of the required processes."""
    for name, code in deaths:
        if code != 0:
            what = "an unknown exit code" if code is None else (
                f"signal {-code}" if code < 0 else f"exit code {code}")
            return False, f"process [{name}] died with {what}"
        if node_of(name) in required and node_of(name) != finisher:
            before = f" before the {finisher}" if finisher else ""
            return False, (f"required process [{name}] ended{before} (killed, or stopped on its own): "
                           f"the run did not finish")
        if node_of(name) == finisher:
            return True, f"the {finisher} finished cleanly"
    if finisher in required:
        return False, f"the {finisher} never finished"
    return True, "no process failed"


GUARDIAN = r"""
import os, signal, sys, time
groups = []
for line in sys.stdin:
    word = line.strip()
    if word == "done":
        sys.exit(0)
    if word.isdigit():
        groups.append(int(word))

def alive(group):
    try:
        os.killpg(group, 0)
        return True
    except OSError:
        return False

left = [g for g in groups if alive(g)]
if left:
    print(f"railvib: the launcher is gone; ending the {len(left)} process group(s) it started", file=sys.stderr)
for sig, grace_s in ((signal.SIGINT, %(grace_s)r), (signal.SIGTERM, %(term_grace_s)r), (signal.SIGKILL, 0.0)):
    left = [g for g in left if alive(g)]
    for g in left:
        try:
            os.killpg(g, sig)
        except OSError:
            pass
    end = time.monotonic() + grace_s
    while time.monotonic() < end and any(alive(g) for g in left):
        time.sleep(0.1)
"""


class Guardian:
    """A process in a session of its own that reads the launch's process groups on a pipe; the pipe's end
    (the launcher killed) without "done" makes it end them."""

    def __init__(self, grace_s=15.0, term_grace_s=5.0):
        self.known = set()
        self.proc = subprocess.Popen([sys.executable, "-c", GUARDIAN % {"grace_s": grace_s,
                                                                        "term_grace_s": term_grace_s}],
                                     stdin=subprocess.PIPE, text=True, start_new_session=True)

    def watch(self, parent):
        """Every process roslaunch has started so far (each in a session, so a group, of its own)."""
        for p in list(parent.pm.procs):
            pid = getattr(getattr(p, "popen", None), "pid", None)
            if pid and pid not in self.known:
                self.known.add(pid)
                self.proc.stdin.write(f"{pid}\n")
        self.proc.stdin.flush()

    def done(self):
        try:
            self.proc.stdin.write("done\n")
            self.proc.stdin.close()
        except (BrokenPipeError, ValueError):
            pass
        self.proc.wait()


INTERRUPTED = []  # the signals that ended the launch


def on_signal(sig, frame):
    INTERRUPTED.append(signal.Signals(sig).name)
    raise KeyboardInterrupt


def note_roslaunch_signals():
    """roslaunch takes SIGINT, SIGTERM and SIGHUP over once it starts processes (its handler shuts the
    nodes down, and its process monitor re-installs it if replaced); its handler is wrapped so that the
    verdict knows the launch was interrupted."""
    original = roslaunch.pmon.rl_signal

    def rl_signal(sig, frame):
        INTERRUPTED.append(signal.Signals(sig).name)
        original(sig, frame)

    roslaunch.pmon.rl_signal = rl_signal


def quiet_clean_finish(finisher):
    """roslaunch reports any required process's end as "REQUIRED process [...] has died!", also the
    finisher's clean one, which is how a successful run ends: that one is said as what it is; every
    other death keeps roslaunch's message."""
    original = roslaunch.pmon.printerrlog

    def printerrlog(msg):
        if (f"REQUIRED process [{finisher}-" in msg and "process has finished cleanly" in msg):
            print(f"railvib: the {finisher} finished cleanly; ending the run", flush=True)
            return
        original(msg)

    roslaunch.pmon.printerrlog = printerrlog


def end_with_the_parent():
    """SIGTERM to this process when the one that started it dies (Linux prctl PR_SET_PDEATHSIG)."""
    parent = os.getppid()
    try:
        libc = ctypes.CDLL(None, use_errno=True)
        PR_SET_PDEATHSIG = 1
        libc.prctl(PR_SET_PDEATHSIG, signal.SIGTERM, 0, 0, 0)
    except (OSError, AttributeError):
        return
    if os.getppid() != parent:  # it died before the request
        os.kill(os.getpid(), signal.SIGTERM)


def conflicting_arguments(launch_args):
    """Why the launch arguments cannot make one run (None if they can): values that the launch file turns
    into processes (soil_ranks) and pairs that contradict each other."""
    given = dict(a.split(":=", 1) for a in launch_args)
    ranks = given.get("soil_ranks")
    if ranks is not None and (not ranks.strip().isdigit() or not 1 <= int(ranks) <= 1024):
        return f"soil_ranks:={ranks}: a whole number of MPI ranks from 1 to 1024"
    building = given.get("building", "true").strip().lower()
    if building not in ("true", "false", "1", "0"):
        return f"building:={given['building']}: true or false"
    if given.get("coupling", "").strip() == "two_way" and building in ("false", "0"):
        return ("coupling:=two_way with building:=false: two-way coupling is the house acting on the soil; "
                "run with the house (building:=true) or one_way")
    part = given.get("part")
    if part is not None and part not in ("all", "upstream", "downstream"):
        return f"part:={part}: all, upstream or downstream"
    return None


def main(argv):
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("-p", "--port", type=int, default=None, help="master port (a new master if none runs)")
    parser.add_argument("--finisher", default="recorder", help="the node whose clean end is the run's end")
    parser.add_argument("launch", nargs="+", help="PACKAGE FILE.launch or PATH.launch, then ARG:=VALUE...")
    options = parser.parse_args(argv[1:])
    args = options.launch
    try:
        files = roslaunch.rlutil.resolve_launch_arguments(args)
    except Exception as e:  # roslaunch raises RLException and friends
        print(f"railvib: launch failed: {e}", file=sys.stderr)
        return 2
    launch_args = [a for a in args if ":=" in a]
    quiet_clean_finish(options.finisher)
    conflict = conflicting_arguments(launch_args)
    if conflict:
        print(f"railvib: launch failed: {conflict}", file=sys.stderr)
        return 2
    uuid = roslaunch.rlutil.get_or_generate_uuid(None, False)
    roslaunch.configure_logging(uuid)
    watch = Watch()
    parent = roslaunch.parent.ROSLaunchParent(uuid, [(files[0], launch_args)], port=options.port,
                                              process_listeners=[watch])
    guardian = Guardian()
    try:
        return run(parent, watch, options, guardian)
    finally:
        guardian.done()


def run(parent, watch, options, guardian):
    try:
        parent.start()
        guardian.watch(parent)
        required = {n.name for n in parent.config.nodes if n.required}
        required.add("master")  # the master roslaunch started, if it did, is required too
        finisher_known = options.finisher in {n.name for n in parent.config.nodes}
        parent.spin()
    except KeyboardInterrupt:
        parent.shutdown()
    except Exception as e:  # a bad launch file or argument
        try:
            parent.shutdown()
        except Exception:
            pass
        if not INTERRUPTED:
            print(f"railvib: launch failed: {e}", file=sys.stderr)
            return 2
    if INTERRUPTED:  # also when roslaunch's handler took the signal and its spin returned
        print(f"railvib: launch interrupted ({INTERRUPTED[0]})", file=sys.stderr)
        return 130
    ok, why = verdict(watch.deaths, required if finisher_known else required - {options.finisher},
                      options.finisher if finisher_known else "")
    print(("railvib: launch finished: " if ok else "railvib: launch failed: ") + why, file=sys.stderr)
    return 0 if ok else 1


if __name__ == "__main__":
    # SIGINT, SIGTERM and SIGHUP end the launch alike (also when started with SIGINT ignored): once
    # roslaunch runs, its handlers shut the nodes down and then call this one.
    for sig in (signal.SIGINT, signal.SIGTERM, signal.SIGHUP):
        signal.signal(sig, on_signal)
    note_roslaunch_signals()
    end_with_the_parent()
    sys.exit(main(sys.argv))
