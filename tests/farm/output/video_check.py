#!/usr/bin/env python3
"""Decodes a video with FFmpeg's own tools and compares it with the PNG frames it was made from.

video_check.py VIDEO FRAMES_DIR FIRST WxH [--decoder NAME] [--over R,G,B] [--at X,Y ...]
prints one line: "frames N min_psnr P" followed by "alpha@X,Y=A" for each --at point (frame 0).
PSNR is over premultiplied RGB and alpha (straight RGB of a transparent pixel means nothing),
8-bit, per frame; the minimum over frames is printed. --over: the video has no alpha, and the
PNG frames are laid over that sRGB colour (as the encoder did) before comparing."""
import math
import os
import subprocess
import sys


def raw_rgba(args):
    return subprocess.run(["ffmpeg", "-v", "error"] + args + ["-f", "rawvideo", "-pix_fmt", "rgba", "-"],
                          check=True, stdout=subprocess.PIPE).stdout


def premultiplied(frame):
    out = bytearray(len(frame))
    for i in range(0, len(frame), 4):
        a = frame[i + 3]
        out[i] = (frame[i] * a + 127) // 255
        out[i + 1] = (frame[i + 1] * a + 127) // 255
        out[i + 2] = (frame[i + 2] * a + 127) // 255
        out[i + 3] = a
    return out


def flattened(frame, over):
    out = bytearray(len(frame))
    for i in range(0, len(frame), 4):
        a = frame[i + 3]
        for c in range(3):
            out[i + c] = (frame[i + c] * a + over[c] * (255 - a) + 127) // 255
        out[i + 3] = 255
    return out


def psnr(a, b):
    se = sum((x - y) * (x - y) for x, y in zip(a, b))
    return 1e9 if se == 0 else 10 * math.log10(255.0 * 255.0 * len(a) / se)


def main():
    video, frames_dir, first, size = sys.argv[1:5]
    w, h = (int(v) for v in size.split("x"))
    rest = sys.argv[5:]
    decoder, points, over = [], [], None
    while rest:
        opt, val = rest[0], rest[1]
        rest = rest[2:]
        if opt == "--decoder":
            decoder = ["-c:v", val]
        elif opt == "--over":
            over = [int(v) for v in val.split(",")]
        elif opt == "--at":
            points.append(tuple(int(v) for v in val.split(",")))
    data = raw_rgba(decoder + ["-i", video, "-vf", "crop=%d:%d:0:0" % (w, h)])
    n = len(data) // (w * h * 4)
    worst = 1e9
    for k in range(n):
        png = os.path.join(frames_dir, "frame_%06d.png" % (int(first) + k))
        ref = raw_rgba(["-i", png])
        if over:
            ref = flattened(ref, over)
        got = data[k * w * h * 4:(k + 1) * w * h * 4]
        worst = min(worst, psnr(premultiplied(got), premultiplied(ref)))
    line = "frames %d min_psnr %.2f" % (n, worst)
    for x, y in points:
        line += " alpha@%d,%d=%d" % (x, y, data[4 * (y * w + x) + 3])
    print(line)


main()
