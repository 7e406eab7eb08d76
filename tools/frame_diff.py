#!/usr/bin/env python3
"""Frame-to-frame difference of image sequences (issue 13 "Coherence", docs/detail.md "Coherence").

Usage: tools/frame_diff.py LABEL=DIR [LABEL=DIR ...]
       tools/frame_diff.py --truth TRUTH.png LABEL=FILE.png [LABEL=FILE.png ...]
The second form prints each image's mean absolute difference (luminance, alpha, as below) from
TRUTH.png, e.g. an in-between frame against the model's own state at that time (tools/motion_blend.sh).
Each DIR holds layer_NNNNNN.png (`nephele animate --layer`: the premultiplied cloud layer). For each
pair of consecutive frames: the mean absolute difference of the luminance (Rec. 709 weights on the
8-bit premultiplied R, G, B) and of the alpha, in 8-bit levels over all pixels; then the mean and
the largest over the pairs. Prints a Markdown table. Then, against the first series (the reference,
e.g. detail none), the change of each other series' own contribution: per pair, the mean of
|(A[k+1] - R[k+1]) - (A[k] - R[k])| — what the detail itself changes from frame to frame (swimming,
boiling), apart from the change of the data underneath. Standard library only (zlib PNG decoder).
"""
import struct
import sys
import zlib
from pathlib import Path


def read_png(path):
    """(width, height, channels, rows of 8-bit values) of a non-interlaced 8/16-bit RGB(A) PNG."""
    data = Path(path).read_bytes()
    if data[:8] != b"\x89PNG\r\n\x1a\n":
        raise SystemExit(f"{path}: not a PNG")
    pos, idat, head = 8, b"", None
    while pos < len(data):
        (length,) = struct.unpack(">I", data[pos:pos + 4])
        kind = data[pos + 4:pos + 8]
        body = data[pos + 8:pos + 8 + length]
        pos += 12 + length
        if kind == b"IHDR":
            head = struct.unpack(">IIBBBBB", body)
        elif kind == b"IDAT":
            idat += body
        elif kind == b"IEND":
            break
    width, height, depth, colour, _, _, interlace = head
    channels = {2: 3, 6: 4, 0: 1, 4: 2}.get(colour)
    if channels is None or depth not in (8, 16) or interlace:
        raise SystemExit(f"{path}: colour type {colour}, depth {depth}, interlace {interlace} not supported")
    bpp = channels * depth // 8
    stride = width * bpp
    raw = zlib.decompress(idat)
    rows, prev = [], bytearray(stride)
    for y in range(height):
        f = raw[y * (stride + 1)]
        line = bytearray(raw[y * (stride + 1) + 1:(y + 1) * (stride + 1)])
        for x in range(stride):
            a = line[x - bpp] if x >= bpp else 0
            b = prev[x]
            c = prev[x - bpp] if x >= bpp else 0
            if f == 1:
                line[x] = (line[x] + a) & 255
            elif f == 2:
                line[x] = (line[x] + b) & 255
            elif f == 3:
                line[x] = (line[x] + ((a + b) >> 1)) & 255
            elif f == 4:
                p = a + b - c
                pa, pb, pc = abs(p - a), abs(p - b), abs(p - c)
                line[x] = (line[x] + (a if pa <= pb and pa <= pc else b if pb <= pc else c)) & 255
        rows.append(bytes(line))
        prev = line
    if depth == 16:  # keep the high bytes: 8-bit levels
        rows = [row[0::2] for row in rows]
    return width, height, channels, rows


def lum_alpha(path):
    w, h, ch, rows = read_png(path)
    lum, alpha = [], []
    for row in rows:
        for x in range(w):
            p = row[x * ch:(x + 1) * ch]
            lum.append(0.2126 * p[0] + 0.7152 * p[1] + 0.0722 * p[2] if ch >= 3 else float(p[0]))
            alpha.append(float(p[3]) if ch == 4 else 255.0)
    return lum, alpha


def mad(a, b):
    return sum(abs(x - y) for x, y in zip(a, b)) / len(a)


def against_truth(truth, args):
    t = lum_alpha(truth)
    print(f"| image | against {Path(truth).name}: luminance / alpha |")
    print("| --- | ---: |")
    for arg in args:
        label, _, path = arg.partition("=")
        a = lum_alpha(path)
        print(f"| {label} | {mad(a[0], t[0]):.3f} / {mad(a[1], t[1]):.3f} |")


def main(args):
    if not args:
        raise SystemExit(__doc__)
    if args[0] == "--truth":
        if len(args) < 3:
            raise SystemExit(__doc__)
        return against_truth(args[1], args[2:])
    series, frames_of = {}, {}
    for arg in args:
        label, _, folder = arg.partition("=")
        frames = sorted(Path(folder).glob("layer_*.png"))
        if len(frames) < 2:
            raise SystemExit(f"{folder}: fewer than 2 layer_*.png frames")
        decoded = [lum_alpha(f) for f in frames]
        frames_of[label] = decoded
        series[label] = [(mad(p[0], q[0]), mad(p[1], q[1])) for p, q in zip(decoded, decoded[1:])]
    labels = list(series)
    pairs = min(len(v) for v in series.values())
    print("| frames | " + " | ".join(f"{l}: luminance / alpha" for l in labels) + " |")
    print("| --- | " + " | ".join("---:" for _ in labels) + " |")
    for i in range(pairs):
        cells = [f"{series[l][i][0]:.3f} / {series[l][i][1]:.3f}" for l in labels]
        print(f"| {i}→{i + 1} | " + " | ".join(cells) + " |")
    for name, agg in (("mean", lambda v: sum(v) / len(v)), ("max", max)):
        cells = []
        for l in labels:
            s = series[l][:pairs]
            cells.append(f"**{agg([p[0] for p in s]):.3f} / {agg([p[1] for p in s]):.3f}**")
        print(f"| {name} | " + " | ".join(cells) + " |")
    ref = labels[0]
    others = labels[1:]
    if not others:
        return
    own = {}
    for l in others:
        a, r = frames_of[l], frames_of[ref]
        rows = []
        for k in range(pairs):
            cells = []
            for c in (0, 1):
                da = [x1 - y1 - (x0 - y0) for x1, y1, x0, y0 in zip(a[k + 1][c], r[k + 1][c], a[k][c], r[k][c])]
                cells.append(sum(abs(v) for v in da) / len(da))
            rows.append(cells)
        own[l] = rows
    print()
    print(f"Change of the contribution against {ref}, |(A[k+1] - {ref}[k+1]) - (A[k] - {ref}[k])|:")
    print()
    print("| frames | " + " | ".join(f"{l}: luminance / alpha" for l in others) + " |")
    print("| --- | " + " | ".join("---:" for _ in others) + " |")
    for k in range(pairs):
        print(f"| {k}→{k + 1} | " + " | ".join(f"{own[l][k][0]:.3f} / {own[l][k][1]:.3f}" for l in others) + " |")
    cells = []
    for l in others:
        cells.append(f"**{sum(r[0] for r in own[l]) / pairs:.3f} / {sum(r[1] for r in own[l]) / pairs:.3f}**")
    print("| mean | " + " | ".join(cells) + " |")


if __name__ == "__main__":
    main(sys.argv[1:])
