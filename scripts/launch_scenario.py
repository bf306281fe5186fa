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
"""
import argparse
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
    uuid = roslaunch.rlutil.get_or_generate_uuid(None, False)
    roslaunch.configure_logging(uuid)
    watch = Watch()
    parent = roslaunch.parent.ROSLaunchParent(uuid, [(files[0], launch_args)], port=options.port,
                                              process_listeners=[watch])
    try:
        parent.start()
        required = {n.name for n in parent.config.nodes if n.required}
        required.add("master")  # the master roslaunch started, if it did, is required too
        finisher_known = options.finisher in {n.name for n in parent.config.nodes}
        parent.spin()
    except KeyboardInterrupt:
        parent.shutdown()
        print("railvib: launch interrupted", file=sys.stderr)
        return 130
    except Exception as e:  # a bad launch file or argument
        try:
            parent.shutdown()
        except Exception:
            pass
        print(f"railvib: launch failed: {e}", file=sys.stderr)
        return 2
    ok, why = verdict(watch.deaths, required if finisher_known else required - {options.finisher},
                      options.finisher if finisher_known else "")
    print(("railvib: launch finished: " if ok else "railvib: launch failed: ") + why, file=sys.stderr)
    return 0 if ok else 1


if __name__ == "__main__":
    sys.exit(main(sys.argv))
