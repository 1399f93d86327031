"""Draws the 2D known-answer scenes of `rigidref validate` (docs/validation.md §"2D"):
block_slide.png (a 4x2 block on a pinned ground row, pushed along it), bar_topple.png (a 2x8 bar
standing on the ground, pushed at its top) and stack_rest.png (three 4x2 blocks stacked on the
ground). One pixel per block, blue is pinned; each body starts one blank row above what it rests
on (so that no two bodies touch as pixels) and falls 0.586 blocks onto it before the push.
Run from the project root: python3 scenes/blocks/draw_validation_scenes.py"""
import json
import struct
import zlib


def png(path, w, h, pix):
    raw = b''.join(b'\x00' + b''.join(bytes(pix.get((x, y), (255, 255, 255))) for x in range(w)) for y in range(h))

    def chunk(t, d):
        return struct.pack('>I', len(d)) + t + d + struct.pack('>I', zlib.crc32(t + d) & 0xffffffff)
    open(path, 'wb').write(b'\x89PNG\r\n\x1a\n' + chunk(b'IHDR', struct.pack('>IIBBBBB', w, h, 8, 2, 0, 0, 0))
                           + chunk(b'IDAT', zlib.compress(raw, 9)) + chunk(b'IEND', b''))


def scene(name, pix, w, h, impulses):
    png(f'scenes/blocks/{name}.png', w, h, pix)
    with open(f'scenes/blocks/{name}.json', 'w') as f:
        json.dump({"image": f"{name}.png", "impulses": impulses}, f, indent=4)
        f.write("\n")


BLUE = (0, 0, 163)
BLACK = (0, 0, 0)
# block_slide: ground row 10 (40 blocks), a 4x2 block (mass 8) at columns 2..5, rows 7..8; it
# settles, then at t = 5 an impulse of 8 along +x gives it v0 = 1.
pix = {(x, 10): BLUE for x in range(40)}
pix.update({(x, y): BLACK for x in range(2, 6) for y in (7, 8)})
scene('block_slide', pix, 40, 11, [{"time": 5, "body": 0, "impulse": [8, 0]}])
# bar_topple: ground row 14 (30 blocks), a 2x8 bar (mass 16) at columns 10..11, rows 4..11; it
# settles, then at t = 3 an impulse of 4 along +x at its top block row topples it.
pix = {(x, 14): BLUE for x in range(30)}
pix.update({(x, y): BLACK for x in (10, 11) for y in range(4, 12)})
scene('bar_topple', pix, 30, 15, [{"time": 3, "body": 0, "impulse": [4, 0], "point": [10.5, 4]}])
# stack_rest: ground row 14 (20 blocks), three 4x2 blocks at columns 8..11, rows 11..12, 8..9
# and 5..6.
pix = {(x, 14): BLUE for x in range(20)}
pix.update({(x, y): BLACK for x in range(8, 12) for y in (5, 6, 8, 9, 11, 12)})
scene('stack_rest', pix, 20, 15, [])
