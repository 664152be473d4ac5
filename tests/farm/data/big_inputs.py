#!/usr/bin/env python3
"""Small files that decode to large inputs, for the tests and benchmarks of huge loads.

    big_inputs.py hdr W H FILE.hdr [SCENE.json]   a Radiance .hdr of W x H texels of one colour,
        run-length encoded (about 2 MB at 8192 x 4096; flat pixels where RLE cannot be used:
        W < 8 or W >= 32768); with SCENE.json, a scene of one sphere lit by it
    big_inputs.py png-bomb SIDE FILE.png GLTF      a grey PNG declaring SIDE x SIDE, all zero (about
        a quarter of a megabyte at 16384), and BoxTextured as GLTF wearing it (its .bin is
        expected beside GLTF)
"""
import json
import os
import struct
import sys
import zlib


def hdr(w, h, out, scene=None):
    def runs(value, n):
        b = b''
        while n:
            k = min(127, n)
            b += bytes([128 + k, value])
            n -= k
        return b
    head = b'#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n\n-Y %d +X %d\n' % (h, w)
    if 8 <= w < 32768:
        line = bytes([2, 2, w >> 8, w & 255]) + runs(128, w) + runs(100, w) + runs(80, w) + runs(129, w)
        body = line * h
    else:
        body = bytes([128, 100, 80, 129]) * (w * h)
    with open(out, 'wb') as f:
        f.write(head + body)
    if scene:
        json.dump({"camera": {"eye": [0, 0, 5], "target": [0, 0, 0]},
                   "environment": {"file": os.path.relpath(out, os.path.dirname(scene) or '.')},
                   "objects": [{"type": "sphere", "center": [0, 0, 0], "radius": 1}]}, open(scene, 'w'))


def png_bomb(side, out, gltf):
    def chunk(kind, data):
        return struct.pack('>I', len(data)) + kind + data + struct.pack('>I', zlib.crc32(kind + data) & 0xffffffff)
    z = zlib.compressobj(9)
    row = bytes(1 + side)  # filter byte 0, then SIDE zero grey samples
    idat = b''.join(z.compress(row) for _ in range(side)) + z.flush()
    png = (b'\x89PNG\r\n\x1a\n' + chunk(b'IHDR', struct.pack('>IIBBBBB', side, side, 8, 0, 0, 0, 0)) +
           chunk(b'IDAT', idat) + chunk(b'IEND', b''))
    with open(out, 'wb') as f:
        f.write(png)
    g = json.load(open('/usr/share/assimp/models/glTF2/BoxTextured-glTF/BoxTextured.gltf'))
    g['images'] = [{'uri': os.path.relpath(out, os.path.dirname(gltf) or '.')}]
    json.dump(g, open(gltf, 'w'))


if __name__ == '__main__':
    if len(sys.argv) >= 5 and sys.argv[1] == 'hdr':
        hdr(int(sys.argv[2]), int(sys.argv[3]), sys.argv[4], sys.argv[5] if len(sys.argv) > 5 else None)
    elif len(sys.argv) == 5 and sys.argv[1] == 'png-bomb':
        png_bomb(int(sys.argv[2]), sys.argv[3], sys.argv[4])
    else:
        sys.exit(__doc__)
