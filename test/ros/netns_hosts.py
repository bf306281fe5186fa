#!/usr/bin/env python3
"""Two hosts on one machine: network namespaces joined by a virtual link (docs/ros.md, "Over several
hosts"). The test creates them and removes them; their addresses are TEST-NET-1 (RFC 5737,
192.0.2.0/24), which no real network routes.

- the ROS graph split over the two hosts (master, vehicle, track on host A; soil, building, sensors
  and recorder on host B, each with its own ROS_IP) records the same bag, bit for bit, as the whole
  graph on host A alone;
- the soil's MPI ranks on the two hosts (OpenMPI's rsh launcher given an agent that enters the
  namespace, TCP between the ranks) agree with one rank to float round-off: test_soil_mpi's checks.

Needs root (ip netns). usage: netns_hosts.py TEST_SOIL_MPI RESULTS_XML
"""
import os
import pathlib
import shutil
import subprocess
import sys
import tempfile
import time
import unittest

ROOT = pathlib.Path(__file__).resolve().parents[2]
sys.path.insert(0, str(ROOT / "scripts"))
sys.path.insert(0, str(ROOT / "test" / "ros"))
import bag_check  # noqa: E402
import railvib_names as names  # noqa: E402
import railvib_process  # noqa: E402
from compare_bags import compare_topic  # noqa: E402
from junit_xml import run_verbose, write_junit  # noqa: E402

LAUNCHER = str(ROOT / "scripts" / "launch_scenario.py")
CONFIG = str(ROOT / "config" / "haren_ci.yaml")
TEST_SOIL_MPI = ""
WORK = pathlib.Path(tempfile.mkdtemp(prefix="railvib_netns_"))
TAG = str(os.getpid() % 100000)
HOSTS = {"a": ("rv" + TAG + "a", "192.0.2.1"), "b": ("rv" + TAG + "b", "192.0.2.2")}
PORT = 11311
MPI_ENV = {"OMPI_ALLOW_RUN_AS_ROOT": "1", "OMPI_ALLOW_RUN_AS_ROOT_CONFIRM": "1", "OMP_NUM_THREADS": "1"}


def ip(*args):
    subprocess.run(["ip"] + list(args), check=True, capture_output=True, text=True)


def create_hosts():
    remove_hosts()
    (ns_a, addr_a), (ns_b, addr_b) = HOSTS["a"], HOSTS["b"]
    ip("netns", "add", ns_a)
    ip("netns", "add", ns_b)
    ip("link", "add", ns_a + "0", "type", "veth", "peer", "name", ns_b + "0")
    for ns, addr in ((ns_a, addr_a), (ns_b, addr_b)):
        ip("link", "set", ns + "0", "netns", ns)
        ip("-n", ns, "addr", "add", addr + "/24", "dev", ns + "0")
        ip("-n", ns, "link", "set", ns + "0", "up")
        ip("-n", ns, "link", "set", "lo", "up")


def remove_hosts():
    for ns, _ in HOSTS.values():
        subprocess.run(["ip", "netns", "del", ns], capture_output=True)  # the veth pair goes with them


def on_host(host, cmd, env_extra=None, **kwargs):
    """Popen of cmd inside the host's namespace with ROS_IP (and ROS_HOSTNAME) set to its address."""
    ns, addr = HOSTS[host]
    env = dict(os.environ, ROS_IP=addr, ROS_HOSTNAME=addr, ROS_MASTER_URI=f"http://{HOSTS['a'][1]}:{PORT}")
    env.update(env_extra or {})
    return subprocess.Popen(["ip", "netns", "exec", ns] + cmd, env=env, text=True, **kwargs)


def wait_for_node(host, node, timeout_s=120.0):
    deadline = time.time() + timeout_s
    while time.time() < deadline:
        p = on_host(host, ["rosnode", "list"], stdout=subprocess.PIPE, stderr=subprocess.DEVNULL)
        out, _ = p.communicate(timeout=60)
        if node in out.split():
            return True
        time.sleep(0.2)
    return False


def stop(proc):
    railvib_process.stop(proc, grace_s=60.0)


class NetnsHosts(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        create_hosts()

    @classmethod
    def tearDownClass(cls):
        remove_hosts()

    def launch_part(self, host, part, bag, log):
        args = [sys.executable, LAUNCHER] + (["-p", str(PORT)] if host == "a" else []) + [
            "railvib", "haren.launch", "config:=" + CONFIG, "part:=" + part, "bag:=" + str(bag)]
        return on_host(host, args, stdout=open(log, "w"), stderr=subprocess.STDOUT, start_new_session=True)

    def test_graph_over_two_hosts_records_the_single_host_bag(self):
        single = WORK / "single.bag"
        log = WORK / "single.log"
        p = self.launch_part("a", "all", single, log)
        self.assertEqual(p.wait(timeout=600), 0, log.read_text()[-3000:])

        split = WORK / "split.bag"
        upstream = self.launch_part("a", "upstream", WORK / "unused.bag", WORK / "upstream.log")
        try:
            self.assertTrue(wait_for_node("b", "/vehicle"), "host B does not see the master and vehicle on host A:\n"
                            + (WORK / "upstream.log").read_text()[-3000:])
            downstream = self.launch_part("b", "downstream", split, WORK / "downstream.log")
            # Host B's nodes talk from host B's address, host A's from A's: the master lists their URIs.
            uris = {}
            deadline = time.time() + 120.0
            while time.time() < deadline and downstream.poll() is None and len(uris) < 3:
                p = on_host("a", ["rosnode", "list", "-a"], stdout=subprocess.PIPE, stderr=subprocess.DEVNULL)
                for line in p.communicate(timeout=60)[0].splitlines():
                    parts = line.split()  # "URI<tab>NODE"
                    if len(parts) == 2 and parts[1] in ("/soil", "/recorder", "/vehicle"):
                        uris[parts[1]] = parts[0]
                time.sleep(0.2)
            code = downstream.wait(timeout=600)
            self.assertEqual(code, 0, (WORK / "downstream.log").read_text()[-3000:])
        finally:
            stop(upstream)
        for node, host in (("/soil", "b"), ("/recorder", "b"), ("/vehicle", "a")):
            self.assertTrue(uris.get(node, "").startswith(f"http://{HOSTS[host][1]}:"), f"{node}: {uris}")
        checked = bag_check.check_bag(split)
        self.assertEqual(checked.code, 0, f"{checked.refused} {checked.findings}")
        for topic in names.STREAMS + [names.SENSOR_METRICS]:
            same, line = compare_topic(single, split, topic)
            self.assertTrue(same, line)

    def test_soil_ranks_on_two_hosts_agree_with_one_rank(self):
        agent = WORK / "netns_agent.sh"
        # OpenMPI runs `agent HOST COMMAND...` the way it would run ssh: enter the host's namespace instead.
        cases = "\n".join(f"  {addr}) ns={ns} ;;" for ns, addr in HOSTS.values())
        agent.write_text("#!/bin/sh\nhost=$1; shift\ncase \"$host\" in\n" + cases +
                         "\n  *) echo \"netns agent: unknown host $host\" >&2; exit 1 ;;\nesac\n"
                         "exec ip netns exec \"$ns\" /bin/sh -c \"$*\"\n")
        agent.chmod(0o755)
        hostfile = WORK / "hosts"
        hostfile.write_text("".join(f"{addr} slots=1\n" for _, addr in HOSTS.values()))
        # No binding: OpenMPI sees two hosts and would pin each one's rank to "its" core 0, the same core.
        mpirun = ["mpirun", "-np", "2", "--bind-to", "none", "--hostfile", str(hostfile),
                  "--mca", "plm_rsh_agent", str(agent), "--mca", "oob_tcp_if_include", "192.0.2.0/24",
                  "--mca", "btl_tcp_if_include", "192.0.2.0/24", "--mca", "btl", "tcp,self",
                  "-x", "OMP_NUM_THREADS", "-x", "PATH"]
        where = on_host("a", mpirun + ["sh", "-c", "echo rank $OMPI_COMM_WORLD_RANK at "
                                       "$(ip -o -4 addr show | grep -o '192\\.0\\.2\\.[0-9]*')"],
                        env_extra=MPI_ENV, stdout=subprocess.PIPE, stderr=subprocess.STDOUT)
        out, _ = where.communicate(timeout=120)
        self.assertIn(f"rank 0 at {HOSTS['a'][1]}", out)
        self.assertIn(f"rank 1 at {HOSTS['b'][1]}", out)
        run = on_host("a", mpirun + [TEST_SOIL_MPI, "--gtest_filter=*AgreesWithOneRank*"],
                      env_extra=MPI_ENV, stdout=subprocess.PIPE, stderr=subprocess.STDOUT)
        out, _ = run.communicate(timeout=900)
        print(out[-2500:])
        self.assertEqual(run.returncode, 0, out[-3000:])
        self.assertIn("PASSED", out)
        self.assertIn("2 ranks vs 1 rank", out)



if __name__ == "__main__":
    if len(sys.argv) != 3:
        sys.exit(__doc__)
    TEST_SOIL_MPI = sys.argv[1]
    railvib_process.interrupts_by_default()
    suite = unittest.defaultTestLoader.loadTestsFromTestCase(NetnsHosts)
    result = run_verbose(suite)
    write_junit(result, "netns_hosts", NetnsHosts, sys.argv[2])
    shutil.rmtree(WORK, ignore_errors=True)
    sys.exit(0 if result.wasSuccessful() else 1)
