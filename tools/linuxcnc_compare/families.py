"""Issue 19's generated program families, with a few more feeds: the one Python text of them, which
tests/python/test_toppra.py loads too (tests/cam_families.rs writes the same programs in Rust).
Plain Python, so that compare.py runs with any python3.

Every program starts with `G21 G90 G64 P0.01` and, where it starts off the origin, a G92 that names
the machine's start point (machine = program − start), so both controllers run it from rest at
the machine origin."""
from __future__ import annotations

import math
from dataclasses import dataclass


@dataclass(frozen=True)
class Program:
    family: str
    name: str
    text: str


def circle(feed: float) -> str:
    """A full circle of R 35.9 mm from rest, one G2."""
    return f"G21 G90 G64 P0.01\nG2 X0 Y0 I35.9 J0 F{feed:g}\nM30\n"


def chord_circle(feed: float, chord: float = 0.2, r: float = 20.0) -> str:
    """A circle of R 20 mm as G1 chords of `chord` mm (4 decimals, as CAM writes them)."""
    n = round(2 * math.pi * r / chord)
    lines = ["G21 G90 G64 P0.01", f"G92 X{r:.4f} Y0"]
    for k in range(1, n + 1):
        a = 2 * math.pi * k / n
        lines.append(f"G1 X{r * math.cos(a):.4f} Y{r * math.sin(a):.4f} F{feed:g}")
    return "\n".join(lines + ["M30"]) + "\n"


def arc_spiral(feed: float = 15000, n: int = 1000, r0: float = 50.0, r1: float = 0.05,
               per_turn: int = 50) -> str:
    """n G2 R arcs, 50 a turn, the radius shrinking linearly from 50 to 0.05 mm; each arc's R the
    mean of its ends' (nearly tangent arcs, curvature stepping at every joint)."""
    lines = ["G21 G90 G64 P0.01", f"G92 X{r0:.4f} Y0"]
    x, y, r, ang = r0, 0.0, r0, 0.0
    for _ in range(n):
        r2 = r - (r0 - r1) / n
        ang -= 2 * math.pi / per_turn
        nx, ny = r2 * math.cos(ang), r2 * math.sin(ang)
        rad = max(0.5 * (r + r2), 0.5 * math.hypot(nx - x, ny - y) * 1.0001)
        lines.append(f"G2 X{nx:.4f} Y{ny:.4f} R{rad:.4f} F{feed:g}")
        x, y, r = nx, ny, r2
    return "\n".join(lines + ["M30"]) + "\n"


def g1_spiral(feed: float = 6000, r0: float = 0.5, r1: float = 20.0, pitch: float = 2.0,
              seg: float = 0.2) -> str:
    """An Archimedean spiral pocket r 0.5 → 20 mm, 2 mm a turn, in G1 moves of about 0.2 mm."""
    lines = ["G21 G90 G64 P0.01", f"G92 X{r0:.4f} Y0"]
    th, r, b = 0.0, r0, pitch / (2 * math.pi)
    while r < r1:
        th += seg / max(r, 0.1)
        r = r0 + b * th
        lines.append(f"G1 X{r * math.cos(th):.4f} Y{r * math.sin(th):.4f} F{feed:g}")
    return "\n".join(lines + ["M30"]) + "\n"


def raster(feed: float = 3000, width: float = 20.0, rows: int = 10, step: float = 0.5,
           seg: float = 0.2) -> str:
    """Zig-zag rows over the surface z = 0.5 sin(x/3) cos(y/2) mm, 0.2 mm G1 moves."""
    lines = ["G21 G90 G64 P0.01"]
    for k in range(rows):
        y = k * step
        xs = [i * seg for i in range(int(width / seg) + 1)]
        for x in (xs[::-1] if k % 2 else xs):
            z = 0.5 * math.sin(x / 3.0) * math.cos(y / 2.0)
            lines.append(f"G1 X{x:.4f} Y{y:.4f} Z{z:.4f} F{feed:g}")
    return "\n".join(lines + ["M30"]) + "\n"


def micro_line(feed: float = 3000, n: int = 2000) -> str:
    """A straight 9 mm line as 2000 moves alternating 8 µm and 1 µm (pcb2gcode-like)."""
    lines = ["G21 G90 G64 P0.01"]
    x = 0.0
    for i in range(n):
        x += 0.008 if i % 2 == 0 else 0.001
        lines.append(f"G1 X{x:.5f} F{feed:g}")
    return "\n".join(lines + ["M30"]) + "\n"


def families() -> list[Program]:
    """The issue's ten programs (test_toppra.py's FAMILIES) and five more feeds."""
    out = [Program("circle from rest", f"circle_F{f}", circle(f)) for f in (6000, 9000, 12000, 15000)]
    out += [Program("chord circle", f"chord_circle_F{f}", chord_circle(f)) for f in (3000, 10000)]
    out += [Program("spiral of G2 R arcs", f"arc_spiral_F{f}", arc_spiral(f)) for f in (15000, 6000)]
    out += [Program("G1 spiral pocket", f"g1_spiral_F{f}", g1_spiral(f)) for f in (6000, 15000)]
    out += [Program("raster", f"raster_F{f}", raster(f)) for f in (3000, 10000)]
    out += [Program("micro-move line", f"micro_line_F{f}", micro_line(f)) for f in (3000, 10000)]
    out += [Program("chord circle", "chord_circle_F6000", chord_circle(6000))]
    return out
