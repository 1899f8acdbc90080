#!/usr/bin/env python3
"""Unpacks the ELF vmlinux from a bzImage (like the kernel's scripts/extract-vmlinux): qemu boots it directly via
PVH, which is 2-3x faster under TCG than letting the bzImage decompress itself."""
import gzip, lzma, subprocess, sys

src, dst = sys.argv[1], sys.argv[2]
data = open(src, "rb").read()
candidates = [(b"\xfd7zXZ\x00", lambda b: lzma.LZMADecompressor().decompress(b)),
              (b"\x1f\x8b\x08", lambda b: gzip.decompress(b)),
              (b"\x28\xb5\x2f\xfd", lambda b: subprocess.run(["zstd", "-dc"], input=b, capture_output=True).stdout)]
for magic, unpack in candidates:
    pos = data.find(magic)
    while pos >= 0:
        try:
            out = unpack(data[pos:])
        except Exception:
            out = b""
        if out[:4] == b"\x7fELF":
            open(dst, "wb").write(out)
            sys.exit(0)
        pos = data.find(magic, pos + 1)
sys.exit("extract-vmlinux: no ELF payload found in " + src)
