"""cubecal record as a process: kill -9 at random moments (loss against what
was sent, every chunk readable and matching its CRC), a file-size limit
(a clear error, earlier chunks intact), malformed and partial lines in
rejects.csv, and a TCP source on 127.0.0.1 that drops and comes back."""
import os
import random
import resource
import signal
import socket
import subprocess
import tempfile
import threading
import time
import unittest
import zlib

from recording_check import chunk_lines, manifest

BINARY = os.environ.get("CUBECAL_BINARY", "")
RATE = 200.0  # lines per second the fake sensor sends


def sensor_line(i):
    return "%.3f,%.6f,%d" % (i / RATE, 1e-3 * ((i * 7919) % 1000), i)


class Sender(threading.Thread):
    """Writes sensor lines to a pipe at RATE, 2 lines every 10 ms; `sent`
    counts the lines whose write() returned."""

    def __init__(self, stream):
        super().__init__(daemon=True)
        self.stream = stream
        self.sent = 0
        self.stop = False

    def run(self):
        try:
            self.stream.write(b"t,gx,n\n")
            self.stream.flush()
            start = time.monotonic()
            while not self.stop:
                due = int((time.monotonic() - start) * RATE)
                if due > self.sent:
                    chunk = "".join(sensor_line(i) + "\n" for i in range(self.sent, due)).encode()
                    self.stream.write(chunk)
                    self.stream.flush()
                    self.sent = due
                time.sleep(0.01)
        except (BrokenPipeError, ValueError, OSError):
            pass


@unittest.skipUnless(BINARY, "CUBECAL_BINARY is not set (run through ctest)")
class RecordProcess(unittest.TestCase):
    def setUp(self):
        self.tmp = tempfile.TemporaryDirectory()

    def tearDown(self):
        self.tmp.cleanup()

    def test_kill9_loses_at_most_one_second(self):
        rng = random.Random(17)
        rows = []
        for trial in range(20):
            d = os.path.join(self.tmp.name, "kill%02d" % trial)
            p = subprocess.Popen([BINARY, "record", "-", "--out", d, "--chunk-seconds", "0.3"],
                                 stdin=subprocess.PIPE, stderr=subprocess.PIPE)
            s = Sender(p.stdin)
            s.start()
            time.sleep(rng.uniform(0.3, 1.3))
            p.send_signal(signal.SIGKILL)
            p.wait()
            sent = s.sent
            s.stop = True
            s.join()
            p.stderr.close()
            try:
                p.stdin.close()
            except BrokenPipeError:
                pass
            # A restart recovers the open chunk (no data: no new segment, and
            # exit 2 for a run that recorded nothing).
            r = subprocess.run([BINARY, "record", "-", "--out", d], stdin=subprocess.DEVNULL,
                               capture_output=True, text=True, timeout=30)
            self.assertEqual(r.returncode, 2, r.stderr)
            self.assertIn("recovered after a crash", r.stderr)
            self.assertIn("no input arrived, so nothing was recorded", r.stderr)
            m = manifest(d)
            self.assertEqual(len(m["segments"]), 1)
            self.assertEqual(m["segments"][0]["end"], "recovered")
            kept = chunk_lines(d)
            # What was kept is exactly the first lines sent, none altered.
            self.assertLessEqual(len(kept), sent)
            for i, line in enumerate(kept):
                if line != sensor_line(i):
                    self.fail("trial %d: line %d is %r, sent %r" % (trial, i, line, sensor_line(i)))
            lost_s = (sent - len(kept)) / RATE
            rows.append((trial, sent, len(kept), lost_s, len(m["segments"][0]["chunks"])))
        print("\nkill -9 loss table (sensor at %.0f Hz; lost = (sent - kept) / rate)" % RATE)
        print("%5s %7s %7s %9s %7s" % ("trial", "sent", "kept", "lost [s]", "chunks"))
        for t, sent, kept, lost, chunks in rows:
            print("%5d %7d %7d %9.3f %7d" % (t, sent, kept, lost, chunks))
        worst = max(r[3] for r in rows)
        print("worst loss %.3f s over %d trials" % (worst, len(rows)))
        for t, sent, kept, lost, _ in rows:
            self.assertGreater(kept, 0, "trial %d kept nothing" % t)
            self.assertLessEqual(lost, 1.0, "trial %d lost %.3f s" % (t, lost))

    def test_file_size_limit_is_a_clear_error_and_earlier_chunks_stay(self):
        d = os.path.join(self.tmp.name, "fsize")
        limit = 64 * 1024

        def limit_size():
            resource.setrlimit(resource.RLIMIT_FSIZE, (limit, limit))

        p = subprocess.Popen([BINARY, "record", "-", "--out", d, "--chunk-seconds", "0.5"],
                             stdin=subprocess.PIPE, stderr=subprocess.PIPE, preexec_fn=limit_size)
        p.stdin.write(b"t,gx,n\n")
        i = 0
        try:
            for _ in range(15):  # 1.5 s of slow data: a few small chunks
                p.stdin.write("".join(sensor_line(i + k) + "\n" for k in range(10)).encode())
                p.stdin.flush()
                i += 10
                time.sleep(0.1)
            burst = "".join(sensor_line(i + k) + "\n" for k in range(20000)).encode()  # > limit in one chunk
            p.stdin.write(burst)
            p.stdin.flush()
            time.sleep(0.5)
            p.stdin.close()
        except BrokenPipeError:
            pass
        err = p.stderr.read().decode()
        p.stderr.close()
        rc = p.wait(timeout=30)
        self.assertEqual(rc, 2, err)
        self.assertEqual(len(err.strip().splitlines()), 1, err)
        self.assertIn("write failed (file too large", err)
        self.assertIn("chunks before it are intact", err)
        m = manifest(d)
        seg = m["segments"][0]
        self.assertEqual(seg["end"], "open")
        closed = [c for c in seg["chunks"] if not c["open"]]
        self.assertGreaterEqual(len(closed), 2)
        for c in closed:
            with open(os.path.join(d, seg["dir"], c["file"]), "rb") as f:
                data = f.read()
            self.assertEqual(len(data), c["bytes"])
            self.assertEqual("%08x" % zlib.crc32(data), c["crc32"])
        # A restart (no limit) recovers the chunk that hit the limit (and,
        # receiving nothing, records nothing: exit 2).
        r = subprocess.run([BINARY, "record", "-", "--out", d], stdin=subprocess.DEVNULL,
                           capture_output=True, text=True, timeout=30)
        self.assertEqual(r.returncode, 2, r.stderr)
        self.assertIn("recovered after a crash", r.stderr)
        kept = chunk_lines(d)
        for k, line in enumerate(kept):
            self.assertEqual(line, sensor_line(k))
        self.assertGreaterEqual(len(kept), 150)

    def test_garbage_and_partial_lines_land_in_rejects(self):
        d = os.path.join(self.tmp.name, "rejects")
        good = [sensor_line(i) for i in range(100)]
        bad = ["hello world", "1.0,2.0", "1.0,abc,3", "1,2,3,4", ",,", "# a comment", "1.0,nan,5"]
        lines = ["t,gx,n"]
        for i, g in enumerate(good):
            lines.append(g)
            if i % 14 == 3:
                lines.append(bad[(i // 14) % len(bad)])
        body = "\r\n".join(lines) + "\r\n" + "\r\n" + "4.2,0.1"  # a blank line, then a partial line
        r = subprocess.run([BINARY, "record", "-", "--out", d], input=body.encode(), capture_output=True, timeout=30)
        self.assertEqual(r.returncode, 0, r.stderr)
        expected_bad = [l for l in lines if l in bad]
        m = manifest(d)
        seg = m["segments"][0]
        self.assertEqual(seg["samples"], 100)
        self.assertEqual(seg["rejects"], len(expected_bad) + 1)
        self.assertEqual(chunk_lines(d), good)
        with open(os.path.join(d, seg["dir"], "rejects.csv")) as f:
            rows = f.read().splitlines()
        self.assertEqual(rows[0], "host_mono_s,host_utc_s,reason,data")
        data = [row.split(",", 3)[3] for row in rows[1:]]
        self.assertEqual(data, ['"%s"' % b for b in expected_bad] + ['"4.2,0.1"'])
        self.assertIn("partial line at end of stream", rows[-1])

    def test_tcp_source_reconnects(self):
        srv = socket.socket(socket.AF_INET, socket.SOCK_STREAM)
        srv.setsockopt(socket.SOL_SOCKET, socket.SO_REUSEADDR, 1)
        srv.bind(("127.0.0.1", 0))
        srv.listen(1)
        port = srv.getsockname()[1]
        d = os.path.join(self.tmp.name, "tcp")
        p = subprocess.Popen([BINARY, "record", "tcp:127.0.0.1:%d" % port, "--out", d, "--duration", "3s"],
                             stderr=subprocess.PIPE)
        srv.settimeout(10)
        for part in range(2):
            conn, _ = srv.accept()
            if part == 0:
                conn.sendall(b"t,gx,n\n")
            conn.sendall("".join(sensor_line(part * 300 + i) + "\n" for i in range(300)).encode())
            time.sleep(0.3)
            conn.close()
        err = p.stderr.read().decode()
        p.stderr.close()
        self.assertEqual(p.wait(timeout=30), 0, err)
        srv.close()
        self.assertIn("reconnected", err)
        m = manifest(d)
        self.assertEqual(m["source"], "tcp:127.0.0.1:%d" % port)
        seg = m["segments"][0]
        self.assertEqual(seg["end"], "clean")
        self.assertEqual(chunk_lines(d), [sensor_line(i) for i in range(600)])
        # The first reconnect is at the 301st sample (a later one may follow
        # the second close: the server still listens).
        reconnects = [e for e in seg["events"] if e["kind"] == "reconnect"]
        self.assertGreaterEqual(len(reconnects), 1)
        self.assertEqual(reconnects[0]["sample"], 300)


if __name__ == "__main__":
    unittest.main()
