"""What the record tests check on a recording directory: its manifest, and
the data lines of its chunks after each chunk's bytes, CRC-32, header and
sample count are compared with the manifest."""
import json
import os
import zlib


def manifest(d):
    with open(os.path.join(d, "manifest.json")) as f:
        return json.load(f)


def chunk_lines(d):
    """The data lines (without the two host stamps) of every chunk of every
    segment, in order."""
    m = manifest(d)
    out = []
    for seg in m["segments"]:
        for c in seg["chunks"]:
            path = os.path.join(d, seg["dir"], c["file"])
            with open(path, "rb") as f:
                data = f.read()
            assert not c["open"], path + " left open"
            assert len(data) == c["bytes"], "%s: %d bytes, manifest %d" % (path, len(data), c["bytes"])
            assert "%08x" % zlib.crc32(data) == c["crc32"], path + ": CRC differs from the manifest"
            lines = data.decode().split("\n")
            assert lines[-1] == "", path + ": does not end with a line end"
            assert lines[0] == "host_mono_s,host_utc_s," + ",".join(m["columns"]), path + ": header"
            assert len(lines) - 2 == c["samples"], path + ": sample count"
            out.extend(l.split(",", 2)[2] for l in lines[1:-1])
    return out
