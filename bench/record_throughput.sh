#!/usr/bin/env bash
# cubecal record's cost on a fast text stream: 10 kHz x 10 channels of CSV
# text piped into `cubecal record - --out DIR` for about 20 s; the recorder's
# CPU seconds (user + system, getrusage of the child) over the wall seconds,
# min / median / max of three runs. Target: < 5 % of a core. Beside it, in
# the same run, the floor of the machine for the same stream: `cat > FILE`
# (the bytes moved from the pipe to a file, nothing parsed, nothing synced).
#   bench/record_throughput.sh [path/to/cubecal] [seconds] [runs]
set -euo pipefail
BIN=${1:-build/bin/cubecal}
SECONDS_PER_RUN=${2:-20}
RUNS=${3:-3}
exec /usr/bin/python3 - "$BIN" "$SECONDS_PER_RUN" "$RUNS" <<'PY'
import os, resource, shutil, statistics, subprocess, sys, tempfile, time
binary, seconds, runs = sys.argv[1], float(sys.argv[2]), int(sys.argv[3])
RATE, CH, BATCH = 10000, 10, 100  # lines per second, channels, lines per write (10 ms)
# A pre-rendered block of lines (values of realistic width), sent in 10 ms slices.
import random
rng = random.Random(1)
rows = []
for i in range(RATE):
    rows.append(",".join("%.6e" % rng.gauss(0, 1e-3) for _ in range(CH)) + "\n")
# No device time column (the host stamps place the samples): a repeated
# block would otherwise read as a time reset every second.
header = ",".join("g%d" % k for k in range(CH)).encode() + b"\n"
slices = ["".join(rows[j:j + BATCH]).encode() for j in range(0, RATE, BATCH)]
fractions, floors = [], []
for run in range(2 * runs):
    recorder = run % 2 == 0  # alternate: recorder, cat, recorder, ...
    d = tempfile.mkdtemp(prefix="cubecal_record_bench_")
    out = os.path.join(d, "rec")
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    if recorder:
        p = subprocess.Popen([binary, "record", "-", "--out", out], stdin=subprocess.PIPE, stderr=subprocess.PIPE)
    else:
        p = subprocess.Popen(["sh", "-c", 'exec cat > "$0"', out], stdin=subprocess.PIPE, stderr=subprocess.PIPE)
    t0 = time.monotonic()
    p.stdin.write(header)
    sent = 0
    k = 0
    while True:
        now = time.monotonic() - t0
        if now >= seconds:
            break
        due = int(now * RATE / BATCH)
        while k < due:
            p.stdin.write(slices[k % len(slices)])
            sent += BATCH
            k += 1
        p.stdin.flush()
        time.sleep(0.005)
    p.stdin.close()
    err = p.stderr.read().decode()
    p.wait()
    wall = time.monotonic() - t0
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    cpu = (after.ru_utime - before.ru_utime) + (after.ru_stime - before.ru_stime)
    user = after.ru_utime - before.ru_utime
    frac = cpu / wall
    (fractions if recorder else floors).append(frac)
    print("run %d (%s): %d lines (%.0f lines/s, %.2f MB/s) in %.2f s wall, CPU %.3f s (user %.3f, sys %.3f): %.2f %% of a core"
          % (run // 2 + 1, "cubecal record" if recorder else "cat > file", sent, sent / wall,
             sent * len(rows[1]) / wall / 1e6, wall, cpu, user, cpu - user, 100 * frac))
    if recorder:
        print("   ", err.strip().splitlines()[-1] if err.strip() else "(no summary)")
    shutil.rmtree(d)
print("recorder CPU / wall: min %.2f %%, median %.2f %%, max %.2f %% of a core (target < 5 %%)"
      % (100 * min(fractions), 100 * statistics.median(fractions), 100 * max(fractions)))
print("cat > file CPU / wall: min %.2f %%, median %.2f %%, max %.2f %%; recorder / cat (medians): %.1f"
      % (100 * min(floors), 100 * statistics.median(floors), 100 * max(floors),
         statistics.median(fractions) / max(statistics.median(floors), 1e-9)))
PY
