"""cubecal simulate --realtime as a fake sensor: the samples arrive at the
model's rate (every one, each near its time), the same samples as the
record written at once, text or binary frames; a reader that goes away
ends it cleanly."""
import os
import struct
import subprocess
import tempfile
import time
import unittest

BINARY = os.environ.get("CUBECAL_BINARY", "")


def simulate(*args):
    return [BINARY, "simulate", "--preset", "sport-gyro", "--seed", "7", "--temp", "const:25", *args]


@unittest.skipUnless(BINARY, "CUBECAL_BINARY is not set (run the tests through ctest)")
class SimulateRealtime(unittest.TestCase):
    def test_two_seconds_at_100_hz_arrive_in_two_seconds(self):
        p = subprocess.Popen(simulate("--rate", "100", "--duration", "2s", "--realtime", "--out", "-"),
                             stdout=subprocess.PIPE, stderr=subprocess.PIPE)
        arrivals, lines = [], []
        for line in p.stdout:  # a line as soon as it is written
            arrivals.append(time.monotonic())
            lines.append(line.decode().rstrip("\n"))
        end = time.monotonic()
        p.stdout.close()
        self.assertEqual(p.wait(), 0, p.stderr.read())
        p.stderr.close()
        self.assertEqual(lines[0], "t,gx,gy,gz,temp")
        samples = lines[1:]
        self.assertEqual(len(samples), 200, "every sample")
        t = [float(s.split(",")[0]) for s in samples]
        for k, tk in enumerate(t):
            self.assertAlmostEqual(tk, k / 100.0, places=9)
        # Sample k leaves at t0 + k / 100: the 2 s record takes 2 s from its
        # first sample to the end of the output (+- 0.2 s).
        took = end - arrivals[1] + 0.01
        self.assertGreater(took, 1.8, "not paced")
        self.assertLess(took, 2.2, "paced too slowly")
        # Each sample near its time: none early, none more than 50 ms late
        # against the earliest (arrival - t).
        offsets = [a - tk for a, tk in zip(arrivals[1:], t)]
        late = max(offsets) - min(offsets)
        self.assertLess(late, 0.05, "a sample %.3f s late" % late)

    def test_same_samples_as_the_record_written_at_once(self):
        with tempfile.TemporaryDirectory() as d:
            path = os.path.join(d, "sim.csv")
            subprocess.run(simulate("--rate", "200", "--duration", "1s", "--out", path), check=True,
                           capture_output=True)
            with open(path) as f:
                at_once = f.read().splitlines()
        paced = subprocess.run(simulate("--rate", "200", "--duration", "1s", "--realtime", "--out", "-"),
                               capture_output=True, check=True).stdout.decode().splitlines()
        self.assertEqual(len(at_once), 201)
        self.assertEqual(paced, at_once)

    def test_binary_frames(self):
        spec = "sync=A55A;fields=t:f64,gx:f32,gy:f32,gz:f32;checksum=xor8;endian=le"
        paced = subprocess.run(simulate("--rate", "100", "--duration", "0.5s", "--realtime", "--frame", spec,
                                        "--out", "-"), capture_output=True, check=True).stdout
        text = subprocess.run(simulate("--rate", "100", "--duration", "0.5s", "--realtime", "--out", "-"),
                              capture_output=True, check=True).stdout.decode().splitlines()[1:]
        size = 2 + 8 + 3 * 4 + 1
        self.assertEqual(len(paced), 50 * size)
        for k in range(50):
            frame = paced[k * size:(k + 1) * size]
            self.assertEqual(frame[:2], b"\xa5\x5a")
            xor = 0
            for b in frame[2:-1]:
                xor ^= b
            self.assertEqual(xor, frame[-1], "checksum of frame %d" % k)
            t, gx, gy, gz = struct.unpack("<dfff", frame[2:-1])
            want = [float(v) for v in text[k].split(",")[:4]]
            self.assertAlmostEqual(t, k / 100.0, places=12)
            self.assertLessEqual(abs(t - want[0]), abs(t) * 5e-9)
            # float32 of the simulated double (half an ulp, 2^-24 relative)
            # against its text (nine significant digits, 5e-9 relative).
            for got, w in zip((gx, gy, gz), want[1:]):
                self.assertLessEqual(abs(got - w), abs(w) * (2.0 ** -24 + 5e-9), "frame %d" % k)

    def test_reader_gone_ends_the_stream_cleanly(self):
        p = subprocess.Popen(simulate("--rate", "100", "--duration", "1h", "--realtime", "--out", "-"),
                             stdout=subprocess.PIPE, stderr=subprocess.PIPE)
        for _ in range(6):
            p.stdout.readline()
        p.stdout.close()  # the reader goes away
        start = time.monotonic()
        rc = p.wait(timeout=5)
        self.assertLess(time.monotonic() - start, 1.0, "noticed at the next sample")
        self.assertEqual(rc, 0)
        err = p.stderr.read().decode()
        p.stderr.close()
        self.assertIn("went away", err)
        self.assertEqual(len(err.strip().splitlines()), 1, err)

    def test_realtime_needs_the_standard_output(self):
        p = subprocess.run(simulate("--duration", "1s", "--realtime", "--out", "x.csv"), capture_output=True)
        self.assertEqual(p.returncode, 2)
        self.assertIn("--out -", p.stderr.decode())


if __name__ == "__main__":
    unittest.main()
