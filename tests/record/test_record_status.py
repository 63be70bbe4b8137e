"""record --target as a process (issue 35, deliverable 3): kill -9 at random
moments of a run with a target, with a reader polling DIR/status.json all
along (the file is always complete JSON once written, never missing, and
the samples before the kill are recovered as record guarantees); and
`analyze DIR` (in memory and --stream) and `cubecal status DIR` on the
recording while it runs; the status line on a terminal."""
import json
import os
import random
import signal
import subprocess
import tempfile
import threading
import time
import unittest

from recording_check import manifest

BINARY = os.environ.get("CUBECAL_BINARY", "")
RATE = 2000  # Hz of the fake sensor (simulate --realtime)


class StatusReader(threading.Thread):
    """Reads DIR/status.json as fast as it can; records every read that was
    not complete JSON of the status format, and a file that vanished once
    it had been seen."""

    def __init__(self, path):
        super().__init__(daemon=True)
        self.path = path
        self.stop = False
        self.reads = 0
        self.bad = []
        self.seen = False
        self.samples = []

    def run(self):
        while not self.stop:
            try:
                with open(self.path, "rb") as f:
                    text = f.read()
            except FileNotFoundError:
                if self.seen:
                    self.bad.append("status.json missing after it was written")
                time.sleep(0.001)
                continue
            self.seen = True
            self.reads += 1
            try:
                j = json.loads(text)
                if j["format"] != "cubecal-record-status/1" or not j["channels"]:
                    self.bad.append("not a status: %r" % text[:80])
                self.samples.append(j["samples"])
            except (ValueError, KeyError) as e:
                self.bad.append("%s: %r" % (e, text[-80:]))


@unittest.skipUnless(BINARY, "CUBECAL_BINARY is not set (run through ctest)")
class RecordStatus(unittest.TestCase):
    def setUp(self):
        self.tmp = tempfile.TemporaryDirectory()

    def tearDown(self):
        self.tmp.cleanup()

    def start(self, d, *extra):
        sim = subprocess.Popen([BINARY, "simulate", "--preset", "sport-gyro", "--rate", str(RATE), "--duration",
                                "60s", "--seed", "9", "--realtime", "--out", "-"],
                               stdout=subprocess.PIPE, stderr=subprocess.DEVNULL)
        rec = subprocess.Popen([BINARY, "record", "-", "--out", d, "--unit", "deg/s", "--target", "B:10%,K:20%",
                                "--status-every", "0.25s", "--chunk-seconds", "0.7", *extra],
                               stdin=sim.stdout, stderr=subprocess.PIPE)
        sim.stdout.close()
        return sim, rec

    def test_kill9_leaves_a_complete_status_and_the_samples(self):
        rng = random.Random(35)
        for trial in range(4):
            d = os.path.join(self.tmp.name, "kill%d" % trial)
            sim, rec = self.start(d)
            reader = StatusReader(os.path.join(d, "status.json"))
            reader.start()
            time.sleep(rng.uniform(0.8, 1.8))
            rec.send_signal(signal.SIGKILL)
            rec.wait()
            time.sleep(0.05)  # the reader reads the file as the kill left it
            reader.stop = True
            reader.join()
            sim.wait()
            rec.stderr.close()
            self.assertEqual(reader.bad, [], "trial %d" % trial)
            self.assertGreater(reader.reads, 3, "trial %d" % trial)
            # Statuses follow each other: samples never go back.
            self.assertEqual(reader.samples, sorted(reader.samples))
            with open(os.path.join(d, "status.json")) as f:
                last = json.load(f)
            self.assertFalse(last["final"])
            self.assertEqual(last["segment"], 1)
            # The first status falls due at 0.25 s of samples (a later one
            # starts at the first sample after the previous one finished).
            self.assertGreaterEqual(last["samples"], RATE // 4)
            # The samples before the kill: a restart recovers the open chunk,
            # and the recovered recording holds at least the status's samples.
            r = subprocess.run([BINARY, "record", "-", "--out", d], stdin=subprocess.DEVNULL,
                               stderr=subprocess.PIPE, timeout=60)
            self.assertEqual(r.returncode, 2, r.stderr)  # recovered, then nothing received
            m = manifest(d)
            self.assertEqual(m["segments"][0]["end"], "recovered")
            self.assertGreaterEqual(m["segments"][0]["samples"], last["samples"])
            a = subprocess.run([BINARY, "analyze", d, "--format", "json"], capture_output=True, timeout=120)
            self.assertEqual(a.returncode, 0, a.stderr)
            # The status of the killed run is still there, whole.
            with open(os.path.join(d, "status.json")) as f:
                self.assertEqual(json.load(f), last)

    def test_analyze_and_status_while_the_recorder_runs(self):
        d = os.path.join(self.tmp.name, "live")
        sim, rec = self.start(d, "--duration", "4s")
        deadline = time.monotonic() + 3.0
        analyses = 0
        while time.monotonic() < deadline:
            if not os.path.exists(os.path.join(d, "status.json")):
                time.sleep(0.05)
                continue
            a = subprocess.run([BINARY, "analyze", d, "--format", "json"], capture_output=True, timeout=60)
            self.assertEqual(a.returncode, 0, a.stderr)
            self.assertGreater(json.loads(a.stdout)["channels"][0]["noise"]["reported"]["white_noise"]["value"], 0)
            st = subprocess.run([BINARY, "analyze", d, "--stream", "--format", "json"], capture_output=True, timeout=60)
            self.assertEqual(st.returncode, 0, st.stderr)
            analyses += 1
            s = subprocess.run([BINARY, "status", d], capture_output=True, text=True, timeout=60)
            self.assertEqual(s.returncode, 0, s.stderr)
            self.assertIn("recorder running", s.stdout.splitlines()[0])
            self.assertIn("\ngx       B  ", s.stdout)
        rec.wait(timeout=30)
        sim.wait(timeout=30)
        err = rec.stderr.read().decode()
        rec.stderr.close()
        self.assertEqual(rec.returncode, 0, err)
        self.assertGreater(analyses, 2)
        with open(os.path.join(d, "status.json")) as f:
            last = json.load(f)
        self.assertTrue(last["final"])
        self.assertEqual(last["samples"], manifest(d)["segments"][0]["samples"])
        s = subprocess.run([BINARY, "status", d], capture_output=True, text=True, timeout=60)
        self.assertIn("recorder ended cleanly", s.stdout)

    def test_status_line_on_a_terminal_shows_the_targets(self):
        d = os.path.join(self.tmp.name, "tty")
        sim = subprocess.Popen([BINARY, "simulate", "--preset", "sport-gyro", "--rate", str(RATE), "--duration",
                                "2.5s", "--seed", "9", "--realtime", "--out", "-"],
                               stdout=subprocess.PIPE, stderr=subprocess.DEVNULL)
        master, slave = os.openpty()
        rec = subprocess.Popen([BINARY, "record", "-", "--out", d, "--target", "B:10%,K:20%", "--status-every",
                                "0.25s"], stdin=sim.stdout, stderr=slave)
        sim.stdout.close()
        os.close(slave)
        received = bytearray()
        while True:
            try:
                b = os.read(master, 4096)
            except OSError:  # EIO: the slave side closed
                break
            if not b:
                break
            received.extend(b)
        rc = rec.wait(timeout=30)
        sim.wait(timeout=30)
        os.close(master)
        text = bytes(received).decode(errors="replace")
        self.assertEqual(rc, 0, text)
        draws = [s for s in text.split("\r") if "samples/s" in s]
        self.assertGreaterEqual(len(draws), 3, repr(text))
        # After the first status (0.25 s of samples), each drawing ends with
        # the targets: how many hold, and the time still needed or why not.
        self.assertRegex(draws[-1], r"  targets \d+/6 met", repr(draws[-1]))


if __name__ == "__main__":
    unittest.main()
