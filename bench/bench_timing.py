"""Timing helpers of the Python benchmarks (python_speed.py, psd_speed.py):
each call run several times, the seconds sorted, shown as min / median / max."""
import time


def timed(call, runs):
    """(sorted seconds of `runs` calls, the last call's result)."""
    seconds, out = [], None
    for _ in range(runs):
        t0 = time.perf_counter()
        out = call()
        seconds.append(time.perf_counter() - t0)
    seconds.sort()
    return seconds, out


def span(s):
    return f"{s[0]:.4f} / {s[len(s) // 2]:.4f} / {s[-1]:.4f} s"


def median(s):
    return s[len(s) // 2]
