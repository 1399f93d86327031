"""Overlays nut reports (`rigidref run … --nut-report FILE.csv`) as one SVG: the heaviest fifth's
fraction in the upper half against shaking cycles, one line per protocol, with the mixture's 0.5
and the 0.8 at which the largest nuts count as risen (docs/blocks2d.md §"Shaking the nut bag").

    python3 scenes/blocks/plot_nut_search.py OUT.svg LABEL=FILE.csv@FREQUENCY ...

FREQUENCY is the shake's f (cycles per time unit), so that t becomes cycles t·f."""
import csv, sys

COLOURS = ["#1f77b4", "#d62728", "#2ca02c", "#9467bd", "#ff7f0e", "#8c564b", "#e377c2", "#17becf", "#000000", "#bcbd22"]


def main(out, runs):
    series = []
    for run in runs:
        label, rest = run.split("=", 1)
        path, f = rest.rsplit("@", 1)
        rows = list(csv.reader(open(path)))[1:]
        series.append((label, [(float(r[0]) * float(f), float(r[3])) for r in rows if len(r) == 5]))
    w, h, left, right, top, bottom = 900, 480, 60, 230, 30, 50
    x_max = max(p[0] for _, pts in series for p in pts)
    sx = lambda c: left + (w - left - right) * c / x_max
    sy = lambda v: top + (h - top - bottom) * (1 - v)
    svg = [f'<svg xmlns="http://www.w3.org/2000/svg" width="{w}" height="{h}" font-family="sans-serif" font-size="12">',
           f'<rect width="{w}" height="{h}" fill="white"/>',
           f'<text x="{left}" y="18" font-size="14">Heaviest fifth of the nuts in the upper half, against shaking cycles</text>']
    for v in (0, 0.2, 0.4, 0.5, 0.6, 0.8, 1.0):
        colour = "red" if v == 0.8 else "#bbb" if v == 0.5 else "#eee"
        svg.append(f'<line x1="{left}" x2="{w - right}" y1="{sy(v):.1f}" y2="{sy(v):.1f}" stroke="{colour}"/>')
        svg.append(f'<text x="{left - 8}" y="{sy(v) + 4:.1f}" text-anchor="end">{v:g}</text>')
    step = 100 if x_max > 300 else 50
    for c in range(0, int(x_max) + 1, step):
        svg.append(f'<text x="{sx(c):.1f}" y="{h - bottom + 18}" text-anchor="middle">{c}</text>')
    svg.append(f'<text x="{(left + w - right) / 2}" y="{h - 12}" text-anchor="middle">cycles</text>')
    for k, (label, pts) in enumerate(series):
        colour = COLOURS[k % len(COLOURS)]
        d = " ".join(f"{sx(c):.1f},{sy(v):.1f}" for c, v in pts)
        svg.append(f'<polyline points="{d}" fill="none" stroke="{colour}" stroke-width="1.2"/>')
        y = top + 10 + 18 * k
        svg.append(f'<line x1="{w - right + 10}" x2="{w - right + 30}" y1="{y}" y2="{y}" stroke="{colour}" stroke-width="2"/>')
        svg.append(f'<text x="{w - right + 35}" y="{y + 4}">{label}</text>')
    svg.append("</svg>")
    open(out, "w").write("\n".join(svg) + "\n")


if __name__ == "__main__":
    main(sys.argv[1], sys.argv[2:])
