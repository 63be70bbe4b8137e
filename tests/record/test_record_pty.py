"""The whole acquisition path on a pseudo-terminal pair standing in for a
board on a serial port: `cubecal simulate --realtime` (the paper's gyro at
100 Hz) paced through the pty master no faster than 115200 baud (11520
bytes/s, 8N1), `cubecal record <pty slave> --baud 115200 --out DIR`, then
`cubecal analyze DIR`: every sample kept, the same analysis as the record
simulated at once, and the simulated white noise N recovered within its
95 % interval."""
import json
import os
import select
import signal
import subprocess
import tempfile
import time
import tty
import unittest

BINARY = os.environ.get("CUBECAL_BINARY", "")
RATE_HZ = 100
SECONDS = 30
SEED = 11
BYTES_PER_S = 115200 / 10  # 8N1: ten bits a byte
# The sport-gyro preset's white noise, sigma_n per sample at 10 Hz (docs/paper.md):
# N = sigma_n sqrt(0.1 s), in deg/sqrt(h).
SIGMA_N_10HZ = {"gx": 13.9e-3, "gy": 14.5e-3, "gz": 13.0e-3}
N_TRUE = {axis: s * 0.1 ** 0.5 * 60.0 for axis, s in SIGMA_N_10HZ.items()}


def simulate(*args):
    return [BINARY, "simulate", "--preset", "sport-gyro", "--seed", str(SEED), "--rate", str(RATE_HZ),
            "--duration", "%ds" % SECONDS, "--temp", "const:25", *args]


def analysis(path):
    p = subprocess.run([BINARY, "analyze", path, "--unit", "deg/s", "--format", "json"], capture_output=True,
                       text=True)
    if p.returncode != 0:
        raise AssertionError("cubecal analyze %s: %s" % (path, p.stderr))
    return json.loads(p.stdout)


@unittest.skipUnless(BINARY, "CUBECAL_BINARY is not set (run the tests through ctest)")
class RecordFromPty(unittest.TestCase):
    def test_simulated_gyro_through_a_pty_recovers_its_noise(self):
        with tempfile.TemporaryDirectory() as d:
            rec = os.path.join(d, "rec")
            master, slave = os.openpty()
            tty.setraw(slave)
            slave_path = os.ttyname(slave)
            recorder = subprocess.Popen([BINARY, "record", slave_path, "--baud", "115200", "--out", rec, "--quiet"],
                                        stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
            try:
                # The recorder opens the port before it records (a port it
                # cannot open ends it at once); what the sensor sends meanwhile
                # waits in the pty.
                time.sleep(1.0)
                if recorder.poll() is not None:
                    self.fail("the recorder ended: " + recorder.communicate()[1])
                sensor = subprocess.Popen(simulate("--realtime", "--out", "-"), stdout=subprocess.PIPE,
                                          stderr=subprocess.PIPE)
                # The board's UART: what the sensor sends, through the pty,
                # never faster than 115200 baud.
                start = time.monotonic()
                sent = 0
                pending = b""
                eof = False
                while not eof or pending:
                    if not eof:
                        r, _, _ = select.select([sensor.stdout], [], [], 0.005)
                        if r:
                            chunk = os.read(sensor.stdout.fileno(), 65536)
                            eof = not chunk
                            pending += chunk
                    allowed = int(BYTES_PER_S * (time.monotonic() - start)) - sent
                    if pending and allowed > 0:
                        n = os.write(master, pending[:allowed])
                        sent += n
                        pending = pending[n:]
                    elif eof and pending:
                        time.sleep(0.002)
                self.assertEqual(sensor.wait(), 0, sensor.stderr.read())
                sensor.stdout.close()
                sensor.stderr.close()
                took = time.monotonic() - start
                self.assertGreater(took, SECONDS - 1, "the sensor was not paced")
                time.sleep(1.0)  # the last lines through the pty
                recorder.send_signal(signal.SIGINT)
                out, err = recorder.communicate(timeout=15)
                self.assertEqual(recorder.returncode, 0, err)
            finally:
                if recorder.poll() is None:
                    recorder.kill()
                    recorder.communicate()
                os.close(master)
                os.close(slave)

            with open(os.path.join(rec, "manifest.json")) as f:
                m = json.load(f)
            self.assertEqual(m["format"], "cubecal-record/1")
            self.assertEqual(m["time_column"], "t")
            self.assertEqual(len(m["segments"]), 1)
            seg = m["segments"][0]
            self.assertEqual(seg["end"], "clean")
            self.assertEqual(seg["samples"], RATE_HZ * SECONDS, "every sample recorded")
            self.assertEqual(seg["rejects"], 0)

            # The recording reads as the record simulated at once.
            at_once = os.path.join(d, "sim.csv")
            subprocess.run(simulate("--out", at_once), check=True, capture_output=True)
            got, want = analysis(rec), analysis(at_once)
            self.assertEqual(got["input"]["samples"], RATE_HZ * SECONDS)
            for g, w in zip(got["channels"], want["channels"]):
                self.assertEqual(g["name"], w["name"])
                self.assertEqual(g["mean"], w["mean"])
                self.assertEqual(g["adev"]["dev"], w["adev"]["dev"])
                self.assertEqual(g["noise"]["arw"]["value"], w["noise"]["arw"]["value"])

            # The simulated white noise, recovered: N read off at 1 s within
            # its 95 % interval (1.96 sigma) of the preset's.
            self.assertEqual([c["name"] for c in got["channels"]], ["gx", "gy", "gz"])
            for c in got["channels"]:
                arw = c["noise"]["arw"]
                self.assertEqual(arw["unit"], "deg/sqrt(h)")
                self.assertLessEqual(abs(arw["value"] - N_TRUE[c["name"]]), 1.96 * arw["sigma"],
                                     "%s: N %.4g +- %.2g, simulated %.4g" % (c["name"], arw["value"], arw["sigma"],
                                                                             N_TRUE[c["name"]]))


if __name__ == "__main__":
    unittest.main()
