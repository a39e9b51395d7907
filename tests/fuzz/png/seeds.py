#!/usr/bin/env python3
# seeds.py: writes the PNG harness's seed corpus (tests/fuzz/png/corpus/):
# one small image for every colour type and bit depth PNG has, plain and
# Adam7-interlaced, with tRNS, gAMA, sRGB, iCCP and an ancillary chunk libpng
# does not know. Run from the repository's top; the files are committed, so
# this only needs running to change them. PNG written by hand (zlib, struct):
# no imaging library needed.
import os
import struct
import zlib

OUT = "tests/fuzz/png/corpus"
W, H = 5, 3                      # odd sizes: partial bytes at depths < 8


def chunk(kind, data):
    body = kind + data
    return struct.pack(">I", len(data)) + body + struct.pack(">I", zlib.crc32(body))


def samples(ctype):
    return {0: 1, 2: 3, 3: 1, 4: 2, 6: 4}[ctype]


def row_bytes(width, ctype, depth):
    return (width * samples(ctype) * depth + 7) // 8


def pixel_row(y, width, ctype, depth):
    """A row of varied samples packed at depth, filter byte first."""
    n = width * samples(ctype)
    top = (1 << depth) - 1
    vals = [((x * 7 + y * 13 + 3) * 37) % (top + 1) for x in range(n)]
    if ctype == 3:
        vals = [v % 4 for v in vals]         # palette of 4 entries
    if depth == 16:
        raw = b"".join(struct.pack(">H", v) for v in vals)
    elif depth == 8:
        raw = bytes(vals)
    else:
        bits, acc, nbits = [], 0, 0
        for v in vals:
            acc = (acc << depth) | v
            nbits += depth
            if nbits == 8:
                bits.append(acc)
                acc, nbits = 0, 0
        if nbits:
            bits.append(acc << (8 - nbits))
        raw = bytes(bits)
    return raw


ADAM7 = [(0, 0, 8, 8), (4, 0, 8, 8), (0, 4, 4, 8), (2, 0, 4, 4), (0, 2, 2, 4),
         (1, 0, 2, 2), (0, 1, 1, 2)]


def image_data(width, height, ctype, depth, interlace, filt):
    out = bytearray()
    if not interlace:
        passes = [(0, 0, 1, 1)]
    else:
        passes = ADAM7
    for x0, y0, dx, dy in passes:
        pw = len(range(x0, width, dx))
        ph = len(range(y0, height, dy))
        if pw == 0 or ph == 0:
            continue
        for y in range(ph):
            out.append(filt)
            raw = pixel_row(y0 + y * dy, pw, ctype, depth)
            if filt == 1:                    # Sub, over whole bytes
                bpp = max(1, samples(ctype) * depth // 8)
                raw = bytes((raw[i] - (raw[i - bpp] if i >= bpp else 0)) & 255
                            for i in range(len(raw)))
            out += raw
    return bytes(out)


def png(ctype, depth, interlace=0, extra=(), filt=0, width=W, height=H):
    ihdr = struct.pack(">IIBBBBB", width, height, depth, ctype, 0, 0, interlace)
    parts = [b"\x89PNG\r\n\x1a\n", chunk(b"IHDR", ihdr)]
    for kind, data in extra:
        if kind != b"tRNS":
            parts.append(chunk(kind, data))
    if ctype == 3:
        parts.append(chunk(b"PLTE", bytes([0, 0, 0, 255, 0, 0, 0, 255, 0, 20, 40, 255])))
    for kind, data in extra:
        if kind == b"tRNS":
            parts.append(chunk(kind, data))
    idat = zlib.compress(image_data(width, height, ctype, depth, interlace, filt), 9)
    parts.append(chunk(b"IDAT", idat))
    parts.append(chunk(b"IEND", b""))
    return b"".join(parts)


def main():
    os.makedirs(OUT, exist_ok=True)
    files = {}
    for ctype, depths in [(0, [1, 2, 4, 8, 16]), (2, [8, 16]), (3, [1, 2, 4, 8]),
                          (4, [8, 16]), (6, [8, 16])]:
        for d in depths:
            files[f"c{ctype}_d{d}.png"] = png(ctype, d)
    for ctype, d in [(0, 1), (0, 16), (2, 8), (3, 2), (6, 16)]:
        files[f"c{ctype}_d{d}_adam7.png"] = png(ctype, d, interlace=1)
    gama = (b"gAMA", struct.pack(">I", 100000))
    srgb = (b"sRGB", b"\x00")
    iccp = (b"iCCP", b"fake\x00\x00" + zlib.compress(b"\x00" * 132))
    files["c0_d8_trns.png"] = png(0, 8, extra=[(b"tRNS", struct.pack(">H", 3))])
    files["c2_d16_trns.png"] = png(2, 16, extra=[(b"tRNS", struct.pack(">HHH", 1, 2, 3))])
    files["c3_d4_trns.png"] = png(3, 4, extra=[(b"tRNS", b"\x00\x80")])
    files["c2_d8_gama_srgb.png"] = png(2, 8, extra=[gama, srgb])
    files["c6_d8_iccp.png"] = png(6, 8, extra=[iccp])
    files["c2_d8_unknown_chunk.png"] = png(2, 8, extra=[(b"zzZz", b"anything")], filt=1)
    files["c0_d8_1x1.png"] = png(0, 8, width=1, height=1)
    for name, data in sorted(files.items()):
        with open(os.path.join(OUT, name), "wb") as f:
            f.write(data)


if __name__ == "__main__":
    main()
