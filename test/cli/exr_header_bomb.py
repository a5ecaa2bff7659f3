#!/usr/bin/env python3
"""exr_header_bomb.py OUT.exr [W H COMPRESSION SIZE]: a small OpenEXR file whose header declares
a huge image (issue 21: a 49 KB DWAB file declaring 16384 x 8192 cost `info` 13.6 s and 3.16 GB).

The header is valid (R, G, B half channels, the data window W x H, a line-offset table that fits
in the file); the chunks are filler, since a loader that bounds its work from the header refuses
the file before it decodes any. COMPRESSION is the OpenEXR code (9: DWAB, 3: ZIP); SIZE the file
size in bytes (default 49152)."""
import struct
import sys

LINES_PER_CHUNK = {0: 1, 1: 1, 2: 1, 3: 16, 4: 32, 5: 16, 6: 32, 7: 32, 8: 32, 9: 256}


def attr(name, type_name, data):
    return name.encode() + b"\0" + type_name.encode() + b"\0" + struct.pack("<i", len(data)) + data


def main():
    out = sys.argv[1]
    w = int(sys.argv[2]) if len(sys.argv) > 2 else 16384
    h = int(sys.argv[3]) if len(sys.argv) > 3 else 8192
    comp = int(sys.argv[4]) if len(sys.argv) > 4 else 9
    size = int(sys.argv[5]) if len(sys.argv) > 5 else 49152
    chl = b""
    for c in "BGR":  # sorted by name, as OpenEXR stores them
        chl += c.encode() + b"\0" + struct.pack("<iB3xii", 1, 0, 1, 1)  # half, linear, 1 x 1
    chl += b"\0"
    box = struct.pack("<iiii", 0, 0, w - 1, h - 1)
    hdr = b"\x76\x2f\x31\x01" + struct.pack("<I", 2)
    hdr += attr("channels", "chlist", chl)
    hdr += attr("compression", "compression", bytes([comp]))
    hdr += attr("dataWindow", "box2i", box)
    hdr += attr("displayWindow", "box2i", box)
    hdr += attr("lineOrder", "lineOrder", b"\0")
    hdr += attr("pixelAspectRatio", "float", struct.pack("<f", 1.0))
    hdr += attr("screenWindowCenter", "v2f", struct.pack("<ff", 0.0, 0.0))
    hdr += attr("screenWindowWidth", "float", struct.pack("<f", 1.0))
    hdr += b"\0"
    lpc = LINES_PER_CHUNK.get(comp, 1)
    nchunks = (h + lpc - 1) // lpc
    table_end = len(hdr) + 8 * nchunks
    room = size - table_end
    per = max(9, room // nchunks)  # y (4), size (4), at least one byte of data
    offsets, chunks = [], b""
    for i in range(nchunks):
        offsets.append(table_end + len(chunks))
        data = b"\0" * (per - 8)
        chunks += struct.pack("<ii", i * lpc, len(data)) + data
    body = hdr + b"".join(struct.pack("<Q", o) for o in offsets) + chunks
    with open(out, "wb") as f:
        f.write(body)


if __name__ == "__main__":
    main()
