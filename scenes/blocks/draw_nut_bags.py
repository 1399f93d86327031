"""Draws the project's nut bags for the nut-bag challenge (docs/blocks2d.md §"Shaking the nut
bag"): one pixel per block, the bag blue (pinned), every nut the same brass colour (so a nut's
mass is its block count), hexagonal nuts placed at random (seeded) without touching, the large ones low in the bag
(the bottom 40 %; 60 % in the fuller bag, where they need the room).

- nut_bag_few_large.png: 12 large nuts (circumradius 12 blocks) among 48 small ones (5 blocks),
  the large ones the heaviest fifth; the pile fills about a third of the bag.
- nut_bag_full.png: 24 large and 96 small in a bag 340 blocks high, the large ones again the
  heaviest fifth; the pile fills about half the bag.

Run from the project root: python3 scenes/blocks/draw_nut_bags.py (the PNGs are committed)."""
import math, random, struct, zlib

BLUE = (0, 0, 163)
BRASS = (200, 160, 60)


def png(path, w, h, pix):
    raw = b"".join(
        b"\x00" + b"".join(bytes(pix.get((x, y), (255, 255, 255))) for x in range(w))
        for y in range(h)
    )

    def chunk(t, d):
        return struct.pack(">I", len(d)) + t + d + struct.pack(">I", zlib.crc32(t + d) & 0xFFFFFFFF)

    open(path, "wb").write(
        b"\x89PNG\r\n\x1a\n"
        + chunk(b"IHDR", struct.pack(">IIBBBBB", w, h, 8, 2, 0, 0, 0))
        + chunk(b"IDAT", zlib.compress(raw, 9))
        + chunk(b"IEND", b"")
    )


def hexagon(cx, cy, r, turn):
    """The pixels whose centres lie inside a regular hexagon of circumradius r."""
    corners = [
        (cx + r * math.cos(turn + k * math.pi / 3), cy + r * math.sin(turn + k * math.pi / 3))
        for k in range(6)
    ]
    out = []
    for y in range(int(cy - r) - 1, int(cy + r) + 2):
        for x in range(int(cx - r) - 1, int(cx + r) + 2):
            px, py = x + 0.5, y + 0.5
            inside = all(
                (bx - ax) * (py - ay) - (by - ay) * (px - ax) >= 0
                for (ax, ay), (bx, by) in zip(corners, corners[1:] + corners[:1])
            )
            if inside:
                out.append((x, y))
    # A corner pixel joined to the rest only diagonally would be a nut of its own: dropped.
    body = set(out)
    return [
        (x, y)
        for x, y in out
        if any(q in body for q in ((x + 1, y), (x - 1, y), (x, y + 1), (x, y - 1)))
    ]


def bag(path, large, small, seed, w=160, h=260, wall=3, low=0.4):
    """Draws a bag of `large` and `small` nuts; fails rather than loop when they do not fit."""
    rng = random.Random(seed)
    pix = {}
    for x in range(w):
        for t in range(wall):
            pix[(x, t)] = BLUE
            pix[(x, h - 1 - t)] = BLUE
    for y in range(h):
        for t in range(wall):
            pix[(t, y)] = BLUE
            pix[(w - 1 - t, y)] = BLUE
    placed = []  # (cx, cy, r)
    # Large nuts first, then small, each at a random free place (2 blocks of gap at least).
    for r, count in ((12, large), (5, small)):
        n, tries = 0, 0
        while n < count:
            tries += 1
            assert tries < 100000, f"{path}: {count} nuts of radius {r} do not fit"
            cx = rng.uniform(wall + r + 2, w - wall - r - 2)
            # Large nuts start in the bottom fraction `low` of the bag (as the experiments
            # start: the large ones under the small), small ones anywhere.
            top = wall + r + 2 if r < 12 else h * (1 - low)
            cy = rng.uniform(top, h - wall - r - 2)
            if all(math.hypot(cx - a, cy - b) > r + q + 3 for a, b, q in placed):
                placed.append((cx, cy, r))
                for p in hexagon(cx, cy, r, rng.uniform(0, math.pi / 3)):
                    pix[p] = BRASS
                n += 1
    png(path, w, h, pix)


bag("scenes/blocks/nut_bag_few_large.png", 12, 48, 1)
bag("scenes/blocks/nut_bag_full.png", 24, 96, 2, h=340, low=0.6)
