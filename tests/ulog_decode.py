#!/usr/bin/python3
# An independent PX4 ULog decoder for test_ulog (struct only, written from
# https://docs.px4.io/main/en/dev_log/ulog_file_format.html, sharing nothing
# with cubecal's reader). Prints, for the log given:
#   topic LABEL COUNT            every topic (LABEL: name, or name:N for instance N > 0)
#   dropouts N MS                the 'O' messages and their total duration
#   first LABEL OFFSET TS V...   the first data message of sensor_combined (gyro_rad[3],
#                                accelerometer_m_s2[3]) and vehicle_magnetometer (magnetometer_ga[3]):
#                                its byte offset, timestamp (us) and values (repr of the float32)
#   nth LABEL K TS V...          the same for message K (1-based) = count // 2
#   median_dt LABEL US           the median timestamp interval
#   second LABEL OFFSET          the byte offset of the second data message
import struct, sys

BASIC = {'int8_t': 'b', 'uint8_t': 'B', 'bool': '?', 'char': 'c', 'int16_t': 'h', 'uint16_t': 'H',
         'int32_t': 'i', 'uint32_t': 'I', 'float': 'f', 'int64_t': 'q', 'uint64_t': 'Q', 'double': 'd'}

b = open(sys.argv[1], 'rb').read()
assert b[:7] == b'ULog\x01\x12\x35'
formats, subs, msgs, labels, order = {}, {}, {}, {}, []
drop = []
p = 16
while p < len(b):
    size, typ = struct.unpack_from('<HB', b, p)
    body = b[p + 3:p + 3 + size]
    assert len(body) == size
    typ = chr(typ)
    if typ == 'F':
        name, fields = body.decode().split(':', 1)
        formats[name] = [f.split(' ') for f in fields.split(';') if f]
    elif typ == 'A':
        multi, msg_id = struct.unpack_from('<BH', body)
        name = body[3:].decode()
        label = name if multi == 0 else '%s:%d' % (name, multi)
        subs[msg_id] = label
        labels[label] = name
        if label not in msgs:
            msgs[label] = []
            order.append(label)
    elif typ == 'D':
        msg_id, = struct.unpack_from('<H', body)
        msgs[subs[msg_id]].append((p, body[2:]))
    elif typ == 'O':
        drop.append(struct.unpack_from('<H', body)[0])
    p += 3 + size

def size_of(t):
    n = 1
    if '[' in t:
        t, n = t[:-1].split('[')
        n = int(n)
    return n * (struct.calcsize('<' + BASIC[t]) if t in BASIC else sum(size_of(ft) for ft, _ in formats[t]))

def field(name, data, fname):
    off = 0
    for ft, fn in formats[name]:
        if fn == fname:
            t, n = (ft[:-1].split('[') + ['1'])[:2] if '[' in ft else (ft, '1')
            return list(struct.unpack_from('<%d%s' % (int(n), BASIC[t]), data, off))
        off += size_of(ft)
    raise KeyError(fname)

for label in order:
    print('topic', label, len(msgs[label]))
print('dropouts', len(drop), sum(drop))
WANT = {'sensor_combined': ['gyro_rad', 'accelerometer_m_s2'], 'vehicle_magnetometer': ['magnetometer_ga']}
for label, fields in WANT.items():
    if label not in msgs:
        continue
    m = msgs[label]
    for tag, k in (('first', 0), ('nth', len(m) // 2 - 1)):
        off, data = m[k]
        vals = [repr(v) for f in fields for v in field(label, data, f)]
        where = str(off) if tag == 'first' else str(k + 1)
        print(tag, label, where, field(label, data, 'timestamp')[0], ' '.join(vals))
    ts = [field(label, d, 'timestamp')[0] for _, d in m]
    dt = sorted(y - x for x, y in zip(ts, ts[1:]))
    print('median_dt', label, dt[len(dt) // 2])
    print('second', label, m[1][0])
