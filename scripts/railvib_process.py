"""Starting and ending the processes a script or test harness runs (launches, masters, nodes), so that
none outlives it:

- `interrupts_by_default()`: a script started in the background (`cmd &` in a non-interactive shell,
  nohup) inherits SIGINT ignored, and so would every process it starts; the master would then never
  end on SIGINT. Called first thing, it gives the script (and what it starts) the default Ctrl-C.
- `free_port()`: a TCP port no process listens on, from the system (for a master of one's own: two
  studies, test suites or harnesses at once never pick the same one, as fixed ranges did).
- `stop(proc)`: ends a process started with `start_new_session=True` and everything in its group:
  SIGINT (a clean ROS shutdown), then SIGTERM after a grace period, then SIGKILL; returns what
  `communicate()` returns, so the caller keeps the output.
"""
import os
import signal
import socket
import subprocess


def free_port():
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


def interrupts_by_default():
    signal.signal(signal.SIGINT, signal.default_int_handler)


def _signal_group(pid, sig):
    try:
        os.killpg(pid, sig)
        return True
    except ProcessLookupError:  # the group has ended
        return False


def stop(proc, grace_s=30.0, term_grace_s=10.0):
    """SIGINT to PROC's group, SIGTERM after GRACE_S, SIGKILL after TERM_GRACE_S more; (stdout, stderr)."""
    if proc.poll() is not None:
        return proc.communicate()
    for sig, wait_s in ((signal.SIGINT, grace_s), (signal.SIGTERM, term_grace_s), (signal.SIGKILL, None)):
        if not _signal_group(proc.pid, sig):
            return proc.communicate()
        try:
            return proc.communicate(timeout=wait_s)
        except subprocess.TimeoutExpired:
            continue
    return proc.communicate()
