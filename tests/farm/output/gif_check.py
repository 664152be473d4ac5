#!/usr/bin/env python3
"""Reads a GIF's structure (GIF89a spec): the first colour table and the NETSCAPE2.0 loop count.

gif_check.py FILE prints "colours N distinct D fixed F loop L", where F is "yes" if the table is
one of the fixed palettes a GIF writer falls back on (3-3-2 RGB, the 6x6x6 web-safe cube, grey
ramp) and L is the loop count (0: for ever; "none" without the extension)."""
import sys


def table(data, pos, flags):
    n = 2 << (flags & 7)
    return [tuple(data[pos + 3 * i:pos + 3 * i + 3]) for i in range(n)], pos + 3 * n


def first_table(data):
    pos = 13
    if data[10] & 0x80:
        return table(data, pos, data[10])[0]
    while pos < len(data):  # the first image's local table
        if data[pos] == 0x21:
            pos += 2
            while data[pos]:
                pos += data[pos] + 1
            pos += 1
        elif data[pos] == 0x2C:
            return table(data, pos + 10, data[pos + 9])[0] if data[pos + 9] & 0x80 else []
        else:
            break
    return []


def fixed(colours):
    s = set(colours)
    rgb332 = {(r * 255 // 7, g * 255 // 7, b * 255 // 3) for r in range(8) for g in range(8) for b in range(4)}
    rgb332 |= {(r * 36, g * 36, b * 85) for r in range(8) for g in range(8) for b in range(4)}  # FFmpeg's rgb8
    web = {(r * 51, g * 51, b * 51) for r in range(6) for g in range(6) for b in range(6)}
    grey = {(v, v, v) for v in range(256)}
    return s <= rgb332 or s <= web or s <= grey


def main():
    data = open(sys.argv[1], "rb").read()
    if data[:6] not in (b"GIF87a", b"GIF89a"):
        sys.exit("not a GIF")
    colours = first_table(data)
    i = data.find(b"NETSCAPE2.0")
    loop = "none" if i < 0 else str(data[i + 13] | data[i + 14] << 8)
    print("colours %d distinct %d fixed %s loop %s" % (len(colours), len(set(colours)), "yes" if fixed(colours) else "no", loop))


main()
