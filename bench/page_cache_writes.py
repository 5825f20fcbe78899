#!/usr/bin/python3
"""Cost of writing a trajectory's worth of data through the page cache, with and without
dropping the written pages (docs/performance.md, "Snapshots at N = 10^6").

Writes 110 blocks of 34 MB (a 2D frame of 10^6 spheres in doubles) to a file in DIR and
prints the wall and system time: `plain` leaves the pages in the page cache, `drop` calls
fdatasync and POSIX_FADV_DONTNEED after each block, as the H5MD writer does every 32 MB.
Usage: bench/page_cache_writes.py plain|drop [DIR]   (standard library only; ~3.9 GB on disk)
"""
import os
import sys
import time


def main():
    mode = sys.argv[1]
    path = os.path.join(sys.argv[2] if len(sys.argv) > 2 else "/tmp", "page_cache_writes.bin")
    block = b"\1" * (34 << 20)
    t0, c0 = time.monotonic(), os.times()
    fd = os.open(path, os.O_WRONLY | os.O_CREAT | os.O_TRUNC)
    offset = 0
    try:
        for _ in range(110):
            os.pwrite(fd, block, offset)
            offset += len(block)
            if mode == "drop":
                os.fdatasync(fd)
                os.posix_fadvise(fd, 0, 0, os.POSIX_FADV_DONTNEED)
    finally:
        os.close(fd)
        c1 = os.times()
        os.unlink(path)
    print(f"{mode}: {time.monotonic() - t0:.2f} s wall, {c1.system - c0.system:.2f} s system, {offset / 1e9:.2f} GB")


if __name__ == "__main__":
    main()
