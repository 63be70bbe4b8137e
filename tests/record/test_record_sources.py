"""cubecal record as a process, its sources and its faces: UDP datagrams on
127.0.0.1, binary frames (--frame) with bad checksums and garbage between
them, the status line on a terminal (and its absence on a pipe), --duration
and SIGTERM ending a run cleanly, a restart with other columns refused, and
a pseudo-terminal opened as a serial device."""
import os
import signal
import socket
import struct
import subprocess
import tempfile
import termios
import threading
import time
import unittest

from recording_check import chunk_lines, manifest

BINARY = os.environ.get("CUBECAL_BINARY", "")


def rejects(d, seg):
    """(reason, data) of each row of the segment's rejects.csv."""
    path = os.path.join(d, seg["dir"], "rejects.csv")
    if not os.path.exists(path):
        return []
    with open(path) as f:
        rows = f.read().splitlines()
    assert rows[0] == "host_mono_s,host_utc_s,reason,data"
    out = []
    for row in rows[1:]:
        _, _, rest = row.split(",", 2)
        assert rest.startswith('"'), row
        end = rest.index('"', 1)
        out.append((rest[1:end], rest[end + 2:]))
    return out


def sensor_line(i):
    return "%.2f,%.4f,%d" % (i / 100.0, 1e-4 * ((i * 7919) % 1000), i)


def port_bound_udp(port):
    """True once some socket is bound to UDP `port` (IPv4 or IPv6)."""
    for table in ("/proc/net/udp", "/proc/net/udp6"):
        try:
            with open(table) as f:
                next(f)
                for row in f:
                    if int(row.split()[1].rsplit(":", 1)[1], 16) == port:
                        return True
        except OSError:
            pass
    return False


def udp_local_addresses(port):
    """The local addresses (hex, as /proc/net/udp* write them) bound to UDP `port`."""
    found = []
    for table in ("/proc/net/udp", "/proc/net/udp6"):
        try:
            with open(table) as f:
                next(f)
                for row in f:
                    addr, p = row.split()[1].rsplit(":", 1)
                    if int(p, 16) == port:
                        found.append(addr)
        except OSError:
            pass
    return found


def free_udp_port():
    s = socket.socket(socket.AF_INET, socket.SOCK_DGRAM)
    s.bind(("127.0.0.1", 0))
    port = s.getsockname()[1]
    s.close()
    return port


def crc16_ccitt_false(data):
    crc = 0xFFFF
    for b in data:
        crc ^= b << 8
        for _ in range(8):
            crc = ((crc << 1) ^ 0x1021) if crc & 0x8000 else crc << 1
            crc &= 0xFFFF
    return crc


@unittest.skipUnless(BINARY, "CUBECAL_BINARY is not set (run through ctest)")
class RecordSources(unittest.TestCase):
    def setUp(self):
        self.tmp = tempfile.TemporaryDirectory()

    def tearDown(self):
        self.tmp.cleanup()

    def out(self, name):
        return os.path.join(self.tmp.name, name)

    def test_udp_datagrams_of_several_lines(self):
        port = free_udp_port()
        d = self.out("udp")
        p = subprocess.Popen([BINARY, "record", "udp:%d" % port, "--out", d], stderr=subprocess.PIPE)
        deadline = time.monotonic() + 10
        while not port_bound_udp(port):
            self.assertIsNone(p.poll(), "the recorder ended before listening")
            self.assertLess(time.monotonic(), deadline, "udp:%d never bound" % port)
            time.sleep(0.02)
        s = socket.socket(socket.AF_INET, socket.SOCK_DGRAM)
        s.sendto(b"t,gx,n\n", ("127.0.0.1", port))
        # 60 datagrams of 1 to 9 lines each, 300 lines in all.
        sent, k = 0, 0
        while sent < 300:
            n = min(1 + k % 9, 300 - sent)
            s.sendto("".join(sensor_line(sent + i) + "\n" for i in range(n)).encode(), ("127.0.0.1", port))
            sent += n
            k += 1
            if k % 10 == 0:
                time.sleep(0.01)
        s.close()
        time.sleep(0.5)
        p.send_signal(signal.SIGTERM)
        err = p.stderr.read().decode()
        p.stderr.close()
        self.assertEqual(p.wait(timeout=20), 0, err)
        m = manifest(d)
        self.assertEqual(m["source"], "udp:%d" % port)
        self.assertEqual(m["columns"], ["t", "gx", "n"])
        seg = m["segments"][0]
        self.assertEqual(seg["end"], "clean")
        self.assertEqual(seg["samples"], 300)
        self.assertEqual(seg["rejects"], 0)
        self.assertEqual(chunk_lines(d), [sensor_line(i) for i in range(300)])

    def start_udp(self, source, port, d):
        p = subprocess.Popen([BINARY, "record", source, "--out", d], stderr=subprocess.PIPE)
        self.addCleanup(lambda: p.poll() is None and (p.kill(), p.wait()))  # a failed test leaves no recorder
        deadline = time.monotonic() + 10
        while not port_bound_udp(port):
            self.assertIsNone(p.poll(), "the recorder ended before listening")
            self.assertLess(time.monotonic(), deadline, "%s never bound" % source)
            time.sleep(0.02)
        return p

    def stop(self, p):
        time.sleep(0.5)
        p.send_signal(signal.SIGTERM)
        err = p.stderr.read().decode()
        p.stderr.close()
        self.assertEqual(p.wait(timeout=20), 0, err)

    def test_udp_port_binds_loopback(self):
        # Issue 33, item 8: udp:PORT listens on 127.0.0.1 only (the docs say
        # a local port; every interface is udp:0.0.0.0:PORT).
        port = free_udp_port()
        p = self.start_udp("udp:%d" % port, port, self.out("udp_lo"))
        self.assertEqual(udp_local_addresses(port), ["0100007F"])
        s = socket.socket(socket.AF_INET, socket.SOCK_DGRAM)
        s.sendto(b"t,gx\n0,1\n", ("127.0.0.1", port))
        s.close()
        self.stop(p)

    def test_udp_datagram_ends_a_line(self):
        # Issue 33, item 8: a datagram without a trailing newline is a line of
        # its own rather than glued to the next datagram.
        port = free_udp_port()
        d = self.out("udp_lines")
        p = self.start_udp("udp:%d" % port, port, d)
        s = socket.socket(socket.AF_INET, socket.SOCK_DGRAM)
        for datagram in (b"t,gx,n", b"0.00,1,0", b"0.01,2,1\n0.02,3,2", b"0.03,4,3\r\n", b"0.04,5,4"):
            s.sendto(datagram, ("127.0.0.1", port))
            time.sleep(0.01)
        s.close()
        self.stop(p)
        m = manifest(d)
        self.assertEqual(m["columns"], ["t", "gx", "n"])
        self.assertEqual(m["segments"][0]["rejects"], 0)
        self.assertEqual(chunk_lines(d), ["0.00,1,0", "0.01,2,1", "0.02,3,2", "0.03,4,3", "0.04,5,4"])

    def test_udp_on_every_interface_when_asked(self):
        port = free_udp_port()
        d = self.out("udp_all")
        p = self.start_udp("udp:0.0.0.0:%d" % port, port, d)
        self.assertEqual(udp_local_addresses(port), ["00000000"])
        s = socket.socket(socket.AF_INET, socket.SOCK_DGRAM)
        s.sendto(b"t,gx\n0,1\n", ("127.0.0.1", port))
        s.close()
        self.stop(p)
        self.assertEqual(manifest(d)["source"], "udp:0.0.0.0:%d" % port)
        self.assertEqual(chunk_lines(d), ["0,1"])

    def test_binary_frames_with_bad_checksums_and_garbage(self):
        spec = "sync=A55A;fields=t:u32,gx:i16,gy:i16,gz:i16;checksum=crc16;endian=le"
        good, bad_frames, garbage_runs = [], [], []
        stream = bytearray()
        for i in range(200):
            body = struct.pack("<Ihhh", 10 * i, (i * 37) % 2000 - 1000, -i, 3 * i)
            frame = b"\xa5\x5a" + body + struct.pack("<H", crc16_ccitt_false(body))
            if i >= 50 and i % 25 == 0:  # 6 frames with a payload bit flipped
                frame = frame[:4] + bytes([frame[4] ^ 0x10]) + frame[5:]
                bad_frames.append(frame.hex())
            else:
                good.append("%d,%d,%d,%d" % struct.unpack("<Ihhh", body))
            stream += frame
            if i % 40 == 7:  # 5 runs of garbage between frames (no sync byte in them)
                junk = bytes((i * 13 + k) % 0xA0 for k in range(3 + i % 11))
                garbage_runs.append(junk.hex())
                stream += junk
        d = self.out("frames")
        r = subprocess.run([BINARY, "record", "-", "--out", d, "--frame", spec], input=bytes(stream),
                           capture_output=True, timeout=30)
        self.assertEqual(r.returncode, 0, r.stderr)
        m = manifest(d)
        self.assertEqual(m["columns"], ["t", "gx", "gy", "gz"])
        self.assertEqual(m["framing"], {"kind": "binary", "frame": spec})
        self.assertEqual(m["time_column"], "t")
        seg = m["segments"][0]
        self.assertEqual(len(bad_frames), 6)
        self.assertEqual(seg["samples"], 194)
        self.assertEqual(chunk_lines(d), good)
        self.assertEqual(seg["rejects"], len(bad_frames) + len(garbage_runs))
        rows = rejects(d, seg)
        self.assertEqual(sorted(x for reason, x in rows if reason == "bad checksum"), sorted(bad_frames))
        self.assertEqual([x for reason, x in rows if reason.startswith("bytes skipped")], garbage_runs)
        # Each missing frame is a gap of 20 in the device time (period 10).
        gaps = [e for e in seg["events"] if e["kind"] == "gap"]
        self.assertEqual([(e["dt"], e["expected_dt"]) for e in gaps], [(20.0, 10.0)] * 6)

    def run_with_stderr(self, stderr_tty):
        """Records 2 s of slow lines with 2 rejects; returns (exit code,
        what stderr received, directory)."""
        d = self.out("status-tty" if stderr_tty else "status-pipe")
        if stderr_tty:
            master, slave = os.openpty()
            p = subprocess.Popen([BINARY, "record", "-", "--out", d], stdin=subprocess.PIPE, stderr=slave)
            os.close(slave)
            received = bytearray()

            def drain():
                while True:
                    try:
                        b = os.read(master, 4096)
                    except OSError:  # EIO: the slave side closed
                        break
                    if not b:
                        break
                    received.extend(b)

            reader = threading.Thread(target=drain, daemon=True)
            reader.start()
        else:
            p = subprocess.Popen([BINARY, "record", "-", "--out", d], stdin=subprocess.PIPE, stderr=subprocess.PIPE)
        p.stdin.write(b"t,gx,n\n")
        for step in range(20):
            p.stdin.write("".join(sensor_line(step * 10 + i) + "\n" for i in range(10)).encode())
            if step in (3, 11):
                p.stdin.write(b"1.0,abc,3\n")
            p.stdin.flush()
            time.sleep(0.1)
        p.stdin.close()
        rc = p.wait(timeout=20)
        if stderr_tty:
            reader.join(timeout=5)
            os.close(master)
            text = bytes(received).decode(errors="replace")
        else:
            text = p.stderr.read().decode()
            p.stderr.close()
        return rc, text, d

    def test_status_line_on_a_terminal(self):
        rc, text, d = self.run_with_stderr(True)
        self.assertEqual(rc, 0, text)
        body, _, summary = text.rpartition("\n")
        if not summary:
            body, _, summary = body.rpartition("\n")
        self.assertIn("cubecal: record: source ended", summary)
        self.assertIn("200 samples", summary)
        self.assertIn("2 rejected", summary)
        # The status line is redrawn in place: a carriage return per drawing,
        # several over 2 s (every 0.5 s).
        draws = [s for s in body.split("\r") if "samples/s" in s]
        self.assertGreaterEqual(len(draws), 3, repr(text))
        for s in draws:
            self.assertRegex(s, r"\d+:\d\d:\d\d  \d+ samples/s  \d+ samples  rejected \d+  gaps \d+  resets \d+")
        self.assertRegex(draws[-1], r"rejected 2 ")
        self.assertIn("free ", draws[-1])
        self.assertEqual(manifest(d)["segments"][0]["samples"], 200)

    def test_no_status_line_on_a_pipe(self):
        rc, text, d = self.run_with_stderr(False)
        self.assertEqual(rc, 0, text)
        self.assertNotIn("\r", text)
        self.assertNotIn("samples/s", text)
        lines = text.splitlines()
        self.assertEqual(len(lines), 1, text)
        self.assertTrue(lines[0].startswith("cubecal: record: source ended after "), text)
        self.assertIn("200 samples", lines[0])
        self.assertIn("2 rejected", lines[0])

    def test_duration_ends_cleanly(self):
        d = self.out("duration")
        start = time.monotonic()
        p = subprocess.Popen([BINARY, "record", "-", "--out", d, "--duration", "2s"], stdin=subprocess.PIPE,
                             stderr=subprocess.PIPE)
        p.stdin.write(b"t,gx,n\n" + "".join(sensor_line(i) + "\n" for i in range(50)).encode())
        p.stdin.flush()  # the pipe stays open: only the duration ends the run
        err = p.stderr.read().decode()
        rc = p.wait(timeout=20)
        elapsed = time.monotonic() - start
        p.stdin.close()
        p.stderr.close()
        self.assertEqual(rc, 0, err)
        self.assertGreaterEqual(elapsed, 2.0)
        self.assertLess(elapsed, 5.0)
        self.assertIn("duration reached", err)
        seg = manifest(d)["segments"][0]
        self.assertEqual(seg["end"], "clean")
        self.assertTrue(seg["end_utc"])
        self.assertEqual(chunk_lines(d), [sensor_line(i) for i in range(50)])

    def test_sigterm_ends_cleanly(self):
        d = self.out("sigterm")
        p = subprocess.Popen([BINARY, "record", "-", "--out", d], stdin=subprocess.PIPE, stderr=subprocess.PIPE)
        p.stdin.write(b"t,gx,n\n" + "".join(sensor_line(i) + "\n" for i in range(120)).encode())
        p.stdin.flush()
        time.sleep(0.7)
        p.send_signal(signal.SIGTERM)
        err = p.stderr.read().decode()
        rc = p.wait(timeout=20)
        p.stdin.close()
        p.stderr.close()
        self.assertEqual(rc, 0, err)
        self.assertIn("cubecal: record: stopped after", err)
        seg = manifest(d)["segments"][0]
        self.assertEqual(seg["end"], "clean")
        self.assertEqual(seg["samples"], 120)
        self.assertEqual(chunk_lines(d), [sensor_line(i) for i in range(120)])

    def test_input_without_any_data_is_reported(self):
        # Only lines that are not data, then the end: nothing can be recorded
        # (no layout), and the user is told what arrived instead.
        d = self.out("nodata")
        r = subprocess.run([BINARY, "record", "-", "--out", d], input=b"# a comment\n# another\n",
                           capture_output=True, timeout=30)
        self.assertEqual(r.returncode, 2, r.stderr)
        err = r.stderr.decode()
        self.assertEqual(len(err.strip().splitlines()), 1, err)
        self.assertIn("no data line or frame arrived", err)
        self.assertIn("2 piece(s) of input were not data", err)
        self.assertIn("# a comment", err)

    def test_restart_with_other_columns_is_refused(self):
        d = self.out("restart")
        first = "t,gx,n\n" + "".join(sensor_line(i) + "\n" for i in range(30))
        r = subprocess.run([BINARY, "record", "-", "--out", d], input=first.encode(), capture_output=True, timeout=30)
        self.assertEqual(r.returncode, 0, r.stderr)
        with open(os.path.join(d, "manifest.json"), "rb") as f:
            before = f.read()
        r = subprocess.run([BINARY, "record", "-", "--out", d], input=b"t,gx\n0.01,1\n0.02,2\n",
                           capture_output=True, timeout=30)
        self.assertEqual(r.returncode, 2, r.stderr)
        err = r.stderr.decode()
        self.assertEqual(len(err.strip().splitlines()), 1, err)
        self.assertIn("t,gx,n", err)
        self.assertIn("columns", err)
        with open(os.path.join(d, "manifest.json"), "rb") as f:
            self.assertEqual(f.read(), before)
        self.assertFalse(os.path.exists(os.path.join(d, "seg-002")))
        self.assertEqual(chunk_lines(d), [sensor_line(i) for i in range(30)])

    def test_pseudo_terminal_as_a_serial_device(self):
        master, slave = os.openpty()
        name = os.ttyname(slave)
        d = self.out("serial")
        p = subprocess.Popen([BINARY, "record", name, "--baud", "115200", "--out", d], stderr=subprocess.PIPE)
        try:
            # The recorder sets the line up (raw, 115200 8N1) once it has it
            # open: wait for that before sending, as a board would be
            # streaming already.
            deadline = time.monotonic() + 10
            while termios.tcgetattr(slave)[3] & termios.ICANON:
                if p.poll() is not None:
                    # libserialport refuses a pseudo-terminal (it looks ports up
                    # in /sys/class/tty); the recorder opens it through termios.
                    self.fail(p.stderr.read().decode())
                self.assertLess(time.monotonic(), deadline, "the recorder never set the port up")
                time.sleep(0.02)
            self.assertEqual(termios.tcgetattr(slave)[5], termios.B115200)
            os.write(master, b"t,gx,n\r\n")
            for step in range(10):  # ~115200 baud: 20 lines of ~20 bytes every 40 ms
                os.write(master, "".join(sensor_line(step * 20 + i) + "\r\n" for i in range(20)).encode())
                time.sleep(0.04)
            time.sleep(0.5)
            p.send_signal(signal.SIGTERM)
            err = p.stderr.read().decode()
            self.assertEqual(p.wait(timeout=20), 0, err)
        finally:
            if p.poll() is None:
                p.kill()
                p.wait()
            p.stderr.close()
            os.close(slave)
            os.close(master)
        m = manifest(d)
        self.assertEqual(m["source"], "%s at 115200 baud" % name)
        seg = m["segments"][0]
        self.assertEqual(seg["end"], "clean")
        self.assertEqual(seg["rejects"], 0)
        self.assertEqual(chunk_lines(d), [sensor_line(i) for i in range(200)])


if __name__ == "__main__":
    unittest.main()
