#!/usr/bin/python3
"""bench/serial_profile.py on a made-up `perf script` text whose answer is known.

Two threads sampled every 2 ms for 0.2 s: the main thread (the lower id) is in `first` for
the first 0.1 s and in `second` for the next; the worker runs ballagg code for the first
0.1 s and only spins in libgomp after. The main thread's samples alone are then the 50 of
`second`: 0.10 s of 0.20 s (50 %), and `first` is not among them. Exit status 0 when the
script's output says so.
"""
import os
import subprocess
import sys
import tempfile

SCRIPT = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "bench", "serial_profile.py")


def sample(tid, time, symbol, dso):
    return (f"ballagg {tid} {time:.6f}:    2004008 cpu-clock:ppp: \n"
            f"\t            1234 {symbol}+0x10 ({dso})\n"
            f"\t            5678 main+0x20 (/usr/bin/ballagg)\n\n")


def main():
    lines = []
    for k in range(100):
        t = 1000.0 + 0.001 + 0.002 * k
        first_half = k < 50
        lines.append(sample(100, t, "first" if first_half else "second", "/usr/bin/ballagg"))
        lines.append(sample(101, t, "work" if first_half else "gomp_spin",
                            "/usr/bin/ballagg" if first_half else "/usr/lib/x86_64-linux-gnu/libgomp.so.1.0.0"))
    with tempfile.NamedTemporaryFile("w", suffix=".txt", delete=False) as f:
        f.write("".join(lines))
    try:
        out = subprocess.run([sys.executable, SCRIPT, f.name, "--frequency", "500"], check=True,
                             capture_output=True, text=True).stdout
    finally:
        os.unlink(f.name)
    ok = "main thread: 0.2 s, alone: 0.1 s (50%)" in out and "0.10 s  second" in out and "first" not in out
    print(out, end="")
    print("serial_profile: ok" if ok else "serial_profile: unexpected output")
    return 0 if ok else 1


if __name__ == "__main__":
    sys.exit(main())
