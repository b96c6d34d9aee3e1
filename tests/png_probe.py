#!/usr/bin/env python3
"""Prints RGB of points of an 8-bit RGBA PNG (as hmdlod writes them), and per half of the image
the number of distinct colours: `png_probe.py FILE X,Y ...` (fractions of width and height)."""
import struct, sys, zlib

def read_rgba(path):
    data = open(path, 'rb').read()
    assert data[:8] == b'\x89PNG\r\n\x1a\n', 'not a PNG'
    pos, idat, w = 8, b'', 0
    while pos < len(data):
        n, kind = struct.unpack('>I4s', data[pos:pos + 8])
        body = data[pos + 8:pos + 8 + n]
        if kind == b'IHDR':
            w, h, depth, colour = struct.unpack('>IIBB', body[:10])
            assert depth == 8 and colour == 6, 'not 8-bit RGBA'
        elif kind == b'IDAT':
            idat += body
        pos += 12 + n
    raw, stride, rows, prev = zlib.decompress(idat), w * 4, [], bytearray(w * 4)
    for y in range(h):
        f, line = raw[y * (stride + 1)], bytearray(raw[y * (stride + 1) + 1:(y + 1) * (stride + 1)])
        for i in range(stride):
            a = line[i - 4] if i >= 4 else 0
            b, c = prev[i], prev[i - 4] if i >= 4 else 0
            if f == 1: line[i] = (line[i] + a) & 255
            elif f == 2: line[i] = (line[i] + b) & 255
            elif f == 3: line[i] = (line[i] + (a + b) // 2) & 255
            elif f == 4:
                p = a + b - c
                pa, pb, pc = abs(p - a), abs(p - b), abs(p - c)
                line[i] = (line[i] + (a if pa <= pb and pa <= pc else b if pb <= pc else c)) & 255
        rows.append(line)
        prev = line
    return w, h, rows

w, h, rows = read_rgba(sys.argv[1])
for arg in sys.argv[2:]:
    fx, fy = (float(v) for v in arg.split(','))
    x, y = min(int(fx * w), w - 1), min(int(fy * h), h - 1)
    print('%s %d %d %d' % (arg, rows[y][4 * x], rows[y][4 * x + 1], rows[y][4 * x + 2]))
for half in range(2):
    colours = {bytes(rows[y][4 * x:4 * x + 3]) for y in range(0, h, 2) for x in range(half * w // 2, (half + 1) * w // 2, 2)}
    print('half%d %d' % (half, len(colours)))
