#!/usr/bin/env python3
"""Writes the bad checkpoints of the bad-input corpus (CASE/checkpoint.bin next to this
script), each derived from a checkpoint of the fuzz seed corpus: the payload of a small
ed-naive run (tests/fuzz/corpus/fuzz_checkpoint_sections/edn.payload) and the fuzzer's
finding nan_largest_radius.payload. The file layout is docs/checkpoints.md's (magic,
format, byte order, payload size, payload, CRC-32 of the payload). Run it again after a
change of the checkpoint format, and commit what it writes."""
import pathlib
import struct
import zlib

HERE = pathlib.Path(__file__).resolve().parent
SEEDS = HERE.parent.parent / "fuzz" / "corpus" / "fuzz_checkpoint_sections"
MAGIC = b"BALLAGG CHECKPT\n"
FORMAT = 2
BYTE_ORDER = 0x01020304


def wrap(payload, version=FORMAT, order=BYTE_ORDER, size=None):
    size = len(payload) if size is None else size
    header = MAGIC + struct.pack("<IIQ", version, order, size)
    return header + payload + struct.pack("<I", zlib.crc32(payload))


def fields(payload):
    """The payload as [program version, dimension, engine, configuration, wall seconds,
    totals, state, engine state, timeseries, snapshots]."""
    out, at = [], 0

    def string():
        nonlocal at
        (n,) = struct.unpack_from("<Q", payload, at)
        at += 8 + n
        return payload[at - n:at]

    out.append(string())
    out.append(struct.unpack_from("<i", payload, at)[0])
    at += 4
    out += [string(), string()]
    out.append(struct.unpack_from("<d", payload, at)[0])
    at += 8
    out += [string() for _ in range(5)]
    assert at == len(payload)
    return out


def payload_of(f):
    def string(s):
        return struct.pack("<Q", len(s)) + s

    return (string(f[0]) + struct.pack("<i", f[1]) + string(f[2]) + string(f[3]) + struct.pack("<d", f[4])
            + b"".join(string(s) for s in f[5:]))


def replaced(f, index, value):
    g = list(f)
    g[index] = value
    return payload_of(g)


def write(case, data):
    d = HERE / case
    d.mkdir(exist_ok=True)
    (d / "checkpoint.bin").write_bytes(data)


def main():
    edn = (SEEDS / "edn.payload").read_bytes()
    f = fields(edn)
    assert payload_of(f) == edn
    good = wrap(edn)
    config = f[3].decode()
    write("not_a_checkpoint", b"[system]\nn = 3\n")
    write("empty", b"")
    write("header_only", good[:32])
    write("truncated", good[:len(good) // 2])
    flipped = bytearray(good)
    flipped[len(good) // 2] ^= 0x10
    write("flipped_bit", bytes(flipped))
    write("format_zero", wrap(edn, version=0))
    write("format_older", wrap(edn, version=FORMAT - 1))  # as the ballagg before the current format wrote it
    write("other_byte_order", wrap(edn, order=0x04030201))
    write("longer_than_its_header", good + b"\0" * 8)
    write("dimension_four", wrap(replaced(f, 1, 4)))
    write("dimension_of_another_configuration", wrap(replaced(f, 1, 3)))
    write("engine_of_another_configuration", wrap(replaced(f, 2, b"ts")))
    write("configuration_with_a_bad_value",
          wrap(replaced(f, 3, config.replace("\nn = ", "\nn = 0\n# was n = ", 1).encode())))
    write("state_cut_short", wrap(replaced(f, 6, f[6][:len(f[6]) // 2])))
    write("engine_state_of_another_run", wrap(replaced(f, 7, f[7][:-8])))
    write("nan_largest_radius", wrap((SEEDS / "nan_largest_radius.payload").read_bytes()))


if __name__ == "__main__":
    main()
